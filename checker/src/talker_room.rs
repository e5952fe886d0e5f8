//! The two-talker room of the microphone-pair checks (`tests/tests/raw_mic_tracks.rs`,
//! `examples/rendered_speech_scene.rs`): the default room's first two people, heard only by its
//! four microphone pairs, from a fixed Unix start.

use fusion_server::config::ServerConfig;
use protocol::SensorModel;
use simulator::Scenario;

/// Scenario time 0 of the room (Unix time, s).
pub const START: f64 = 1_763_700_000.0;

/// The server's configuration for this room of talkers, as its user would write it: talkers are
/// followed by what they say, so their pauses are modelled (`filter.speech_activity`), and people
/// who walk about while talking are a random walk (`filter.motion`, 0.15 m/√s; 0.1 for talkers who
/// stand) rather than a constant velocity that a silent talker's track would coast away on. Few people
/// come in (`filter.birth_rate` 0.05 a second): every birth component is a candidate for a ghost at the
/// crossing of two talkers' hyperbolas.
pub const SERVER_TOML: &str = "[site]
name = \"default\"

[filter]
speech_activity = true
motion = \"random_walk\"
position_noise_std = 0.15
birth_rate = 0.05
";

/// [`SERVER_TOML`] read and checked.
pub fn server_config() -> anyhow::Result<ServerConfig> {
    let config: ServerConfig = toml::from_str(SERVER_TOML)?;
    config.validate()?;
    Ok(config)
}

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
