//! The sensor subcommands on real data files (written by the tests): camera frames and MOT detections, a
//! stereo WAV for the microphone pair, and the replay lines they produce.

mod common;

use std::path::Path;

use common::{check_replay, edge_agent_ok, START};

/// A 320×240 camera looking along the world's y axis; its exact projection does not matter to the agent.
const CAMERA_DESCRIPTOR: &str = r#"
sensor = "cam7"
detection_probability = 0.9
clutter_rate = 0.5
[model]
kind = "camera"
projection = [[250, 160, 0, 0], [0, 120, -250, 500], [0, 1, 0, 0]]
image_size = [320, 240]
noise_std = [2.0, 2.0]
"#;

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).expect("write test file");
}

fn path_str(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// `det.txt` of one 30×90 px box moving right by 4 px per frame over 25 frames.
fn moving_box_detections() -> String {
    (1..=25)
        .map(|frame| format!("{frame},-1,{},60,30,90,0.9\n", 100 + 4 * frame))
        .collect()
}

#[test]
fn camera_detections_go_through_the_single_view_tracker() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("cam7.toml");
    write(&descriptor, CAMERA_DESCRIPTOR);
    let detections = dir.path().join("det.txt");
    write(&detections, &moving_box_detections());
    let args = [
        "camera",
        "--descriptor",
        path_str(&descriptor),
        "--detections",
        path_str(&detections),
        "--fps",
        "10",
        "--start",
        START,
        "--output",
        "-",
    ];
    let replay = check_replay(&edge_agent_ok(&args));
    assert_eq!(replay.descriptors[0].site.as_str(), "default");
    assert_eq!(replay.sets.len(), 25, "one set per frame");
    let last = replay.sets.last().expect("sets");
    assert!((last.stamp - (1_763_700_000.0 + 2.4)).abs() < 1e-6);
    assert_eq!(last.measurements.len(), 1, "one tracked head: {last:?}");
    // Head point of frame 25: top-centre of the box.
    let (u, v) = (100.0 + 4.0 * 25.0 + 15.0, 60.0);
    assert!((last.measurements[0][0] - u).abs() < 3.0, "{last:?}");
    assert!((last.measurements[0][1] - v).abs() < 3.0, "{last:?}");
    let covariance = &last
        .covariances
        .as_ref()
        .expect("tracker estimates carry covariances")[0];
    // The estimate is the label's merged component, which includes its missed-detection hypothesis, so its
    // spread lies between the measurement noise (4 px²) and a few times it; far below a birth cell's.
    assert!(
        covariance[0][0] > 1.0 && covariance[0][0] < 25.0,
        "{covariance:?}"
    );

    let raw = check_replay(&edge_agent_ok(&[&args[..], &["--raw"]].concat()));
    assert!(raw.sets.iter().all(|s| s.covariances.is_none()));
    assert_eq!(raw.sets[24].measurements, vec![vec![u, v]]);
}

#[test]
fn camera_frames_go_through_background_subtraction() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("cam7.json");
    let json: serde_json::Value = toml::from_str::<toml::Value>(CAMERA_DESCRIPTOR)
        .map(|t| serde_json::to_value(t).expect("toml to json"))
        .expect("descriptor toml");
    write(&descriptor, &json.to_string());
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).expect("frames dir");
    // 16 empty frames train the background; then a dark 30×80 box walks in.
    for index in 0..26u32 {
        let mut image = image::RgbImage::from_pixel(320, 240, image::Rgb([170, 180, 160]));
        if index >= 16 {
            let left = 60 + 6 * (index - 16);
            for y in 70..150 {
                for x in left..left + 30 {
                    image.put_pixel(x, y, image::Rgb([40, 30, 90]));
                }
            }
        }
        image
            .save(frames.join(format!("{index:04}.png")))
            .expect("save frame");
    }
    let replay = check_replay(&edge_agent_ok(&[
        "camera",
        "--descriptor",
        path_str(&descriptor),
        "--frames",
        path_str(&frames),
        "--fps",
        "25",
        "--start",
        START,
        "--output",
        "-",
        "--raw",
    ]));
    assert_eq!(
        replay.sets.len(),
        10,
        "the 16 learning frames yield no sets"
    );
    assert!((replay.sets[0].stamp - (1_763_700_000.0 + 16.0 / 25.0)).abs() < 1e-6);
    let first = &replay.sets[0].measurements;
    assert_eq!(first.len(), 1, "{first:?}");
    assert!(
        (first[0][0] - 75.0).abs() < 3.0 && (first[0][1] - 70.0).abs() < 3.0,
        "{first:?}"
    );

    // A stamps file gives the frames' own stamps; with --start they are shifted so the first is there.
    let stamps = dir.path().join("stamps.txt");
    let lines: String = (0..26)
        .map(|i| format!("{}\n", 500.0 + 0.05 * f64::from(i)))
        .collect();
    write(&stamps, &format!("# capture times\n{lines}"));
    let with_stamps = |extra: &[&str]| {
        let args = [
            "camera",
            "--descriptor",
            path_str(&descriptor),
            "--frames",
            path_str(&frames),
            "--stamps",
            path_str(&stamps),
            "--output",
            "-",
            "--raw",
        ];
        check_replay(&edge_agent_ok(&[&args[..], extra].concat()))
    };
    let recorded = with_stamps(&[]);
    assert!((recorded.sets[0].stamp - 500.8).abs() < 1e-9);
    let shifted = with_stamps(&["--start", START]);
    assert!((shifted.sets[0].stamp - (1_763_700_000.0 + 0.8)).abs() < 1e-6);
    assert_eq!(shifted.sets[0].measurements, recorded.sets[0].measurements);
}

/// A stereo 16 kHz WAV of white noise whose second channel lags the first by `lag` samples.
fn write_delayed_noise(path: &Path, seconds: f64, lag: usize) {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: 16_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let count = (seconds * 16_000.0) as usize;
    // A fixed linear congruential generator: the same noise on every run.
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let noise: Vec<i16> = (0..count + lag)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            ((state >> 33) as i32 % 16_000 - 8_000) as i16
        })
        .collect();
    let mut writer = hound::WavWriter::create(path, spec).expect("create wav");
    for n in 0..count {
        writer.write_sample(noise[n + lag]).expect("mic 1 sample");
        writer.write_sample(noise[n]).expect("mic 2 sample");
    }
    writer.finalize().expect("finish wav");
}

#[test]
fn mic_pair_turns_a_delayed_stereo_recording_into_its_tdoa() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("pair.toml");
    write(
        &descriptor,
        r#"
        site = "room"
        sensor = "mics_s"
        detection_probability = 0.7
        clutter_rate = 1.0
        [model]
        kind = "mic_pair"
        mics = [[1.25, 0.0, 1.5], [1.75, 0.0, 1.5]]
        noise_std = 6.25e-5
        "#,
    );
    let wav = dir.path().join("pair.wav");
    // Mic 2 hears the sound 8 samples (0.5 ms) after mic 1: the source is closer to mic 1, tau > 0.
    write_delayed_noise(&wav, 1.0, 8);
    // A broadband noise source looks like background noise to the speech-presence check: off.
    let frontend = dir.path().join("frontend.toml");
    write(
        &frontend,
        "mic_distance = 0.5\nmin_spectral_contrast = 0.0\n",
    );
    let replay = check_replay(&edge_agent_ok(&[
        "mic-pair",
        "--frontend-config",
        path_str(&frontend),
        "--descriptor",
        path_str(&descriptor),
        "--wav",
        path_str(&wav),
        "--start",
        START,
        "--output",
        "-",
    ]));
    assert_eq!(replay.descriptors[0].site.as_str(), "room");
    assert_eq!(
        replay.sets.len(),
        3,
        "three whole 256 ms frames in one second"
    );
    for set in &replay.sets {
        let strongest = set
            .measurements
            .first()
            .expect("a correlated pair gives a TDOA")[0];
        assert!(
            (strongest - 0.0005).abs() < 2e-5,
            "tau {strongest} in {set:?}"
        );
    }
    assert!((replay.sets[0].stamp - (1_763_700_000.0 + 0.128)).abs() < 1e-6);
}

/// A LIDAR scan: flat ground 1.5 m below the sensor, a person-sized column of points `person_x` metres ahead,
/// and a small object 30 m away (beyond the descriptor's `max_range`).
fn lidar_scene(person_x: f32) -> frontends::lidar::PointCloud {
    let mut points = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            points.push([-5.0 + 0.25 * i as f32, -5.0 + 0.25 * j as f32, -1.5]);
        }
    }
    for k in 0..200 {
        let (a, b, layer) = ((k % 5) as f32, ((k / 5) % 5) as f32, (k / 25) as f32);
        points.push([person_x + 0.02 * a, 0.02 * b, -1.2 + 0.2 * layer]);
    }
    for k in 0..50 {
        points.push([
            30.0 + 0.05 * (k % 5) as f32,
            0.05 * ((k / 5) % 5) as f32,
            -1.0 + 0.1 * (k / 25) as f32,
        ]);
    }
    frontends::lidar::PointCloud::from_points(points)
}

#[test]
fn lidar_scans_become_person_centres_inside_the_sensor_region() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("lidar.toml");
    write(
        &descriptor,
        r#"
        sensor = "lidar1"
        detection_probability = 0.9
        clutter_rate = 1.0
        [model]
        kind = "lidar"
        position = [0.0, 0.0, 1.5]
        orientation = [1.0, 0.0, 0.0, 0.0]
        noise_std = [0.05, 0.01, 0.01]
        max_range = 20.0
        elevation_limits = [-1.0, 1.0]
        "#,
    );
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).expect("scans dir");
    frontends::lidar::write_kitti_bin(scans.join("000.bin"), &lidar_scene(3.0)).expect("bin scan");
    frontends::lidar::write_pcd(
        scans.join("001.pcd"),
        &lidar_scene(3.2),
        frontends::lidar::PcdEncoding::Binary,
    )
    .expect("pcd scan");
    write(&scans.join("notes.txt"), "not a scan");
    let replay = check_replay(&edge_agent_ok(&[
        "lidar",
        "--descriptor",
        path_str(&descriptor),
        "--scans",
        path_str(&scans),
        "--rate",
        "10",
        "--start",
        START,
        "--output",
        "-",
    ]));
    assert_eq!(
        replay.sets.len(),
        2,
        "one set per scan file, other files ignored"
    );
    assert!((replay.sets[1].stamp - replay.sets[0].stamp - 0.1).abs() < 1e-6);
    for (set, x) in replay.sets.iter().zip([3.0, 3.2]) {
        assert_eq!(
            set.measurements.len(),
            1,
            "the far object is outside max_range: {set:?}"
        );
        // The front end reports a person's centre, not the visible points' mean: the centroid pushed back
        // along the ray by (π/4) × the default body radius 0.17 m, at the column's highest point (0.2 m).
        let (cx, cz) = (x + 0.04 + std::f64::consts::FRAC_PI_4 * 0.17, 0.2);
        let m = &set.measurements[0];
        assert!((m[0] - f64::hypot(cx, cz)).abs() < 0.05, "range {m:?}");
        assert!(m[1].abs() < 0.05, "azimuth {m:?}");
        assert!((m[2] - f64::atan2(cz, cx)).abs() < 0.02, "elevation {m:?}");
    }
}
