//! LIDAR front end: a point cloud (PCD or KITTI `.bin`) to `[range, azimuth, elevation]` measurements of object
//! centroids in the sensor frame.
//!
//! Lee et al. (ACM SAC 2010) segment a Velodyne scan and use the centroids of the segmented clusters as the
//! measurements of a GM-PHD tracker. This module does the same with the steps common in current LIDAR stacks:
//! remove the ground (a height threshold, or a RANSAC plane fit), group the remaining points by Euclidean
//! clustering over a k-d tree, and turn each cluster's centroid into a measurement with the protocol's
//! convention `azimuth = atan2(y, x)`, `elevation = atan2(z, √(x² + y²))`.

mod error;
mod kitti;
mod pcd;
mod pcd_header;
mod point_cloud;

pub use error::{CloudFileError, CloudFileProblem, LidarConfigError};
pub use kitti::{decode_kitti_bin, encode_kitti_bin, read_kitti_bin, write_kitti_bin};
pub use pcd::{decode_pcd, encode_pcd, read_pcd, write_pcd, PcdEncoding};
pub use point_cloud::PointCloud;
