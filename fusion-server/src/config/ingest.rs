//! `[ingest]`: how sets are admitted and how late they may be.

use serde::Deserialize;

use super::{invalid, positive, ConfigError};

/// `[ingest]`: how incoming sets are admitted.
///
/// Every admitted set is processed at once; a set older than sets already processed makes the
/// filter go back to a snapshot taken before its stamp and process again in stamp order
/// (`timeline.rs`), so nothing waits for slower sensors and late sets are not lost.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IngestConfig {
    /// How far behind the newest processed stamp a set may be and still be used (seconds); an
    /// older set is refused as late. Memory grows with it: the sets and the snapshots of this
    /// much history are kept.
    pub max_lateness_s: f64,
    /// Seconds of stamp time between two snapshots of the filter state: a rollback re-processes
    /// at most this much more than it must, and the snapshots kept number
    /// `max_lateness_s / snapshot_interval_s`.
    pub snapshot_interval_s: f64,
    /// At most one rollback per this many seconds: late sets wait (at most this long) and go
    /// back together, so a sensor that is always late does not make the filter re-process the
    /// others' sets once per set of its own. Sets newer than everything processed never wait.
    /// 0 (the default): every late set goes back at once, which keeps late sets' latency low
    /// while the engine has time to spare (the room: 14 % busy with two cameras late); raise it
    /// (e.g. 0.1) when rollbacks saturate the engine (the dense benchmark scenario).
    pub rollback_interval_s: f64,
    /// No longer used: sets are not held any more. Present only to say so at start.
    pub reorder_window_ms: Option<u64>,
    /// A set stamped more than this ahead of the server's clock is rejected.
    pub max_future_s: f64,
    /// Capacity of the queue between Zenoh and the filter; overflow is counted.
    pub queue_capacity: usize,
    /// Sets per second one sensor may send before the excess is dropped and counted (flood guard).
    pub max_rate_hz: f64,
}

impl Default for IngestConfig {
    fn default() -> Self {
        Self {
            max_lateness_s: 2.0,
            snapshot_interval_s: 0.1,
            rollback_interval_s: 0.0,
            reorder_window_ms: None,
            max_future_s: 2.0,
            queue_capacity: 4096,
            max_rate_hz: 500.0,
        }
    }
}

impl IngestConfig {
    /// Checks every value; the error names the first offending key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.reorder_window_ms.is_some() {
            return Err(invalid(
                "ingest.reorder_window_ms",
                "sets are no longer held in a reorder window: each is processed at once and a \
                 late one rolls the filter back; remove the key (ingest.max_lateness_s sets how \
                 late a set may be)",
            ));
        }
        positive("ingest.max_lateness_s", self.max_lateness_s)?;
        positive("ingest.snapshot_interval_s", self.snapshot_interval_s)?;
        if !(self.rollback_interval_s >= 0.0 && self.rollback_interval_s < self.max_lateness_s) {
            return Err(invalid(
                "ingest.rollback_interval_s",
                format!(
                    "{} must be at least 0 and below ingest.max_lateness_s",
                    self.rollback_interval_s
                ),
            ));
        }
        positive("ingest.max_future_s", self.max_future_s)?;
        positive("ingest.max_rate_hz", self.max_rate_hz)?;
        if self.queue_capacity == 0 {
            return Err(invalid("ingest.queue_capacity", "must be at least 1"));
        }
        Ok(())
    }
}
