//! Configuration of the LIDAR pipeline, read from the edge agent's configuration file.

use super::clustering::ClusteringConfig;
use super::error::LidarConfigError;
use super::ground::GroundRemoval;
use serde::{Deserialize, Serialize};

/// Everything the LIDAR pipeline needs; every field has a default, so an empty table is a valid configuration:
///
/// ```toml
/// [ground]
/// method = "ransac"            # "ransac" (default), "height" or "none"
/// iterations = 100
/// distance_threshold = 0.15    # metres
/// max_tilt_deg = 15.0
/// min_inliers = 100
/// seed = 0
///
/// [clustering]
/// tolerance = 0.5              # metres
/// min_points = 10
/// max_points = 20000
/// ```
///
/// With `method = "height"` the ground table takes `max_ground_z` (metres, sensor frame, default −1.5) instead.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LidarConfig {
    /// Ground removal method and its parameters (default: RANSAC).
    pub ground: GroundRemoval,
    /// Euclidean clustering parameters.
    pub clustering: ClusteringConfig,
}

impl LidarConfig {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the first bad parameter.
    pub fn validate(&self) -> Result<(), LidarConfigError> {
        self.ground.validate()?;
        self.clustering.validate()
    }
}
