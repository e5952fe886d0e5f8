//! `TruthSet`: the true object positions, written by simulators only on `fusion/<site>/truth`.

use serde::{Deserialize, Serialize};

/// One true object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TruthObject {
    /// The object's identity in the simulation.
    pub id: u64,
    /// World position in metres.
    pub position: [f64; 3],
}

/// Every simulated object at one instant.
///
/// JSON: `{"version": 1, "stamp": 1763700000.040, "objects": [{"id": 1, "position": [1.0, 0.5, 1.7]}]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TruthSet {
    /// Protocol version; must be [`crate::PROTOCOL_VERSION`].
    pub version: u32,
    /// The simulated instant, seconds since the Unix epoch.
    pub stamp: f64,
    /// The objects present at that instant.
    pub objects: Vec<TruthObject>,
}
