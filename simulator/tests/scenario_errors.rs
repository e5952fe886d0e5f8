//! A bad scenario file is refused with a message that names the offending key.

use simulator::{Scenario, ScenarioError};

/// A valid scenario to break one key at a time.
const GOOD: &str = r#"
site = "lab"
duration_s = 10.0
truth_rate_hz = 10.0

[[targets]]
id = 1
appear_s = 1.0
motion = { kind = "random_walk", position = [1.0, 1.0, 1.7], std = [0.3, 0.3, 0.0], bounds = { min = [0.0, 0.0, 1.7], max = [3.0, 2.0, 1.7] } }

[[targets]]
id = 2
motion = { kind = "waypoints", points = [[0.0, [0.0, 0.0, 1.7]], [5.0, [3.0, 2.0, 1.7]]] }

[[sensors]]
sensor = "pos1"
detection_probability = 0.9
clutter_rate = 2.0
rate_hz = 10.0
model = { kind = "position", noise_std = [0.1, 0.1, 0.1], region = { min = [0.0, 0.0, 0.0], max = [3.0, 2.0, 2.5] } }
"#;

/// The error of `GOOD` with `from` replaced by `to` (which must occur in it).
fn error_of(from: &str, to: &str) -> ScenarioError {
    assert!(GOOD.contains(from), "test text lacks {from:?}");
    let text = GOOD.replacen(from, to, 1);
    match Scenario::from_toml_str(&text) {
        Ok(_) => panic!("accepted a scenario with {to:?}"),
        Err(e) => {
            println!("{to:?} -> {e}\n");
            e
        }
    }
}

/// Asserts that the message mentions every one of `words`.
fn assert_names(error: &ScenarioError, words: &[&str]) {
    let message = error.to_string();
    for word in words {
        assert!(
            message.contains(word),
            "{message:?} does not mention {word:?}"
        );
    }
}

#[test]
fn the_template_is_valid() {
    let scenario = Scenario::from_toml_str(GOOD).unwrap();
    assert_eq!(scenario.site.as_str(), "lab");
    assert_eq!(scenario.targets.len(), 2);
    assert_eq!(scenario.sensors[0].phase_s, 0.0);
}

#[test]
fn missing_and_unknown_keys_are_named() {
    let e = error_of("duration_s = 10.0\n", "");
    assert!(matches!(e, ScenarioError::Syntax { .. }), "{e:?}");
    assert_names(&e, &["duration_s"]);

    let e = error_of("duration_s", "duraton_s");
    assert_names(&e, &["duraton_s"]);

    let e = error_of("std = [0.3, 0.3, 0.0]", "stdev = [0.3, 0.3, 0.0]");
    assert_names(&e, &["stdev"]);

    let e = error_of("rate_hz = 10.0\nmodel", "rate = 10.0\nmodel");
    assert_names(&e, &["rate"]);
}

#[test]
fn wrong_types_and_kinds_are_named() {
    let e = error_of("truth_rate_hz = 10.0", "truth_rate_hz = \"fast\"");
    assert!(matches!(e, ScenarioError::Syntax { .. }), "{e:?}");
    assert_names(&e, &["truth_rate_hz"]);

    let e = error_of("kind = \"waypoints\"", "kind = \"teleport\"");
    assert_names(&e, &["teleport"]);

    let e = error_of("kind = \"position\"", "kind = \"sonar\"");
    assert_names(&e, &["sonar"]);

    let e = error_of("sensor = \"pos1\"", "sensor = \"pos/1\"");
    assert_names(&e, &["pos/1"]);
}

#[test]
fn bad_values_are_named_by_their_path() {
    let cases: &[(&str, &str, &[&str])] = &[
        ("duration_s = 10.0", "duration_s = -1.0", &["`duration_s`"]),
        (
            "truth_rate_hz = 10.0",
            "truth_rate_hz = 0.0",
            &["`truth_rate_hz`"],
        ),
        ("id = 2", "id = 1", &["`targets[1].id`", "another target"]),
        (
            "appear_s = 1.0",
            "appear_s = 1.0\ndisappear_s = 0.5",
            &["`targets[0].disappear_s`"],
        ),
        (
            "std = [0.3, 0.3, 0.0]",
            "std = [0.3, -0.3, 0.0]",
            &["`targets[0].motion.std[1]`"],
        ),
        (
            "position = [1.0, 1.0, 1.7]",
            "position = [5.0, 1.0, 1.7]",
            &["`targets[0].motion.position`", "outside"],
        ),
        (
            "[5.0, [3.0, 2.0, 1.7]]",
            "[0.0, [3.0, 2.0, 1.7]]",
            &["`targets[1].motion.points[1]`"],
        ),
        (
            "points = [[0.0, [0.0, 0.0, 1.7]], [5.0, [3.0, 2.0, 1.7]]]",
            "points = []",
            &["`targets[1].motion.points`"],
        ),
        (
            "detection_probability = 0.9",
            "detection_probability = 1.5",
            &["`sensors[0].detection_probability`"],
        ),
        (
            "clutter_rate = 2.0",
            "clutter_rate = -2.0",
            &["`sensors[0].clutter_rate`"],
        ),
        (
            "\nrate_hz = 10.0",
            "\nrate_hz = 0.0",
            &["`sensors[0].rate_hz`"],
        ),
        (
            "\nrate_hz = 10.0",
            "\nrate_hz = 10.0\nphase_s = -0.1",
            &["`sensors[0].phase_s`"],
        ),
    ];
    for (from, to, words) in cases {
        let e = error_of(from, to);
        assert!(
            matches!(e, ScenarioError::InvalidValue { .. }),
            "{to}: {e:?}"
        );
        assert_names(&e, words);
    }
}

#[test]
fn degenerate_models_and_duplicate_sensors_are_named() {
    let e = error_of("noise_std = [0.1, 0.1, 0.1]", "noise_std = [0.1, 0.0, 0.1]");
    assert!(matches!(e, ScenarioError::Descriptor { .. }), "{e:?}");
    assert_names(&e, &["`sensors[0]`", "noise_std"]);

    let twice = format!(
        "{GOOD}\n[[sensors]]\nsensor = \"pos1\"\ndetection_probability = 0.9\nclutter_rate = 0.0\n\
         rate_hz = 5.0\nmodel = {{ kind = \"position\", noise_std = [0.1, 0.1, 0.1], \
         region = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }} }}\n"
    );
    let e = Scenario::from_toml_str(&twice).unwrap_err();
    assert_names(&e, &["`sensors[1].sensor`", "pos1"]);
}

#[test]
fn a_missing_file_names_the_path() {
    let e = Scenario::from_file("/nonexistent/scenario.toml").unwrap_err();
    assert!(matches!(e, ScenarioError::Io { .. }), "{e:?}");
    assert_names(&e, &["/nonexistent/scenario.toml"]);
}
