//! Raw sensor signals rendered from a scenario's truth, for running the agents' real front ends
//! end to end: microphone-pair audio through a reverberant room (`mic_pair.rs`, built on the
//! image-source model in `room_acoustics.rs` and the speech-like voices of `speech.rs`), and
//! ray-cast LIDAR scans (`lidar.rs`, the scene's primitives in `lidar_scene.rs`), and camera frames
//! (`camera.rs`).
//! Deterministic from (scenario, seed), like the simulated measurement sets.

pub mod camera;
pub mod lidar;
pub mod lidar_scene;
pub mod mic_pair;
pub mod room_acoustics;
pub mod speech;

pub use lidar::{render_lidar_scan, BeamLayout, LidarReturn, RenderedScan, ScanPattern};
pub use lidar_scene::{LidarScene, Pole};
pub use mic_pair::{render_mic_pair, AcousticRoom, RenderedPair, Talker};
