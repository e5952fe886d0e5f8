//! The LIDAR pipeline: point cloud → ground removal → Euclidean clusters → centroid measurements.

use super::clustering::{euclidean_clusters, PointCluster};
use super::config::LidarConfig;
use super::error::LidarConfigError;
use super::measurement::point_to_measurement;
use super::point_cloud::PointCloud;

/// What the pipeline made of one scan, for inspection and tests; [`LidarPipeline::measurements`] keeps only the
/// centroids.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Object clusters; their `indices` point into the input cloud's `points`.
    pub clusters: Vec<PointCluster>,
    /// Number of points taken for ground.
    pub ground_points: usize,
    /// Number of points skipped as "no return": non-finite coordinates, or exactly the sensor origin (which some
    /// drivers write for a missing return).
    pub invalid_points: usize,
}

/// Turns LIDAR scans into `[range, azimuth, elevation]` measurements of object centroids in the sensor frame.
/// Deterministic: the same scan and configuration always give the same measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct LidarPipeline {
    config: LidarConfig,
}

impl LidarPipeline {
    /// A pipeline with a checked configuration.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the first bad parameter.
    pub fn new(config: LidarConfig) -> Result<Self, LidarConfigError> {
        config.validate()?;
        Ok(Self { config })
    }

    /// The configuration in use.
    pub fn config(&self) -> &LidarConfig {
        &self.config
    }

    /// Removes the ground and clusters the remaining points.
    pub fn segment(&self, cloud: &PointCloud) -> Segmentation {
        let mut original_index = Vec::with_capacity(cloud.points.len());
        let mut points = Vec::with_capacity(cloud.points.len());
        for (index, point) in cloud.points.iter().enumerate() {
            let point = point.map(f64::from);
            if point.iter().all(|v| v.is_finite()) && point != [0.0; 3] {
                original_index.push(index);
                points.push(point);
            }
        }
        let invalid_points = cloud.points.len() - points.len();

        let ground = self.config.ground.ground_mask(&points);
        let ground_points = ground.iter().filter(|&&is_ground| is_ground).count();
        let (object_points, object_index): (Vec<[f64; 3]>, Vec<usize>) = points
            .iter()
            .zip(&original_index)
            .zip(&ground)
            .filter(|(_, &is_ground)| !is_ground)
            .map(|((point, &index), _)| (*point, index))
            .unzip();

        let mut clusters = euclidean_clusters(&object_points, &self.config.clustering);
        for cluster in &mut clusters {
            for index in &mut cluster.indices {
                *index = object_index[*index];
            }
        }
        Segmentation {
            clusters,
            ground_points,
            invalid_points,
        }
    }

    /// One `[range, azimuth, elevation]` measurement per object cluster centroid (see
    /// [`super::point_to_measurement`]), in the order of [`Self::segment`]'s clusters.
    pub fn measurements(&self, cloud: &PointCloud) -> Vec<[f64; 3]> {
        self.segment(cloud)
            .clusters
            .iter()
            .map(|cluster| point_to_measurement(cluster.centroid))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lidar::{ClusteringConfig, GroundRemoval, HeightThreshold};

    #[test]
    fn skips_invalid_points_and_maps_indices_back_to_the_cloud() {
        let mut points = vec![[f32::NAN, 0.0, 0.0], [0.0, 0.0, 0.0], [5.0, 0.0, -3.0]];
        // A 4 × 4 patch of points 0.1 m apart, 10 m ahead, above the ground threshold.
        for k in 0..16 {
            points.push([10.0, 0.1 * (k % 4) as f32, 0.1 * (k / 4) as f32]);
        }
        let cloud = PointCloud::from_points(points);
        let pipeline = LidarPipeline::new(LidarConfig {
            ground: GroundRemoval::Height(HeightThreshold { max_ground_z: -1.0 }),
            clustering: ClusteringConfig {
                tolerance: 0.15,
                min_points: 4,
                max_points: 100,
            },
        })
        .unwrap();
        let segmentation = pipeline.segment(&cloud);
        assert_eq!(segmentation.invalid_points, 2);
        assert_eq!(segmentation.ground_points, 1);
        assert_eq!(segmentation.clusters.len(), 1);
        let mut indices = segmentation.clusters[0].indices.clone();
        indices.sort_unstable();
        assert_eq!(indices, (3..19).collect::<Vec<_>>());
        let [range, azimuth, elevation] = pipeline.measurements(&cloud)[0];
        let centroid: [f64; 3] = [10.0, 0.15, 0.15];
        assert!((range - centroid.iter().map(|v| v * v).sum::<f64>().sqrt()).abs() < 1e-6);
        assert!((azimuth - 0.015f64.atan()).abs() < 1e-6);
        assert!((elevation - 0.15f64.atan2(10.0f64.hypot(0.15))).abs() < 1e-6);
    }

    #[test]
    fn rejects_an_invalid_configuration() {
        let config = LidarConfig {
            clustering: ClusteringConfig {
                min_points: 0,
                ..ClusteringConfig::default()
            },
            ..LidarConfig::default()
        };
        assert!(LidarPipeline::new(config).is_err());
    }
}
