//! Sensor front ends: raw data to measurements; pure, no networking.
//!
//! - [`camera`]: people tracked on the background-subtracted image by a multi-Bernoulli filter
//!   ([`camera::multi_bernoulli`], Hoseinnezhad, Vo & Vu); background subtraction in rgI chromaticity,
//!   blobs, head points; MOT `det.txt`.
//! - [`mic`]: GCC-PHAT time differences of arrival from a microphone pair.
//! - [`lidar`]: point-cloud readers, ground removal, Euclidean clustering, centroids.

pub mod camera;
pub mod lidar;
pub mod mic;
