//! Raw sensor signals rendered from a scenario's truth, for running the agents' real front ends
//! end to end: microphone-pair audio through a reverberant room (`mic_pair.rs`, built on the
//! image-source model in `room_acoustics.rs` and the speech-like voices of `speech.rs`).
//! Deterministic from (scenario, seed), like the simulated measurement sets.

pub mod camera;
pub mod mic_pair;
pub mod room_acoustics;
pub mod speech;

pub use mic_pair::{render_mic_pair, AcousticRoom, RenderedPair, Talker};
