//! The command line parses, and refuses what it must refuse with a clear message and a failing exit code.

mod common;

use common::{edge_agent, START};

/// Flags every subcommand has.
const SHARED_FLAGS: [&str; 7] = [
    "--site",
    "--config",
    "--mode",
    "--connect",
    "--listen",
    "--output",
    "--json",
];

#[test]
fn every_subcommand_has_help_with_its_flags() {
    let cases: [(&[&str], &[&str]); 5] = [
        (&["--help"], &["sim", "camera", "mic-pair", "lidar"]),
        (
            &["sim", "--help"],
            &[
                "--scenario",
                "--sensor",
                "--truth",
                "--seed",
                "--speed",
                "--start",
                "--duration",
            ],
        ),
        (
            &["camera", "--help"],
            &[
                "--frames",
                "--fps",
                "--stamps",
                "--detections",
                "--descriptor",
                "--simulate",
            ],
        ),
        (
            &["mic-pair", "--help"],
            &["--wav", "--left", "--right", "--start", "--descriptor"],
        ),
        (&["lidar", "--help"], &["--scans", "--rate", "--descriptor"]),
    ];
    for (args, flags) in cases {
        let output = edge_agent(args);
        assert!(output.status.success(), "{args:?}: {}", output.status);
        let help = String::from_utf8_lossy(&output.stdout);
        // Subcommands also carry the shared output and Zenoh flags.
        let shared: &[&str] = if args.len() > 1 { &SHARED_FLAGS } else { &[] };
        for flag in flags.iter().chain(shared) {
            assert!(help.contains(flag), "{args:?} help lacks {flag}:\n{help}");
        }
    }
}

#[test]
fn bad_flags_fail_with_a_message() {
    let cases: [(&[&str], &str); 5] = [
        (&["sim", "--site", "no/slash"], "site"),
        (&["sim", "--sensor", "nope", "--output", "-"], "nope"),
        (
            &["sim", "--speed", "0", "--output", "-", "--publish"],
            "--speed",
        ),
        (&["sim", "--mode", "router", "--output", "-"], "zenoh.mode"),
        (
            &["camera", "--output", "-", "--start", START],
            "--descriptor",
        ),
    ];
    for (args, needle) in cases {
        let output = edge_agent(args);
        assert!(!output.status.success(), "{args:?} should fail");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains(needle),
            "{args:?}: stderr lacks {needle:?}:\n{stderr}"
        );
        assert!(
            output.stdout.is_empty(),
            "{args:?} wrote output before failing"
        );
    }
}

#[test]
fn zenoh_settings_come_from_file_then_environment_then_flags() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = dir.path().join("agent.toml");
    std::fs::write(&config, "[zenoh]\nmode = \"client\"\n").expect("write config");
    let config = config.to_str().expect("utf-8 path");
    let run = |env: Option<(&str, &str)>, extra: &[&str]| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_edge-agent"));
        command.args([
            "sim",
            "--duration",
            "0.1",
            "--start",
            START,
            "--output",
            "-",
        ]);
        command.args(extra);
        if let Some((key, value)) = env {
            command.env(key, value);
        }
        command.output().expect("the edge-agent binary runs")
    };
    // A client needs a router: the file alone is refused, naming the key.
    let from_file = run(None, &["--config", config]);
    assert!(!from_file.status.success());
    assert!(String::from_utf8_lossy(&from_file.stderr).contains("zenoh.connect"));
    // The environment adds the router ...
    let with_env = run(
        Some(("AGENT__ZENOH__CONNECT", "tcp/127.0.0.1:7447")),
        &["--config", config],
    );
    assert!(
        with_env.status.success(),
        "{}",
        String::from_utf8_lossy(&with_env.stderr)
    );
    // ... or overrides the mode, and a flag overrides the environment.
    let env_mode = run(Some(("AGENT__ZENOH__MODE", "router")), &[]);
    assert!(String::from_utf8_lossy(&env_mode.stderr).contains("zenoh.mode"));
    let flag_wins = run(Some(("AGENT__ZENOH__MODE", "router")), &["--mode", "peer"]);
    assert!(
        flag_wins.status.success(),
        "{}",
        String::from_utf8_lossy(&flag_wins.stderr)
    );
}

#[test]
fn invalid_descriptor_file_is_refused_with_a_clear_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("cam.toml");
    std::fs::write(
        &descriptor,
        r#"
        sensor = "cam1"
        detection_probability = 1.5
        clutter_rate = 2.0
        [model]
        kind = "camera"
        projection = [[500, 0, 320, 0], [0, 500, 240, 0], [0, 0, 1, -2]]
        image_size = [640, 480]
        noise_std = [3.0, 3.0]
        "#,
    )
    .expect("write descriptor");
    let detections = dir.path().join("det.txt");
    std::fs::write(&detections, "1,-1,100,50,40,120,0.9\n").expect("write det.txt");
    let output = edge_agent(&[
        "camera",
        "--descriptor",
        descriptor.to_str().expect("utf-8 path"),
        "--detections",
        detections.to_str().expect("utf-8 path"),
        "--fps",
        "10",
        "--output",
        "-",
    ]);
    assert!(!output.status.success());
    assert_ne!(output.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("cam1") && stderr.contains("detection_probability"),
        "unclear error: {stderr}"
    );
    assert!(
        output.stdout.is_empty(),
        "nothing may be written for an invalid sensor"
    );
}
