//! The LIDAR pipeline: point cloud → ground removal → segments (range image, or Euclidean clusters) →
//! person-sized objects, less the parts of a person seen apart (`body_parts.rs`) → their centres as
//! measurements.

use super::body_parts::drop_body_parts;
use super::clustering::{euclidean_clusters, PointCluster};
use super::config::{LidarConfig, SegmentationMethod};
use super::error::LidarConfigError;
use super::measurement::{measurement_covariance, point_to_measurement};
use super::objects::{detect_object, DetectedObject, GroundFrame};
use super::people_split::split_people;
use super::point_cloud::PointCloud;
use super::range_image::RangeImage;
use super::range_segmentation::segment_range_image;

/// What the pipeline made of one scan, for inspection and tests; [`LidarPipeline::measurements`] keeps only the
/// objects' centres.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Segments (of the range image, or Euclidean clusters); their `indices` point into the input cloud's
    /// `points`, their `centroid` is the mean of the visible points.
    pub clusters: Vec<PointCluster>,
    /// The segments that passed the object limits, in the order of `clusters`.
    pub objects: Vec<DetectedObject>,
    /// Whether the range image was used (`false`: Euclidean clustering, configured or as the fallback for a
    /// cloud without ring structure).
    pub range_image: bool,
    /// Number of points taken for ground.
    pub ground_points: usize,
    /// Number of points skipped as "no return": non-finite coordinates, or exactly the sensor origin (which some
    /// drivers write for a missing return).
    pub invalid_points: usize,
}

/// Turns LIDAR scans into `[range, azimuth, elevation]` measurements of objects in the sensor frame.
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

    /// Removes the ground, segments the remaining points and picks out the objects.
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
        let (ground, plane) = self.config.ground.classify(&points);
        let ground_points = ground.iter().filter(|&&is_ground| is_ground).count();
        let (segments, range_image) = self.segments(&points, &ground);
        let frame = GroundFrame::new(plane.as_ref());
        let segments: Vec<Vec<usize>> = segments
            .iter()
            .flat_map(|indices| split_people(&points, indices, &frame, &self.config.objects))
            .collect();
        let objects = segments
            .iter()
            .enumerate()
            .filter_map(|(k, indices)| {
                detect_object(&points, (k, indices), &frame, &self.config.objects)
            })
            .collect();
        let objects = drop_body_parts(objects, &frame, &self.config.objects);
        let clusters = segments
            .into_iter()
            .map(|indices| PointCluster {
                centroid: centroid(&points, &indices),
                indices: indices.into_iter().map(|i| original_index[i]).collect(),
            })
            .collect();
        Segmentation {
            clusters,
            objects,
            range_image,
            ground_points,
            invalid_points,
        }
    }

    /// The segments of the non-ground points (indices into `points`) and whether the range image made them.
    fn segments(&self, points: &[[f64; 3]], ground: &[bool]) -> (Vec<Vec<usize>>, bool) {
        let objects: Vec<bool> = ground.iter().map(|is_ground| !is_ground).collect();
        if self.config.segmentation == SegmentationMethod::RangeImage {
            if let Some(image) = RangeImage::build(points, &objects, &self.config.range_image) {
                return (
                    segment_range_image(&image, points, &self.config.range_image),
                    true,
                );
            }
        }
        let object_index: Vec<usize> = (0..points.len()).filter(|&i| objects[i]).collect();
        let object_points: Vec<[f64; 3]> = object_index.iter().map(|&i| points[i]).collect();
        let clusters = euclidean_clusters(&object_points, &self.config.clustering)
            .into_iter()
            .map(|cluster| {
                cluster
                    .indices
                    .into_iter()
                    .map(|i| object_index[i])
                    .collect()
            })
            .collect();
        (clusters, false)
    }

    /// One `[range, azimuth, elevation]` measurement per object (see [`super::point_to_measurement`]), in the
    /// order of [`Self::segment`]'s objects.
    pub fn measurements(&self, cloud: &PointCloud) -> Vec<[f64; 3]> {
        self.segment(cloud)
            .objects
            .iter()
            .map(|object| point_to_measurement(object.centre))
            .collect()
    }

    /// The covariances `measurements` of this pipeline are published with, one each: the sensor's
    /// `noise_std` plus the objects' own error `objects.centre_std` (see [`super::measurement_covariance`]);
    /// `None` when that error is 0, which leaves the uncertainty to the descriptor's noise.
    pub fn covariances(
        &self,
        measurements: &[[f64; 3]],
        noise_std: [f64; 3],
    ) -> Option<Vec<[[f64; 3]; 3]>> {
        let centre_std = self.config.objects.centre_std;
        (centre_std > 0.0).then(|| {
            measurements
                .iter()
                .map(|&m| measurement_covariance(m, centre_std, noise_std))
                .collect()
        })
    }
}

/// Mean of the indexed points.
fn centroid(points: &[[f64; 3]], indices: &[usize]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for &index in indices {
        for (axis, total) in sum.iter_mut().enumerate() {
            *total += points[index][axis];
        }
    }
    sum.map(|total| total / indices.len().max(1) as f64)
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
        let pipeline = LidarPipeline::new(LidarConfig::euclidean_centroids(
            GroundRemoval::Height(HeightThreshold { max_ground_z: -1.0 }),
            ClusteringConfig {
                tolerance: 0.15,
                min_points: 4,
                max_points: 100,
            },
        ))
        .unwrap();
        let segmentation = pipeline.segment(&cloud);
        assert_eq!(segmentation.invalid_points, 2);
        assert_eq!(segmentation.ground_points, 1);
        assert_eq!(segmentation.clusters.len(), 1);
        assert!(!segmentation.range_image);
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
