//! Probes of the deployment's access control and topology, for the compose tests: an impostor
//! that writes where its identity may not (another sensor's sets, the tracks, a fake status
//! queryable), a sniffer that counts what of it got through, one server instance's own status,
//! and every site's tracks and status seen from one router.
//!
//! The impostor's payloads are JSON built by hand (not the protocol's types: a forged message
//! needs no type), marked so that the sniffer tells them from the genuine ones: a `seq` of at
//! least [`FORGED_SEQ`], a track id [`FORGED_TRACK_ID`], a status with `"forged": true`.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use protocol::{keys, InstanceId, SensorId, Site, WireFormat};
use serde_json::{json, Value};
use zenoh::query::{ConsolidationMode, Query};
use zenoh::sample::Sample;

/// The first `seq` of a forged set or track set (far beyond any genuine one).
pub const FORGED_SEQ: u64 = 1 << 40;
/// The id of the forged track.
pub const FORGED_TRACK_ID: u64 = 4_242_424_242;

/// What the impostor tried.
#[derive(Debug, Default, serde::Serialize)]
pub struct ImpostorReport {
    /// Puts attempted, by key.
    pub puts: BTreeMap<String, u64>,
    /// Whether declaring the fake status queryable returned an error (the router denies it
    /// silently: a client cannot tell).
    pub queryable_error: Option<String>,
    /// Queries the fake queryable was asked (0 when the router refused its declaration).
    pub queries_answered: u64,
}

fn forged_set(sensor: &SensorId, i: u64) -> Value {
    json!({"version": 1, "sensor": sensor.as_str(), "seq": FORGED_SEQ + i,
           "stamp": fusion_server::clock::now(), "measurements": [], "covariances": null})
}

fn forged_tracks(site: &Site, i: u64) -> Value {
    let now = fusion_server::clock::now();
    json!({"version": 1, "site": site.as_str(), "seq": FORGED_SEQ + i, "stamp": now,
           "expected_count": 1.0,
           "tracks": [{"id": FORGED_TRACK_ID, "position": [1.0, 1.0, 1.0], "velocity": null,
                       "position_covariance": [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]],
                       "weight": 1.0, "first_seen": now}]})
}

/// For `duration`, at `rate_hz`: puts forged sets on `victim`'s measurement key and forged
/// track sets on the site's tracks keys, while holding a fake `status` queryable.
pub async fn impersonate(
    session: &zenoh::Session,
    site: &Site,
    victim: &SensorId,
    duration: Duration,
    rate_hz: f64,
) -> anyhow::Result<ImpostorReport> {
    let mut report = ImpostorReport::default();
    let answered = Arc::new(AtomicU64::new(0));
    let counter = answered.clone();
    let status_key = keys::status_key(site);
    let reply_key = status_key.clone();
    let queryable = session
        .declare_queryable(status_key)
        .callback(move |query: Query| {
            counter.fetch_add(1, Ordering::Relaxed);
            let body = json!({"forged": true}).to_string();
            let _ = zenoh::Wait::wait(
                query
                    .reply(reply_key.clone(), body)
                    .encoding(WireFormat::Json.to_zenoh()),
            );
        })
        .await;
    report.queryable_error = queryable.as_ref().err().map(|e| e.to_string());
    let measurements = keys::measurements_key(site, victim);
    let tracks = keys::tracks_key(site);
    let tracks_json = keys::tracks_json_key(site);
    let period = Duration::from_secs_f64(1.0 / rate_hz.max(1.0));
    let began = Instant::now();
    let mut i = 0;
    while began.elapsed() < duration {
        let messages = [
            (&measurements, forged_set(victim, i)),
            (&tracks, forged_tracks(site, i)),
            (&tracks_json, forged_tracks(site, i)),
        ];
        for (key, body) in messages {
            let put = session
                .put(key.as_str(), body.to_string())
                .encoding(WireFormat::Json.to_zenoh());
            if let Err(e) = put.await {
                tracing::warn!(key = %key, error = %e, "put failed");
            }
            *report.puts.entry(key.clone()).or_default() += 1;
        }
        i += 1;
        tokio::time::sleep(period).await;
    }
    report.queries_answered = answered.load(Ordering::Relaxed);
    drop(queryable);
    Ok(report)
}

/// What the sniffer saw under `fusion/<site>/**` and in the site's status replies.
#[derive(Debug, Default, serde::Serialize)]
pub struct SniffReport {
    /// Genuine samples, by the key's last two chunks (e.g. `lidar/measurements`, `default/tracks`).
    pub genuine: BTreeMap<String, u64>,
    /// Forged samples received, by key.
    pub forged: BTreeMap<String, u64>,
    /// Status replies received, and how many of them were forged.
    pub status_replies: u64,
    /// Forged status replies.
    pub forged_status_replies: u64,
}

fn is_forged(sample: &Sample) -> bool {
    if WireFormat::from_zenoh(sample.encoding()).ok() != Some(WireFormat::Json) {
        return false;
    }
    let Ok(value) = serde_json::from_slice::<Value>(&sample.payload().to_bytes()) else {
        return false;
    };
    let forged_seq = value["seq"].as_u64().is_some_and(|seq| seq >= FORGED_SEQ);
    let forged_track = value["tracks"].as_array().is_some_and(|tracks| {
        tracks
            .iter()
            .any(|t| t["id"].as_u64() == Some(FORGED_TRACK_ID))
    });
    forged_seq || forged_track || value["forged"] == json!(true)
}

fn short_key(key: &str) -> String {
    let chunks: Vec<&str> = key.rsplitn(3, '/').collect();
    match chunks.as_slice() {
        [last, before, _] => format!("{before}/{last}"),
        _ => key.to_owned(),
    }
}

/// Subscribes to everything of `site` for `duration`, asking for its status every second.
pub async fn sniff(
    session: &zenoh::Session,
    site: &Site,
    duration: Duration,
) -> anyhow::Result<SniffReport> {
    let report = Arc::new(std::sync::Mutex::new(SniffReport::default()));
    let sink = report.clone();
    let subscriber = session
        .declare_subscriber(format!("{}/{site}/**", keys::ROOT))
        .callback(move |sample: Sample| {
            let mut report = sink.lock().unwrap_or_else(|p| p.into_inner());
            let key = sample.key_expr().as_str();
            if is_forged(&sample) {
                *report.forged.entry(key.to_owned()).or_default() += 1;
            } else {
                *report.genuine.entry(short_key(key)).or_default() += 1;
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing: {e}"))?;
    let began = Instant::now();
    let selector = format!("{}?format=json", keys::status_key(site));
    while began.elapsed() < duration {
        let replies = get_all(session, &selector).await?;
        {
            let mut report = report.lock().unwrap_or_else(|p| p.into_inner());
            report.status_replies += replies.len() as u64;
            report.forged_status_replies += replies.iter().filter(|s| is_forged(s)).count() as u64;
        }
        tokio::time::sleep(Duration::from_secs(1)).await;
    }
    drop(subscriber);
    let report = std::mem::take(&mut *report.lock().unwrap_or_else(|p| p.into_inner()));
    Ok(report)
}

/// Every successful reply to `selector` (no consolidation: one per replier and key).
async fn get_all(session: &zenoh::Session, selector: &str) -> anyhow::Result<Vec<Sample>> {
    let replies = session
        .get(selector)
        .consolidation(ConsolidationMode::None)
        .timeout(Duration::from_secs(3))
        .await
        .map_err(|e| anyhow::anyhow!("get {selector}: {e}"))?;
    let mut samples = Vec::new();
    while let Ok(reply) = replies.recv_async().await {
        if let Ok(sample) = reply.result() {
            samples.push(sample.clone());
        }
    }
    Ok(samples)
}

fn json_payload(sample: &Sample) -> Option<Value> {
    serde_json::from_slice(&sample.payload().to_bytes()).ok()
}

/// For `duration`: how many track sets arrived and the longest silence between two of them
/// (`{"sets": n, "max_gap_s": s}`, the silence before the first one included).
pub async fn track_gaps(
    session: &zenoh::Session,
    site: &Site,
    duration: Duration,
) -> anyhow::Result<Value> {
    let arrivals = Arc::new(std::sync::Mutex::new(Vec::<Instant>::new()));
    let sink = arrivals.clone();
    let subscriber = session
        .declare_subscriber(keys::tracks_key(site))
        .callback(move |_| {
            sink.lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(Instant::now())
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing to tracks: {e}"))?;
    let began = Instant::now();
    tokio::time::sleep(duration).await;
    drop(subscriber);
    let arrivals = arrivals.lock().unwrap_or_else(|p| p.into_inner()).clone();
    let mut previous = began;
    let mut max_gap = Duration::ZERO;
    for at in &arrivals {
        max_gap = max_gap.max(at.duration_since(previous));
        previous = *at;
    }
    Ok(json!({"sets": arrivals.len(), "max_gap_s": max_gap.as_secs_f64()}))
}

/// One server instance's own status (`fusion/<site>/server/<instance>/status`), as the JSON it
/// sent (its `role` field included, whatever this build's `Status` type knows).
pub async fn instance_status(
    session: &zenoh::Session,
    site: &Site,
    instance: &str,
) -> anyhow::Result<Value> {
    let key = keys::server_status_key(site, &InstanceId::new(instance)?);
    let selector = format!("{key}?format=json");
    let replies = get_all(session, &selector).await?;
    let sample = replies
        .first()
        .ok_or_else(|| anyhow::anyhow!("get {selector}: no reply (is instance {instance} up?)"))?;
    json_payload(sample).ok_or_else(|| anyhow::anyhow!("get {selector}: the reply is not JSON"))
}

/// [`all_sites`] again and again (every 200 ms) until every site of `expect` has tracks and a
/// status, for at most `timeout`; the last answer with `"complete"` and `"elapsed_s"` added.
pub async fn wait_sites(
    session: &zenoh::Session,
    expect: &[String],
    timeout: Duration,
) -> anyhow::Result<Value> {
    let began = Instant::now();
    loop {
        let mut answer = all_sites(session).await?;
        let complete = expect.iter().all(|site| {
            answer["tracks"][site].as_u64().is_some_and(|n| n > 0)
                && answer["status"][site].as_u64().is_some()
        });
        if complete || began.elapsed() >= timeout {
            answer["complete"] = json!(complete);
            answer["elapsed_s"] = json!(began.elapsed().as_secs_f64());
            return Ok(answer);
        }
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

/// Every site's tracks and status as answered to `fusion/*/tracks` and `fusion/*/status`:
/// `{"tracks": {site: track count}, "status": {site: live sensors}}`.
pub async fn all_sites(session: &zenoh::Session) -> anyhow::Result<Value> {
    let mut tracks = BTreeMap::new();
    let selector = format!("{}/*/tracks?format=json", keys::ROOT);
    for sample in get_all(session, &selector).await? {
        if let Some(set) = json_payload(&sample) {
            let site = set["site"].as_str().unwrap_or("?").to_owned();
            tracks.insert(site, set["tracks"].as_array().map_or(0, Vec::len));
        }
    }
    let mut status = BTreeMap::new();
    let selector = format!("{}/*/status?format=json", keys::ROOT);
    for sample in get_all(session, &selector).await? {
        if let Some(s) = json_payload(&sample) {
            let site = s["site"].as_str().unwrap_or("?").to_owned();
            let alive = s["sensors"].as_array().map_or(0, |sensors| {
                sensors.iter().filter(|x| x["alive"] == json!(true)).count()
            });
            status.insert(site, alive);
        }
    }
    Ok(json!({"tracks": tracks, "status": status}))
}
