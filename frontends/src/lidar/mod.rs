//! LIDAR front end: a point cloud (PCD or KITTI `.bin`) to `[range, azimuth, elevation]` measurements of object
//! centroids in the sensor frame.
//!
//! Lee et al. (ACM SAC 2010) segment a Velodyne scan and use the centroids of the segmented clusters as the
//! measurements of a GM-PHD tracker. This module does the same with the steps common in current LIDAR stacks:
//! remove the ground (a height threshold, or a RANSAC plane fit), group the remaining points by Euclidean
//! clustering over a k-d tree, and turn each cluster's centroid into a measurement with the protocol's
//! convention `azimuth = atan2(y, x)`, `elevation = atan2(z, √(x² + y²))`.
//!
//! ```
//! use frontends::lidar::{LidarConfig, LidarPipeline, PointCloud};
//!
//! // A 5 × 5 patch of points 0.1 m apart, 8 m ahead of the sensor and 0.5 m above it.
//! let points = (0..25).map(|k| [8.0, 0.1 * (k % 5) as f32, 0.5 + 0.1 * (k / 5) as f32]).collect();
//! let pipeline = LidarPipeline::new(LidarConfig::default()).unwrap();
//! let measurements = pipeline.measurements(&PointCloud::from_points(points));
//! assert_eq!(measurements.len(), 1);
//! let [range, azimuth, elevation] = measurements[0];
//! assert!((range - 8.03).abs() < 0.01 && azimuth > 0.0 && elevation > 0.0);
//! ```

mod cloud_file;
mod clustering;
mod config;
mod error;
mod ground;
mod kitti;
mod measurement;
mod pcd;
mod pcd_header;
mod pipeline;
mod point_cloud;
mod ransac_plane;
mod velodyne;

pub use cloud_file::read_point_cloud;
pub use clustering::{euclidean_clusters, ClusteringConfig, PointCluster};
pub use config::LidarConfig;
pub use error::{CloudFileError, CloudFileProblem, LidarConfigError};
pub use ground::{GroundRemoval, HeightThreshold};
pub use kitti::{decode_kitti_bin, encode_kitti_bin, read_kitti_bin, write_kitti_bin};
pub use measurement::point_to_measurement;
pub use pcd::{decode_pcd, encode_pcd, read_pcd, write_pcd, PcdEncoding};
pub use pipeline::{LidarPipeline, Segmentation};
pub use point_cloud::PointCloud;
pub use ransac_plane::{fit_ground_plane, GroundPlaneFit, Plane, RansacPlaneParams};
pub use velodyne::{
    decode_velodyne_packet, to_point, FiringBlock, RotationAssembler, VelodyneError, VelodyneModel,
    FIRST_SCAN_START_DEG, PACKET_LEN,
};
