//! `TrackSet`: the fusion server's estimate, on `fusion/<site>/tracks` and as each output line of a replay.

use crate::ids::Site;
use serde::{Deserialize, Serialize};

/// One estimated object.
///
/// JSON: `{"id": 3, "position": [1.2, 0.8, 1.7], "velocity": [0.1, 0.0, 0.0],
/// "position_covariance": [[0.01,0,0],[0,0.01,0],[0,0,0.02]], "weight": 0.98, "first_seen": 1763699990.120}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Track {
    /// Track label: stays with the same object for as long as the filter keeps it.
    pub id: u64,
    /// World position in metres.
    pub position: [f64; 3],
    /// World velocity in m/s; `null` for a motion model without velocity.
    pub velocity: Option<[f64; 3]>,
    /// Covariance of `position` (rows), m².
    pub position_covariance: [[f64; 3]; 3],
    /// Weight of the track's Gaussian in the intensity (≥ 0).
    pub weight: f64,
    /// Stamp of the data that first created this label, seconds since the Unix epoch.
    pub first_seen: f64,
}

/// The tracks published after processing one or more measurement sets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSet {
    /// Protocol version; must be [`crate::PROTOCOL_VERSION`].
    pub version: u32,
    /// The deployment the tracks belong to.
    pub site: Site,
    /// Increases by one per published set.
    pub seq: u64,
    /// Time the estimate refers to, seconds since the Unix epoch.
    pub stamp: f64,
    /// Total mass of the intensity: the PHD's expected number of objects (≥ 0).
    pub expected_count: f64,
    /// The extracted tracks.
    pub tracks: Vec<Track>,
}
