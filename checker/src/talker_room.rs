//! The two-talker room of the microphone-pair checks (`tests/tests/raw_mic_tracks.rs`,
//! `examples/rendered_speech_scene.rs`): the default room's first two people, heard only by its
//! four microphone pairs, from a fixed Unix start.

use protocol::SensorModel;
use simulator::Scenario;

/// Scenario time 0 of the room (Unix time, s).
pub const START: f64 = 1_763_700_000.0;

/// The default room with its first two people and its four microphone pairs only, `duration_s`
/// seconds long from [`START`].
pub fn two_talker_room(duration_s: f64) -> Scenario {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    scenario.duration_s = duration_s;
    scenario.targets.truncate(2);
    scenario
        .sensors
        .retain(|s| matches!(s.model, SensorModel::MicPair(_)));
    scenario
}
