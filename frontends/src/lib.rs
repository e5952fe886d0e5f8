//! Sensor front ends: raw data to measurements; pure, no networking.
//!
//! - [`camera`]: background subtraction in rgI chromaticity, blobs, head points; MOT `det.txt`.
//! - [`mic`]: GCC-PHAT time differences of arrival from a microphone pair.
//! - [`lidar`]: point-cloud readers, ground removal, Euclidean clustering, centroids.

pub mod camera;
pub mod lidar;
pub mod mic;
