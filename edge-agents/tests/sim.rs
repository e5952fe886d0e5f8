//! `edge-agent sim --output`: the replay files it writes are well-formed, reproducible, and the same whether
//! a sensor is simulated alone or with the others.

mod common;

use common::{check_replay, edge_agent_ok, START};

/// The built-in room, 3 s of it, seed 7, with truth.
fn room_replay(extra: &[&str]) -> Vec<u8> {
    let mut args = vec![
        "sim",
        "--output",
        "-",
        "--truth",
        "--seed",
        "7",
        "--duration",
        "3",
        "--start",
        START,
    ];
    args.extend_from_slice(extra);
    edge_agent_ok(&args)
}

#[test]
fn sim_writes_a_valid_replay_file_identically_twice() {
    let first = room_replay(&[]);
    let replay = check_replay(&first);
    let names: Vec<&str> = replay
        .descriptors
        .iter()
        .map(|d| d.sensor.as_str())
        .collect();
    assert_eq!(
        names,
        ["cam1", "cam2", "mics_s", "mics_e", "mics_n", "mics_w", "lidar"],
        "every sensor of the room, in scenario order"
    );
    // 3 s: truth at 25 Hz, cameras at 25 Hz, mic pairs every 256 ms, the LIDAR at 10 Hz.
    assert_eq!(replay.truth_lines, 75);
    let count = |name: &str| {
        replay
            .sets
            .iter()
            .filter(|s| s.sensor.as_str() == name)
            .count()
    };
    assert_eq!(count("cam1"), 75);
    assert_eq!(count("lidar"), 30);
    assert_eq!(count("mics_s"), 12);
    assert!(
        replay.sets.iter().any(|s| !s.measurements.is_empty()),
        "people are in the room: some sets must hold measurements"
    );
    let first_stamp = replay.sets[0].stamp;
    assert!(
        (first_stamp - 1_763_700_000.0).abs() < 1.0,
        "stamps start at --start"
    );

    let second = room_replay(&[]);
    assert!(
        first == second,
        "two runs with the same seed and start differ"
    );
    let other_seed = edge_agent_ok(&[
        "sim",
        "--output",
        "-",
        "--seed",
        "8",
        "--duration",
        "3",
        "--start",
        START,
    ]);
    assert!(first != other_seed, "the seed must matter");
}

#[test]
fn a_sensor_simulated_alone_gets_exactly_its_sets_of_the_full_run() {
    let full = check_replay(&room_replay(&[]));
    let alone_bytes = edge_agent_ok(&[
        "sim",
        "--output",
        "-",
        "--seed",
        "7",
        "--duration",
        "3",
        "--start",
        START,
        "--sensor",
        "mics_e",
        "--sensor",
        "cam2",
    ]);
    let alone = check_replay(&alone_bytes);
    assert_eq!(alone.truth_lines, 0, "no truth without --truth");
    let names: Vec<&str> = alone
        .descriptors
        .iter()
        .map(|d| d.sensor.as_str())
        .collect();
    assert_eq!(
        names,
        ["cam2", "mics_e"],
        "scenario order, whatever the flag order"
    );
    for name in ["cam2", "mics_e"] {
        let pick = |sets: &[protocol::MeasurementSet]| -> Vec<protocol::MeasurementSet> {
            sets.iter()
                .filter(|s| s.sensor.as_str() == name)
                .cloned()
                .collect()
        };
        assert_eq!(
            pick(&alone.sets),
            pick(&full.sets),
            "{name} differs when simulated alone"
        );
    }

    // `camera --simulate` is the same code path as `sim --sensor`.
    let simulated_camera = check_replay(&edge_agent_ok(&[
        "camera",
        "--simulate",
        "--sensor",
        "cam2",
        "--output",
        "-",
        "--seed",
        "7",
        "--duration",
        "3",
        "--start",
        START,
    ]));
    let alone_cam2: Vec<_> = alone
        .sets
        .iter()
        .filter(|s| s.sensor.as_str() == "cam2")
        .cloned()
        .collect();
    assert_eq!(simulated_camera.sets, alone_cam2);
}

#[test]
fn a_scenario_file_and_site_override_are_honoured() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scenario = dir.path().join("one.toml");
    std::fs::write(
        &scenario,
        r#"
        duration_s = 2.0
        truth_rate_hz = 5.0
        [[targets]]
        id = 1
        motion = { kind = "constant_velocity", position = [0.0, 0.0, 1.0], velocity = [0.5, 0.0, 0.0] }
        [[sensors]]
        sensor = "gps"
        detection_probability = 1.0
        clutter_rate = 0.0
        rate_hz = 4.0
        model = { kind = "position", noise_std = [0.1, 0.1, 0.1], region = { min = [-10.0, -10.0, -1.0], max = [10.0, 10.0, 3.0] } }
        "#,
    )
    .expect("write scenario");
    let bytes = edge_agent_ok(&[
        "sim",
        "--scenario",
        scenario.to_str().expect("utf-8 path"),
        "--site",
        "lab-2",
        "--truth",
        "--output",
        "-",
        "--start",
        START,
    ]);
    let replay = check_replay(&bytes);
    assert_eq!(replay.descriptors.len(), 1);
    assert_eq!(replay.descriptors[0].site.as_str(), "lab-2");
    assert_eq!(replay.truth_lines, 10);
    assert_eq!(replay.sets.len(), 8);
    assert!(
        replay.sets.iter().all(|s| s.measurements.len() == 1),
        "p_D = 1, no clutter"
    );
}
