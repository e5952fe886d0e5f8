//! The error of turning a descriptor into a measurement model.

use gmphd::FilterError;
use protocol::SensorKind;
use thiserror::Error;

/// Why a `SensorDescriptor` does not make a usable measurement model.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// The descriptor is of a protocol version this crate does not know.
    #[error(
        "sensor `{sensor}`: descriptor version {version} is not supported (expected {expected})"
    )]
    UnsupportedVersion {
        /// The sensor's name.
        sensor: String,
        /// The version the descriptor carries.
        version: u32,
        /// The version this crate implements.
        expected: u32,
    },
    /// `detection_probability` is outside (0, 1] or `clutter_rate` is negative or not finite.
    #[error("sensor `{sensor}`: {source}")]
    Detection {
        /// The sensor's name.
        sensor: String,
        /// The filter's description of the bad value.
        source: FilterError,
    },
    /// The model's fields are degenerate (singular camera, coinciding microphones,
    /// non-unit quaternion, non-positive noise or range, empty region, ...).
    #[error("sensor `{sensor}`, {kind} model: {source}")]
    Model {
        /// The sensor's name.
        sensor: String,
        /// The model's kind.
        kind: SensorKind,
        /// The filter's description of the bad field.
        source: FilterError,
    },
}
