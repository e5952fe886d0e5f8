//! Replay files (JSON Lines): each input line holds one descriptor, measurement set or truth set.
//!
//! Output lines are plain [`crate::TrackSet`]s and need no wrapper.

use super::{MeasurementSet, SensorDescriptor, TruthSet};
use serde::{Deserialize, Serialize};

/// One input line of a replay file: exactly one of `{"descriptor": ...}`, `{"measurements": ...}`, `{"truth": ...}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ReplayLine {
    /// `{"descriptor": SensorDescriptor}`.
    Descriptor(SensorDescriptor),
    /// `{"measurements": MeasurementSet}`.
    Measurements(MeasurementSet),
    /// `{"truth": TruthSet}`.
    Truth(TruthSet),
}

impl ReplayLine {
    /// The stamp the line carries, if any (descriptors have none).
    pub fn stamp(&self) -> Option<f64> {
        match self {
            ReplayLine::Descriptor(_) => None,
            ReplayLine::Measurements(set) => Some(set.stamp),
            ReplayLine::Truth(set) => Some(set.stamp),
        }
    }
}
