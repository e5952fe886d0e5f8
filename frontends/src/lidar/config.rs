//! Configuration of the LIDAR pipeline, read from the edge agent's configuration file.

use super::clustering::ClusteringConfig;
use super::error::LidarConfigError;
use super::ground::GroundRemoval;
use super::objects::ObjectConfig;
use super::range_image::RangeImageConfig;
use serde::{Deserialize, Serialize};

/// How the non-ground points are grouped into segments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SegmentationMethod {
    /// Neighbours in the range image (beam × azimuth step) within a range jump (default); a cloud without
    /// ring structure falls back to Euclidean clustering.
    #[default]
    RangeImage,
    /// Euclidean clustering with one fixed tolerance, whatever the cloud.
    Euclidean,
}

/// Everything the LIDAR pipeline needs; every field has a default, so an empty table is a valid configuration:
///
/// ```toml
/// segmentation = "range_image" # or "euclidean"
///
/// [ground]
/// method = "ransac"            # "ransac" (default), "height" or "none"
/// iterations = 400
/// distance_threshold = 0.15    # metres
/// max_tilt_deg = 15.0
/// min_inliers = 100
/// seed = 0
///
/// [range_image]
/// beams_deg = []               # the beams' elevations; empty: rings found in each scan
/// ring_gap_deg = 0.25
/// max_rings = 256              # more rings: no ring structure, Euclidean clustering instead
/// azimuth_step_deg = 0.2
/// max_gap_cells = 2
/// max_range_jump = 0.2         # metres
/// min_points = 4
/// max_points = 20000
///
/// [clustering]                 # Euclidean clustering, and the fallback
/// tolerance = 0.5              # metres
/// min_points = 10
/// max_points = 20000
///
/// [objects]                    # what is reported, and which segments are people-sized
/// estimate = "person"          # or "centroid"
/// body_radius = 0.17           # metres
/// # head_height = 1.75         # metres above the ground; absent: the segment's highest point
/// max_width = 1.2              # metres
/// min_top_height = 0.5         # metres above the ground
/// max_top_height = 2.2
/// ```
///
/// With `method = "height"` the ground table takes `max_ground_z` (metres, sensor frame, default −1.5) instead.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LidarConfig {
    /// Range image (default) or Euclidean clustering.
    pub segmentation: SegmentationMethod,
    /// Ground removal method and its parameters (default: RANSAC).
    pub ground: GroundRemoval,
    /// Range-image parameters.
    pub range_image: RangeImageConfig,
    /// Euclidean clustering parameters (also used when a cloud has no ring structure).
    pub clustering: ClusteringConfig,
    /// Object estimation and size limits.
    pub objects: ObjectConfig,
}

impl LidarConfig {
    /// Euclidean clustering with `clustering`, every cluster reported at its centroid: the pipeline as it was
    /// before range images and object limits, for generic (not person) objects.
    pub fn euclidean_centroids(ground: GroundRemoval, clustering: ClusteringConfig) -> Self {
        Self {
            segmentation: SegmentationMethod::Euclidean,
            ground,
            clustering,
            objects: ObjectConfig::centroids(),
            ..Self::default()
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the first bad parameter.
    pub fn validate(&self) -> Result<(), LidarConfigError> {
        self.ground.validate()?;
        self.range_image.validate()?;
        self.clustering.validate()?;
        self.objects.validate()
    }
}
