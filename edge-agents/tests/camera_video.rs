//! `edge-agent camera --video`: the default room's camera `cam1` rendered by the simulator (people walking in
//! a textured room, `simulator::render::camera`) to PNG frames and made into a lossless video (FFV1, RGB), read
//! as a file and played live into stdin by `ffmpeg -re`, each giving the head points of the frames to the
//! pixel; and sources that are garbage, end, or never open.
//!
//! Needs the `ffmpeg` executable: skipped (saying so) without it, failed under CI.

mod common;
mod live_support;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use common::{check_replay, edge_agent, edge_agent_ok, START};
use live_support::{children_of, have_ffmpeg, now, start_agent, terminate};
use protocol::MeasurementSet;
use simulator::render::camera::{write_frame_directory, CameraRenderer, CameraRoom};

/// Frame rate of the rendered video; low enough for the live run to keep up on a loaded 2-core host.
const FPS: u32 = 10;
/// Frames of the empty room before anybody walks in (the background model's default N = 16 learns
/// from them).
const EMPTY_FRAMES: usize = 16;
/// Frames from the scenario's start on (target 1 walks in at 0.5 s, the others at 2 and 4.5 s).
const PEOPLE_FRAMES: usize = 60;
/// The camera rendered.
const CAMERA: &str = "cam1";
const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;

/// The camera's descriptor, as the scenario publishes it.
fn descriptor(dir: &Path) -> String {
    let scenario = simulator::default_room();
    let (_, spec) = scenario.sensor(CAMERA).expect("the room has cam1");
    let path = dir.join("cam.json");
    let text = serde_json::to_string(&spec.descriptor(&scenario.site)).expect("descriptor JSON");
    std::fs::write(&path, text).expect("write descriptor");
    path.to_str().expect("utf-8 path").to_owned()
}

/// Renders the room's `cam1` at `FPS` to `dir/frames/NNNNNN.png` (from before anybody is in) and encodes
/// `dir/people.mkv` from them, losslessly.
fn render_video(dir: &Path) -> (String, String) {
    let frames = dir.join("frames");
    let scenario = simulator::default_room();
    let (_, spec) = scenario.sensor(CAMERA).expect("the room has cam1");
    let mut spec = spec.clone();
    (spec.rate_hz, spec.phase_s) = (f64::from(FPS), 0.0);
    let mut renderer = CameraRenderer::new(&scenario, CAMERA, &CameraRoom::default(), 20_240_611)
        .expect("cam1 renders");
    let from = -(EMPTY_FRAMES as f64) / f64::from(FPS);
    let to = PEOPLE_FRAMES as f64 / f64::from(FPS);
    let rendered =
        write_frame_directory(&mut renderer, &spec, from, to, &frames).expect("write frames");
    assert_eq!(rendered.paths.len(), EMPTY_FRAMES + PEOPLE_FRAMES);
    let video = dir.join("people.mkv");
    let status = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-y"])
        .args(["-framerate", &FPS.to_string()])
        .arg("-i")
        .arg(frames.join("%06d.png"))
        .args(["-c:v", "ffv1", "-pix_fmt", "bgr0"])
        .arg(&video)
        .status()
        .expect("ffmpeg runs");
    assert!(status.success(), "ffmpeg made no video");
    let text = |p: &Path| p.to_str().expect("utf-8 path").to_owned();
    (text(&frames), text(&video))
}

fn points(sets: &[MeasurementSet]) -> Vec<&Vec<Vec<f64>>> {
    sets.iter().map(|s| &s.measurements).collect()
}

#[test]
fn a_video_file_and_a_live_stream_give_the_head_points_of_its_frames() {
    if !have_ffmpeg("a_video_file_and_a_live_stream_give_the_head_points_of_its_frames") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = descriptor(dir.path());
    let (frames, video) = render_video(dir.path());
    let common = [
        "camera",
        "--descriptor",
        &descriptor,
        "--raw",
        "--output",
        "-",
    ];
    let fps = FPS.to_string();
    let reference = check_replay(&edge_agent_ok(
        &[
            &common[..],
            &["--frames", &frames, "--fps", &fps, "--start", START],
        ]
        .concat(),
    ));
    assert_eq!(
        reference.sets.len(),
        PEOPLE_FRAMES,
        "one set per frame after learning"
    );
    let people_seen = reference
        .sets
        .iter()
        .filter(|s| !s.measurements.is_empty())
        .count();
    assert!(
        people_seen > PEOPLE_FRAMES / 2,
        "the scene has people in it"
    );

    // The file: the frame rate from the stream, the very same sets (stamps included).
    let file = check_replay(&edge_agent_ok(
        &[&common[..], &["--video", &video, "--start", START]].concat(),
    ));
    assert_eq!(
        file.sets, reference.sets,
        "--video FILE differs from --frames"
    );

    // Live: ffmpeg plays the file in real time into the agent's stdin.
    let mut player = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-re", "-i", &video])
        .args(["-c", "copy", "-f", "matroska", "-"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("ffmpeg plays the video");
    let started = now();
    let agent = start_agent(
        &[&common[..], &["--video", "-"]].concat(),
        Stdio::from(player.stdout.take().expect("player stdout")),
    );
    let live = agent.finish(Duration::from_secs(60));
    let ended = now();
    let _ = player.wait();
    assert!(
        live.success,
        "live run failed ({}): {}",
        live.status, live.log
    );
    let text: String = live.lines.iter().map(|(_, l)| format!("{l}\n")).collect();
    let replay = check_replay(text.as_bytes());
    // When the agent falls behind it drops whole frames, and the background model then learns from other
    // frames: the head points are compared only when none was dropped (the log says which).
    let none_dropped = live.log.contains("dropped=0");
    println!(
        "live: {} sets of {} ({})",
        replay.sets.len(),
        reference.sets.len(),
        if none_dropped {
            "no frame dropped"
        } else {
            "frames dropped"
        }
    );
    if none_dropped {
        assert_eq!(
            points(&replay.sets),
            points(&reference.sets),
            "live head points differ"
        );
    } else {
        assert!(replay.sets.len() <= reference.sets.len());
    }
    // Stamps are the arrival times on the host clock: within the run, spaced like the frames, each set out
    // shortly after its frame arrived.
    let stamps: Vec<f64> = replay.sets.iter().map(|s| s.stamp).collect();
    let (first, last) = (stamps[0], stamps[stamps.len() - 1]);
    assert!(
        first >= started && last <= ended,
        "stamps {first}..{last} outside the run {started}..{ended}"
    );
    let spacing = (last - first) / (stamps.len() - 1) as f64;
    println!(
        "live: stamps span {:.2} s for {} frames at {FPS} fps (mean spacing {:.1} ms, expected {:.1} ms)",
        last - first,
        stamps.len(),
        spacing * 1e3,
        1e3 / f64::from(FPS)
    );
    if none_dropped {
        // Dropped frames would widen the spacing; without them it is the frame period.
        assert!(
            (spacing * f64::from(FPS) - 1.0).abs() < 0.5,
            "stamps do not follow the wall clock"
        );
    }
    let lags: Vec<f64> = live
        .lines
        .iter()
        .skip(1)
        .zip(&stamps)
        .map(|((at, _), s)| at - s)
        .collect();
    let worst = lags.iter().cloned().fold(0.0, f64::max);
    let mean = lags.iter().sum::<f64>() / lags.len() as f64;
    println!(
        "live: set written {:.1} ms after its frame arrived on average, {:.1} ms at worst",
        mean * 1e3,
        worst * 1e3
    );
}

#[test]
fn bad_and_vanishing_video_sources_end_the_run_cleanly() {
    if !have_ffmpeg("bad_and_vanishing_video_sources_end_the_run_cleanly") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = descriptor(dir.path());
    let common = [
        "camera",
        "--descriptor",
        &descriptor,
        "--raw",
        "--output",
        "-",
    ];

    // Garbage on stdin: ffmpeg finds no video in it, a clear error.
    let garbage: Vec<u8> = (0..200_000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    std::fs::write(dir.path().join("garbage.bin"), &garbage).expect("write garbage");
    let agent = start_agent(
        &[&common[..], &["--video", "-"]].concat(),
        Stdio::from(std::fs::File::open(dir.path().join("garbage.bin")).expect("garbage file")),
    );
    let run = agent.finish(Duration::from_secs(20));
    assert!(!run.success, "garbage was accepted");
    assert!(
        run.log.contains("error: video: no frame from -"),
        "{}",
        run.log
    );
    println!(
        "garbage on stdin: {}",
        run.log.lines().last().unwrap_or_default()
    );

    // A missing file: the same kind of error, naming it.
    let output = edge_agent(&[&common[..], &["--video", "nowhere.mkv", "--fps", "25"]].concat());
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && log.contains("nowhere.mkv"),
        "{log}"
    );

    // No ffmpeg on PATH: an error that says how to install it.
    let output = Command::new(env!("CARGO_BIN_EXE_edge-agent"))
        .args([&common[..], &["--video", "-"]].concat())
        .env("PATH", dir.path())
        .stdin(Stdio::null())
        .output()
        .expect("edge-agent runs");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && log.contains("apt-get install ffmpeg"),
        "{log}"
    );

    // A stream that stops in the middle (its writer killed): the frames so far, the end logged, exit 0.
    let mut writer = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-re", "-f", "lavfi"])
        .args([
            "-i",
            &format!("testsrc=size={WIDTH}x{HEIGHT}:rate=25"),
            "-t",
            "30",
        ])
        .args(["-c:v", "ffv1", "-pix_fmt", "bgr0", "-f", "matroska", "-"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("ffmpeg writes a stream");
    let agent = start_agent(
        &[&common[..], &["--video", "-"]].concat(),
        Stdio::from(writer.stdout.take().expect("writer stdout")),
    );
    std::thread::sleep(Duration::from_millis(1500));
    writer.kill().expect("kill the writer");
    let _ = writer.wait();
    let run = agent.finish(Duration::from_secs(20));
    assert!(
        run.success,
        "a vanished stream is not a failure: {}",
        run.log
    );
    assert!(run.log.contains("video source ended"), "{}", run.log);
    println!(
        "vanished stream: {} sets, then: {}",
        run.lines.len() - 1,
        run.log
            .lines()
            .find(|l| l.contains("video source ended"))
            .unwrap_or_default()
    );
    assert!(run.lines.len() > 1, "sets before the stream vanished");

    // A network source nobody serves: re-opened with a growing pause until the agent is stopped, which
    // stops its ffmpeg too.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let url = format!("http://127.0.0.1:{port}/stream");
    let agent = start_agent(&[&common[..], &["--video", &url]].concat(), Stdio::null());
    std::thread::sleep(Duration::from_millis(2500));
    let ffmpegs = children_of(agent.child.id());
    terminate(agent.child.id());
    let run = agent.finish(Duration::from_secs(10));
    assert!(run.success, "{}", run.log);
    for pause in ["250 ms", "500 ms", "1000 ms"] {
        assert!(
            run.log.contains(&format!("opening it again in {pause}")),
            "no re-open after {pause}: {}",
            run.log
        );
    }
    std::thread::sleep(Duration::from_millis(200));
    for pid in ffmpegs {
        let state = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
        assert!(
            has_ended(&state),
            "ffmpeg {pid} outlived the agent: {state}"
        );
    }
    println!(
        "unreachable network source: {} re-opens logged before SIGTERM",
        run.log.matches("opening it again").count()
    );
}

/// Whether a process whose `/proc/<pid>/stat` reads `stat` has ended: gone, or a zombie (it exited;
/// the init process it was handed to after the agent ended has not collected its status yet, which
/// one that does not reap, as in some containers, never does).
fn has_ended(stat: &str) -> bool {
    let state = stat.rsplit_once(')').map(|(_, rest)| rest.trim_start());
    match state {
        None => stat.is_empty(),
        Some(rest) => rest.starts_with('Z') || rest.starts_with('X'),
    }
}
