//! A misbehaving publisher, for fault tests: garbage bytes, out-of-range sets, sets of unknown
//! sensors, far-future stamps and a flood, all on the site's measurement keys.

use std::time::{Duration, Instant};

use protocol::{keys, MeasurementSet, SensorId, Site, WireFormat};
use zenoh::bytes::Encoding;

/// How many of each kind of bad message a rogue run sent.
#[derive(Debug, Default, Clone, Copy)]
pub struct RogueReport {
    /// Payloads that are not a message at all.
    pub garbage: u64,
    /// Decodable sets that break a validation rule (wrong dimension, non-finite, future stamp).
    pub invalid: u64,
    /// Sets of a sensor no descriptor announces.
    pub unknown: u64,
}

/// Publishes bad input for `duration` at about `rate_hz` messages per second, impersonating
/// `victim` (a real sensor's key) and inventing an unknown sensor.
pub async fn run_rogue(
    session: &zenoh::Session,
    site: &Site,
    victim: &SensorId,
    duration: Duration,
    rate_hz: f64,
) -> anyhow::Result<RogueReport> {
    let mut report = RogueReport::default();
    let victim_key = keys::measurements_key(site, victim);
    let stranger = SensorId::new("rogue-sensor")?;
    let stranger_key = keys::measurements_key(site, &stranger);
    let postcard = Encoding::from(WireFormat::Postcard.encoding_str());
    let json = Encoding::APPLICATION_JSON;
    let period = Duration::from_secs_f64(1.0 / rate_hz.max(1.0));
    let began = Instant::now();
    let mut i: u64 = 0;
    while began.elapsed() < duration {
        let now = fusion_server::clock::now();
        let put = |key: &str, bytes: Vec<u8>, encoding: Encoding| {
            let key = key.to_string();
            async move { session.put(key, bytes).encoding(encoding).await }
        };
        let result = match i % 5 {
            0 => {
                report.garbage += 1;
                put(
                    &victim_key,
                    (0..64).map(|b| (b * 37 + i) as u8).collect(),
                    postcard.clone(),
                )
                .await
            }
            1 => {
                report.garbage += 1;
                put(
                    &victim_key,
                    b"{\"version\": 1, \"sensor\": ".to_vec(),
                    json.clone(),
                )
                .await
            }
            2 => {
                // A camera measures 2 values; 5 is the wrong dimension for any sensor.
                report.invalid += 1;
                let set =
                    MeasurementSet::new(victim.clone(), 1_000_000 + i, now, vec![vec![1.0; 5]]);
                put(
                    &victim_key,
                    protocol::encode(&set, WireFormat::Json)?,
                    json.clone(),
                )
                .await
            }
            3 => {
                report.invalid += 1;
                let set = MeasurementSet::new(victim.clone(), 2_000_000 + i, now + 3600.0, vec![]);
                put(
                    &victim_key,
                    protocol::encode(&set, WireFormat::Postcard)?,
                    postcard.clone(),
                )
                .await
            }
            _ => {
                report.unknown += 1;
                let set = MeasurementSet::new(stranger.clone(), i, now, vec![vec![1.0, 2.0, 3.0]]);
                put(
                    &stranger_key,
                    protocol::encode(&set, WireFormat::Postcard)?,
                    postcard.clone(),
                )
                .await
            }
        };
        if let Err(e) = result {
            tracing::warn!(error = %e, "rogue put failed");
        }
        i += 1;
        tokio::time::sleep(period).await;
    }
    Ok(report)
}
