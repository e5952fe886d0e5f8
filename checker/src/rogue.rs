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

/// Which counter of the report a message adds to.
#[derive(Debug, Clone, Copy)]
enum Bad {
    Garbage,
    Invalid,
    Unknown,
}

impl RogueReport {
    fn count(&mut self, bad: Bad) {
        match bad {
            Bad::Garbage => self.garbage += 1,
            Bad::Invalid => self.invalid += 1,
            Bad::Unknown => self.unknown += 1,
        }
    }
}

/// One message to put: its key, payload and declared encoding.
struct Message<'a> {
    key: &'a str,
    bytes: Vec<u8>,
    encoding: Encoding,
}

/// The keys and encodings a rogue run abuses: the victim's measurement key and that of a sensor
/// no descriptor announces.
struct Rogue {
    victim: SensorId,
    victim_key: String,
    stranger: SensorId,
    stranger_key: String,
    postcard: Encoding,
    json: Encoding,
}

impl Rogue {
    fn new(site: &Site, victim: &SensorId) -> anyhow::Result<Self> {
        let stranger = SensorId::new("rogue-sensor")?;
        Ok(Self {
            victim: victim.clone(),
            victim_key: keys::measurements_key(site, victim),
            stranger_key: keys::measurements_key(site, &stranger),
            stranger,
            postcard: Encoding::from(WireFormat::Postcard.encoding_str()),
            json: Encoding::APPLICATION_JSON,
        })
    }

    /// The `i`-th message of the run, stamped `now` where it carries a stamp: the five kinds of
    /// bad input in turn.
    fn message(&self, i: u64, now: f64) -> anyhow::Result<(Bad, Message<'_>)> {
        Ok(match i % 5 {
            0 => {
                let bytes = (0..64).map(|b| (b * 37 + i) as u8).collect();
                (Bad::Garbage, self.to_victim(bytes, &self.postcard))
            }
            1 => {
                let bytes = b"{\"version\": 1, \"sensor\": ".to_vec();
                (Bad::Garbage, self.to_victim(bytes, &self.json))
            }
            2 => {
                // A camera measures 2 values; 5 is the wrong dimension for any sensor.
                let set = MeasurementSet::new(
                    self.victim.clone(),
                    1_000_000 + i,
                    now,
                    vec![vec![1.0; 5]],
                );
                let bytes = protocol::encode(&set, WireFormat::Json)?;
                (Bad::Invalid, self.to_victim(bytes, &self.json))
            }
            3 => {
                let future = now + 3600.0;
                let set = MeasurementSet::new(self.victim.clone(), 2_000_000 + i, future, vec![]);
                let bytes = protocol::encode(&set, WireFormat::Postcard)?;
                (Bad::Invalid, self.to_victim(bytes, &self.postcard))
            }
            _ => {
                let set =
                    MeasurementSet::new(self.stranger.clone(), i, now, vec![vec![1.0, 2.0, 3.0]]);
                let message = Message {
                    key: &self.stranger_key,
                    bytes: protocol::encode(&set, WireFormat::Postcard)?,
                    encoding: self.postcard.clone(),
                };
                (Bad::Unknown, message)
            }
        })
    }

    fn to_victim(&self, bytes: Vec<u8>, encoding: &Encoding) -> Message<'_> {
        Message {
            key: &self.victim_key,
            bytes,
            encoding: encoding.clone(),
        }
    }
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
    let rogue = Rogue::new(site, victim)?;
    let mut report = RogueReport::default();
    let period = Duration::from_secs_f64(1.0 / rate_hz.max(1.0));
    let began = Instant::now();
    let mut i: u64 = 0;
    while began.elapsed() < duration {
        let (bad, message) = rogue.message(i, fusion_server::clock::now())?;
        report.count(bad);
        let put = session
            .put(message.key, message.bytes)
            .encoding(message.encoding);
        // A failed put is logged and the run goes on: the point is to keep misbehaving.
        if let Err(e) = put.await {
            tracing::warn!(error = %e, "rogue put failed");
        }
        i += 1;
        tokio::time::sleep(period).await;
    }
    Ok(report)
}
