//! Sensor front ends: raw data to measurements; pure, no networking.
pub mod lidar;
pub mod camera;
pub mod mic;
