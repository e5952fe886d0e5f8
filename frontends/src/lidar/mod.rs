//! LIDAR front end: a point cloud (PCD, KITTI `.bin`, Velodyne packets) to `[range, azimuth, elevation]`
//! measurements of people's centres in the sensor frame.
//!
//! Lee et al. (ACM SAC 2010) project a Velodyne scan onto a range image (beam × azimuth), segment it and use
//! the segments' centroids as the measurements of a GM-PHD tracker. This module: removes the ground (a height
//! threshold, or a RANSAC plane fit), rebuilds the range image from the points' angles (`range_image.rs`; the
//! files carry no ring field), joins neighbouring cells whose ranges are close (`range_segmentation.rs`), keeps
//! the person-sized segments and reports each one's centre, not its visible surface's centroid, at the height
//! of the top of the head (`objects.rs`). A cloud with no ring structure is grouped by Euclidean clustering
//! over a k-d tree instead (`clustering.rs`). Measurements follow the protocol's convention
//! `azimuth = atan2(y, x)`, `elevation = atan2(z, √(x² + y²))`.
//!
//! ```
//! use frontends::lidar::{LidarConfig, LidarPipeline, PointCloud};
//!
//! // Four rings 2° apart and five columns 0.2° apart of a surface 8 m ahead, around the sensor's height.
//! let mut points = Vec::new();
//! for ring in 0..4 {
//!     for column in 0..5 {
//!         let (elevation, azimuth) = ((-3.0 + 2.0 * ring as f32).to_radians(), (0.1 + 0.2 * column as f32).to_radians());
//!         points.push([8.0 * azimuth.cos(), 8.0 * azimuth.sin(), 8.0 * elevation.tan()]);
//!     }
//! }
//! let pipeline = LidarPipeline::new(LidarConfig::default()).unwrap();
//! let measurements = pipeline.measurements(&PointCloud::from_points(points));
//! assert_eq!(measurements.len(), 1);
//! let [range, azimuth, elevation] = measurements[0];
//! // The body's axis: (π/4) · 0.17 m behind the surface; at the top ring's height (no ground seen here).
//! assert!((range - 8.14).abs() < 0.01 && azimuth > 0.0 && elevation > 0.0);
//! ```

mod body_parts;
mod cloud_file;
mod clustering;
mod config;
mod error;
mod ground;
mod kitti;
mod measurement;
mod objects;
mod pcd;
mod pcd_header;
mod people_split;
mod pipeline;
mod point_cloud;
mod range_image;
mod range_segmentation;
mod ransac_plane;
mod velodyne;

pub use cloud_file::read_point_cloud;
pub use clustering::{euclidean_clusters, ClusteringConfig, PointCluster};
pub use config::{LidarConfig, SegmentationMethod};
pub use error::{CloudFileError, CloudFileProblem, LidarConfigError};
pub use ground::{GroundRemoval, HeightThreshold};
pub use kitti::{decode_kitti_bin, encode_kitti_bin, read_kitti_bin, write_kitti_bin};
pub use measurement::{measurement_covariance, point_to_measurement};
pub use objects::{detect_object, DetectedObject, Estimate, GroundFrame, ObjectConfig};
pub use pcd::{decode_pcd, encode_pcd, read_pcd, write_pcd, PcdEncoding};
pub use pipeline::{LidarPipeline, Segmentation};
pub use point_cloud::PointCloud;
pub use range_image::RangeImageConfig;
pub use ransac_plane::{fit_ground_plane, GroundPlaneFit, Plane, RansacPlaneParams};
pub use velodyne::{
    decode_velodyne_packet, to_point, FiringBlock, RotationAssembler, VelodyneError, VelodyneModel,
    FIRST_SCAN_START_DEG, PACKET_LEN,
};
