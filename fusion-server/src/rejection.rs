//! Why the engine did not admit a payload.

use protocol::SensorId;
use thiserror::Error;

/// Why an incoming set or descriptor was not admitted. Each is counted in `Status`.
#[derive(Debug, Error)]
pub enum Rejection {
    /// The payload could not be decoded.
    #[error("undecodable payload: {0}")]
    Undecodable(String),
    /// The set or descriptor broke a validation rule.
    #[error("invalid {what} from {sensor}: {reason}")]
    Invalid {
        /// `set` or `descriptor`.
        what: &'static str,
        /// The sensor it named (or the key's sensor).
        sensor: String,
        /// The rule it broke.
        reason: String,
    },
    /// No descriptor is known for the sensor; `.1` counts its sets so far (ask for the
    /// descriptor on the first one).
    #[error("set from unknown sensor {0} (set {1} without a descriptor)")]
    UnknownSensor(SensorId, u64),
    /// Older than the history the server keeps (`ingest.max_lateness_s`).
    #[error(
        "late set from {sensor}: stamp {stamp} is before {horizon}, the oldest stamp still kept"
    )]
    Late {
        /// The sensor.
        sensor: SensorId,
        /// Its stamp.
        stamp: f64,
        /// The oldest stamp a set may have.
        horizon: f64,
    },
    /// More sets are waiting to be processed than `ingest.queue_capacity`.
    #[error("too many sets waiting, set from {0} dropped")]
    Overflow(SensorId),
}
