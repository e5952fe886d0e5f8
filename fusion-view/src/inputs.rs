//! The view's Zenoh inputs, for every site it can reach: subscriptions to the tracks, the truth,
//! the descriptors, the microphone pairs' measurements and the agents' liveliness; a status
//! query every second; the descriptors asked for now and then; and, for each new site, the
//! history of its tracks (a `_time` query) to fill the trails at once.
//!
//! Callbacks decode and validate, then update [`Sites`] under its lock; nothing that fails to
//! decode goes further (it is counted per site and logged, rate-limited).

use std::sync::{Arc, Mutex};
use std::time::Duration;

use fusion_server::clock;
use protocol::{
    keys, parse_sensor_key, parse_site_key, MeasurementSet, SensorDescriptor, SensorKeyKind, Site,
    SiteKeyKind, Status, TrackSet, TruthSet, WireFormat,
};
use serde::de::DeserializeOwned;
use transport::LogLimiter;
use zenoh::query::ConsolidationMode;
use zenoh::sample::{Sample, SampleKind};

use crate::state::Sites;

/// Shared state of the view.
pub type SharedSites = Arc<Mutex<Sites>>;

/// Keeps the subscriptions alive.
pub struct Inputs {
    _subscribers: Vec<zenoh::pubsub::Subscriber<()>>,
    _alive: zenoh::pubsub::Subscriber<()>,
}

struct Sink {
    sites: SharedSites,
    limiter: Mutex<LogLimiter>,
}

impl Sink {
    fn lock(&self) -> std::sync::MutexGuard<'_, Sites> {
        self.sites.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn decode<T: DeserializeOwned>(&self, site: &Site, sample: &Sample, what: &str) -> Option<T> {
        let decoded = WireFormat::from_zenoh(sample.encoding())
            .and_then(|format| protocol::decode::<T>(&sample.payload().to_bytes(), format));
        match decoded {
            Ok(value) => Some(value),
            Err(e) => {
                self.refuse(site, sample.key_expr().as_str(), what, &e.to_string());
                None
            }
        }
    }

    fn refuse(&self, site: &Site, key: &str, what: &str, reason: &str) {
        self.lock().on_rejected(site);
        let mut limiter = self.limiter.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(suppressed) = limiter.allow(key) {
            tracing::warn!(key, suppressed, "{what} refused: {reason}");
        }
    }

    fn on_site_sample(&self, sample: &Sample) {
        let Ok((site, kind)) = parse_site_key(sample.key_expr().as_str()) else {
            return;
        };
        match kind {
            SiteKeyKind::Tracks => {
                if let Some(set) = self.decode::<TrackSet>(&site, sample, "track set") {
                    match set.validate() {
                        Ok(()) if set.site == site => self.lock().on_tracks(set),
                        Ok(()) => self.refuse(
                            &site,
                            sample.key_expr().as_str(),
                            "track set",
                            "site differs from its key",
                        ),
                        Err(e) => self.refuse(
                            &site,
                            sample.key_expr().as_str(),
                            "track set",
                            &e.to_string(),
                        ),
                    }
                }
            }
            SiteKeyKind::Truth => {
                if let Some(truth) = self.decode::<TruthSet>(&site, sample, "truth set") {
                    match truth.validate() {
                        Ok(()) => self.lock().on_truth(&site, truth),
                        Err(e) => self.refuse(
                            &site,
                            sample.key_expr().as_str(),
                            "truth set",
                            &e.to_string(),
                        ),
                    }
                }
            }
            SiteKeyKind::Status => {}
        }
    }

    fn on_descriptor(&self, sample: &Sample) {
        let Ok((site, _, _)) = parse_sensor_key(sample.key_expr().as_str()) else {
            return;
        };
        if let Some(descriptor) = self.decode::<SensorDescriptor>(&site, sample, "descriptor") {
            match descriptor.validate() {
                Ok(()) if descriptor.site == site => self.lock().on_descriptor(descriptor),
                Ok(()) => self.refuse(
                    &site,
                    sample.key_expr().as_str(),
                    "descriptor",
                    "site differs from its key",
                ),
                Err(e) => self.refuse(
                    &site,
                    sample.key_expr().as_str(),
                    "descriptor",
                    &e.to_string(),
                ),
            }
        }
    }

    fn on_measurements(&self, sample: &Sample) {
        let Ok((site, sensor, _)) = parse_sensor_key(sample.key_expr().as_str()) else {
            return;
        };
        // Only the microphone pairs' sets are drawn (as hyperbolas); the rest is not decoded.
        if !self.lock().is_mic_pair(&site, &sensor) {
            return;
        }
        if let Some(set) = self.decode::<MeasurementSet>(&site, sample, "measurement set") {
            let taus: Vec<f64> = set
                .measurements
                .iter()
                .filter_map(|m| m.first().copied())
                .filter(|tau| tau.is_finite())
                .collect();
            if set.stamp.is_finite() {
                self.lock().on_mic_set(&site, &sensor, set.stamp, taus);
            }
        }
    }
}

/// Subscribes to every site's keys and starts the periodic queries.
pub async fn start(session: &zenoh::Session, sites: SharedSites) -> anyhow::Result<Inputs> {
    let sink = Arc::new(Sink {
        sites: sites.clone(),
        limiter: Mutex::new(LogLimiter::new(std::time::Duration::from_secs(5))),
    });
    let mut subscribers = Vec::new();
    let root = keys::ROOT;
    type Handler = fn(&Sink, &Sample);
    let wanted: [(String, Handler); 4] = [
        (format!("{root}/*/tracks"), Sink::on_site_sample),
        (format!("{root}/*/truth"), Sink::on_site_sample),
        (
            format!("{root}/*/sensors/*/descriptor"),
            Sink::on_descriptor,
        ),
        (
            format!("{root}/*/sensors/*/measurements"),
            Sink::on_measurements,
        ),
    ];
    for (key, handler) in wanted {
        let sink = sink.clone();
        let subscriber = session
            .declare_subscriber(key.clone())
            .callback(move |sample: Sample| handler(&sink, &sample))
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to {key}: {e}"))?;
        subscribers.push(subscriber);
    }
    let alive = {
        let sites = sites.clone();
        session
            .liveliness()
            .declare_subscriber(format!("{root}/*/sensors/*/alive"))
            .history(true)
            .callback(move |sample: Sample| {
                if let Ok((site, sensor, SensorKeyKind::Alive)) =
                    parse_sensor_key(sample.key_expr().as_str())
                {
                    let alive = sample.kind() == SampleKind::Put;
                    let mut sites = sites.lock().unwrap_or_else(|p| p.into_inner());
                    sites.on_alive(&site, &sensor, alive);
                }
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to liveliness: {e}"))?
    };
    tokio::spawn(poll(session.clone(), sink));
    Ok(Inputs {
        _subscribers: subscribers,
        _alive: alive,
    })
}

/// Every second: the status of every server; every fifth: the descriptors; and the history of
/// the tracks of each site seen for the first time.
async fn poll(session: zenoh::Session, sink: Arc<Sink>) {
    let mut tick = tokio::time::interval(Duration::from_secs(1));
    for round in 0u64.. {
        tick.tick().await;
        if round % 5 == 0 {
            let selector = format!("{}/*/sensors/*/descriptor", keys::ROOT);
            for sample in get(&session, &selector, ConsolidationMode::Auto).await {
                sink.on_descriptor(&sample);
            }
        }
        let selector = format!("{}/*/status?format=postcard", keys::ROOT);
        for sample in get(&session, &selector, ConsolidationMode::None).await {
            let Ok((site, SiteKeyKind::Status)) = parse_site_key(sample.key_expr().as_str()) else {
                continue;
            };
            if let Some(status) = sink.decode::<Status>(&site, &sample, "status") {
                sink.lock().on_status(status, clock::now());
            }
        }
        let unfilled: Vec<Site> = {
            let mut sites = sink.lock();
            sites
                .sites
                .iter_mut()
                .filter(|(_, s)| s.tracks.is_some() && !s.history_asked)
                .map(|(site, s)| {
                    s.history_asked = true;
                    site.clone()
                })
                .collect()
        };
        for site in unfilled {
            fill_history(&session, &sink, &site).await;
        }
    }
}

async fn fill_history(session: &zenoh::Session, sink: &Sink, site: &Site) {
    let trail_s = sink.lock().trail_s;
    let selector = format!(
        "{}?_time=[now(-{trail_s}s)..now()];format=postcard",
        keys::tracks_key(site)
    );
    let sets: Vec<TrackSet> = get(session, &selector, ConsolidationMode::None)
        .await
        .iter()
        .filter_map(|sample| sink.decode::<TrackSet>(site, sample, "history track set"))
        .filter(|set| set.validate().is_ok())
        .collect();
    tracing::info!(site = %site, sets = sets.len(), "trails filled from the tracks history");
    sink.lock().on_history(site, &sets);
}

/// The samples of every successful reply to `selector` (error replies are logged).
async fn get(
    session: &zenoh::Session,
    selector: &str,
    consolidation: ConsolidationMode,
) -> Vec<Sample> {
    let replies = match session
        .get(selector)
        .consolidation(consolidation)
        .timeout(Duration::from_secs(2))
        .await
    {
        Ok(replies) => replies,
        Err(e) => {
            tracing::warn!(selector, error = %e, "query failed");
            return Vec::new();
        }
    };
    let mut samples = Vec::new();
    while let Ok(reply) = replies.recv_async().await {
        match reply.result() {
            Ok(sample) => samples.push(sample.clone()),
            Err(e) => {
                tracing::debug!(selector, reply = ?e.payload().try_to_string(), "error reply")
            }
        }
    }
    samples
}
