//! Configuration: the example file holds the defaults, environment variables override keys,
//! and a bad value stops the server with an error that names the key.

use std::io::Write;
use std::path::Path;

use fusion_server::config::{BirthKind, MotionKind, ServerConfig};

fn example() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/fusion.example.toml"))
}

fn write_toml(text: &str) -> tempfile::NamedTempFile {
    let mut file = tempfile::Builder::new().suffix(".toml").tempfile().unwrap();
    file.write_all(text.as_bytes()).unwrap();
    file
}

#[test]
fn the_example_file_is_valid_and_holds_the_defaults() {
    let loaded = ServerConfig::load(Some(example())).unwrap();
    let defaults = ServerConfig::default();
    assert_eq!(
        format!("{:?}", loaded.filter),
        format!("{:?}", defaults.filter)
    );
    assert_eq!(
        format!("{:?}", loaded.tracks),
        format!("{:?}", defaults.tracks)
    );
    assert_eq!(
        format!("{:?}", loaded.ingest),
        format!("{:?}", defaults.ingest)
    );
    assert_eq!(
        format!("{:?}", loaded.output),
        format!("{:?}", defaults.output)
    );
    assert!(loaded.output.json && loaded.output.history_s == 600.0);
    assert_eq!(loaded.zenoh.listen, vec!["tcp/127.0.0.1:7447".to_string()]);
    assert_eq!(loaded.site.name, "default");
}

/// A static position sensor, as `fusion.example.toml` shows it.
const STATIC_SENSOR: &str = "[[sensors]]
version = 1
site = \"default\"
sensor = \"pos1\"
detection_probability = 0.9
clutter_rate = 1.0
model = { kind = \"position\", noise_std = [0.1, 0.1, 0.1], region = { min = [0, 0, 0], max = [3, 2, 2.2] } }
";

#[test]
fn typed_values_at_load() {
    let file = write_toml(&format!(
        "[filter]\nmotion = \"random_walk\"\nbirth = \"mixture\"\nbirth_means = [[1, 1, 1]]\n{STATIC_SENSOR}"
    ));
    let config = ServerConfig::load(Some(file.path())).unwrap();
    assert_eq!(config.filter.motion, MotionKind::RandomWalk);
    assert_eq!(config.filter.birth, BirthKind::Mixture);
    assert_eq!(config.sensors.len(), 1);
    assert_eq!(config.sensors[0].sensor.as_str(), "pos1");
    assert_eq!(config.sensors[0].detection_probability, 0.9);
}

#[test]
fn bad_values_name_their_key() {
    let foreign_sensor = STATIC_SENSOR.replace("\"default\"", "\"elsewhere\"");
    let impossible_sensor = STATIC_SENSOR.replace("= 0.9", "= 1.9");
    let cases = [
        (
            "[filter]\nsurvival_probability = 1.5\n",
            "filter.survival_probability",
        ),
        ("[filter]\nmotion = \"teleport\"\n", "filter.motion"),
        ("[filter]\nbirth = \"everywhere\"\n", "filter.birth"),
        ("[filter]\nbirth = \"mixture\"\n", "filter.birth_means"),
        (
            "[[sensors]]\nversion = 1\nsite = \"default\"\nsensor = \"pos1\"\n",
            "sensors[0]",
        ),
        (foreign_sensor.as_str(), "sensors[0]"),
        (impossible_sensor.as_str(), "sensors[0]"),
        (
            "[filter]\nadaptive_birth_rate = -0.5\n",
            "filter.adaptive_birth_rate",
        ),
        (
            "[filter]\nadaptive_birth_velocity_std = 0\n",
            "filter.adaptive_birth_velocity_std",
        ),
        (
            "[filter]\ntdoa_side_peak_offset_s = -1e-4\n",
            "filter.tdoa_side_peak_offset_s",
        ),
        (
            "[filter]\ntdoa_side_peak_rate = 0\n",
            "filter.tdoa_side_peak_rate",
        ),
        ("[zenoh]\nmode = \"router\"\n", "zenoh.mode"),
        ("[zenoh]\nconnect = [\"localhost\"]\n", "zenoh.connect"),
        ("[site]\nname = \"a/b\"\n", "site.name"),
        ("[tracks]\nconfirm_hits = 9\n", "tracks.confirm_hits"),
        (
            "[tracks]\nconfirm_at_once_threshold = 0.2\n",
            "tracks.confirm_at_once_threshold",
        ),
        ("[ingest]\nmax_future_s = -1\n", "ingest.max_future_s"),
        ("[output]\nhistory_s = -5\n", "output.history_s"),
        ("[output]\nmax_publish_hz = 0\n", "output.max_publish_hz"),
    ];
    for (text, key) in cases {
        let file = write_toml(text);
        let error = ServerConfig::load(Some(file.path()))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(key),
            "{text:?} gave {error:?}, which does not name {key}"
        );
    }
    let file = write_toml("[filter]\nmax_componentz = 3\n");
    let error = ServerConfig::load(Some(file.path()))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("max_componentz"),
        "a misspelt key is named: {error}"
    );
}
