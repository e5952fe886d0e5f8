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
    /// The largest share of the engine's time that rollbacks may take (0 < share ≤ 1). While
    /// rollbacks cost less (the room: 15 % of one core with two cameras late), each late set
    /// goes back at once; when they would cost more (many targets and sensors), late sets wait
    /// and go back together, one rollback for many, so that the on-time sets do not queue
    /// behind re-processing. Sets newer than everything processed never wait. 1: never hold.
    pub max_rollback_share: f64,
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
            max_rollback_share: 0.25,
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
        if !(self.max_rollback_share > 0.0 && self.max_rollback_share <= 1.0) {
            return Err(invalid(
                "ingest.max_rollback_share",
                format!("{} must be above 0 and at most 1", self.max_rollback_share),
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
