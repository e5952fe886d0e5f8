//! Watching a running deployment from the outside, as any client would: subscribe to the truth
//! (simulations only) and to the tracks, score them with OSPA/GOSPA (the `evaluation` crate),
//! and query `tracks` and `status`. Used by `fusion-checker` (compose tests), `fusion-demo` and
//! the integration tests.

pub mod probe;
pub mod processes;
pub mod raw_inputs;
pub mod raw_profile;
pub mod replay_file;
pub mod rogue;
pub mod talker_room;

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use evaluation::{score, Score};
use protocol::{keys, Site, Status, TrackSet, TruthSet, WireFormat};
use serde::de::DeserializeOwned;
use zenoh::sample::Sample;

/// Everything observed so far.
#[derive(Debug, Default, Clone)]
pub struct Observed {
    /// Track sets in arrival order.
    pub tracks: Vec<TrackSet>,
    /// Truth sets by stamp.
    pub truth: BTreeMap<u64, TruthSet>,
    /// Payloads that could not be decoded.
    pub undecodable: u64,
}

impl Observed {
    /// Each track set scored against the nearest truth.
    pub fn scores(&self) -> Vec<Score> {
        score(&self.tracks, &self.truth).unwrap_or_default()
    }

    /// The truth sets in stamp order.
    pub fn truth_sets(&self) -> Vec<TruthSet> {
        self.truth.values().cloned().collect()
    }
}

/// Subscribes to a site's truth and tracks until dropped.
pub struct Observer {
    observed: Arc<Mutex<Observed>>,
    _truth: zenoh::pubsub::Subscriber<()>,
    _tracks: zenoh::pubsub::Subscriber<()>,
}

fn decode_sample<T: DeserializeOwned>(sample: &Sample) -> Option<T> {
    let format = WireFormat::from_zenoh(sample.encoding()).ok()?;
    protocol::decode(&sample.payload().to_bytes(), format).ok()
}

impl Observer {
    /// Starts observing `site` on `session`.
    pub async fn start(session: &zenoh::Session, site: &Site) -> anyhow::Result<Self> {
        let observed = Arc::new(Mutex::new(Observed::default()));
        let sink = observed.clone();
        let truth = session
            .declare_subscriber(keys::truth_key(site))
            .callback(move |sample: Sample| {
                let mut observed = sink.lock().unwrap_or_else(|p| p.into_inner());
                match decode_sample::<TruthSet>(&sample) {
                    Some(set) if set.stamp.is_finite() && set.stamp >= 0.0 => {
                        observed.truth.insert(set.stamp.to_bits(), set);
                    }
                    _ => observed.undecodable += 1,
                }
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to truth: {e}"))?;
        let sink = observed.clone();
        let tracks = session
            .declare_subscriber(keys::tracks_key(site))
            .callback(move |sample: Sample| {
                let mut observed = sink.lock().unwrap_or_else(|p| p.into_inner());
                match decode_sample::<TrackSet>(&sample) {
                    Some(set) => observed.tracks.push(set),
                    None => observed.undecodable += 1,
                }
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to tracks: {e}"))?;
        Ok(Self {
            observed,
            _truth: truth,
            _tracks: tracks,
        })
    }

    /// A copy of what was observed so far.
    pub fn snapshot(&self) -> Observed {
        self.observed
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// The latest track set received, if any.
    pub fn latest_tracks(&self) -> Option<TrackSet> {
        self.observed
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .tracks
            .last()
            .cloned()
    }
}

/// Asks the server for its current tracks, in `format`.
pub async fn query_tracks(
    session: &zenoh::Session,
    site: &Site,
    format: WireFormat,
) -> anyhow::Result<TrackSet> {
    query(session, &keys::tracks_key(site), format).await
}

/// Asks the server for its status, in `format`.
pub async fn query_status(
    session: &zenoh::Session,
    site: &Site,
    format: WireFormat,
) -> anyhow::Result<Status> {
    query(session, &keys::status_key(site), format).await
}

async fn query<T: DeserializeOwned>(
    session: &zenoh::Session,
    key: &str,
    format: WireFormat,
) -> anyhow::Result<T> {
    let parameter = match format {
        WireFormat::Json => "json",
        WireFormat::Postcard => "postcard",
    };
    let selector = format!("{key}?format={parameter}");
    let replies = session
        .get(&selector)
        .timeout(Duration::from_secs(3))
        .await
        .map_err(|e| anyhow::anyhow!("get {selector}: {e}"))?;
    let reply = replies
        .recv_async()
        .await
        .map_err(|_| anyhow::anyhow!("get {selector}: no reply (is the server running?)"))?;
    let sample = reply.result().map_err(|e| {
        anyhow::anyhow!(
            "get {selector}: error reply: {:?}",
            e.payload().try_to_string()
        )
    })?;
    let got = WireFormat::from_zenoh(sample.encoding())?;
    anyhow::ensure!(got == format, "get {selector}: reply encoded as {got:?}");
    Ok(protocol::decode(&sample.payload().to_bytes(), got)?)
}
