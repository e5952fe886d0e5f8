//! `edge-agent camera --detections -`: a detector writing MOT or JSON lines slowly into the agent's stdin,
//! one set per frame as soon as the frame is complete; garbage lines dropped and counted.

mod live_support;

use std::io::Write;
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

use live_support::{now, start_agent, LiveAgent};
use protocol::{MeasurementSet, ReplayLine};

/// How long the writer pauses between two frames.
const PAUSE: Duration = Duration::from_millis(120);
/// Longest wait for a set that must come.
const PATIENCE: Duration = Duration::from_secs(10);

fn descriptor(dir: &Path) -> String {
    let path = dir.join("cam.toml");
    std::fs::write(
        &path,
        "sensor = \"cam3\"\ndetection_probability = 0.9\nclutter_rate = 0.5\n[model]\nkind = \"camera\"\n\
         projection = [[250, 160, 0, 0], [0, 120, -250, 500], [0, 1, 0, 0]]\n\
         image_size = [320, 240]\nnoise_std = [2.0, 2.0]\n",
    )
    .expect("write descriptor");
    path.to_str().expect("utf-8 path").to_owned()
}

/// Starts the agent on stdin and waits for its descriptor line (written before any input is read).
fn start(dir: &Path) -> LiveAgent {
    let descriptor = descriptor(dir);
    let agent = start_agent(
        &[
            "camera",
            "--descriptor",
            &descriptor,
            "--detections",
            "-",
            "--raw",
            "--output",
            "-",
        ],
        Stdio::piped(),
    );
    let (_, line) = agent.next_line(PATIENCE).expect("the descriptor line");
    assert!(line.starts_with(r#"{"descriptor""#), "{line}");
    agent
}

/// Writes `text` to the agent's stdin at once.
fn send(agent: &mut LiveAgent, text: &str) {
    let stdin = agent.stdin.as_mut().expect("stdin piped");
    stdin
        .write_all(text.as_bytes())
        .expect("write to edge-agent");
    stdin.flush().expect("flush");
}

/// The next set the agent writes, with its arrival time; fails after [`PATIENCE`].
fn next_set(agent: &LiveAgent) -> (f64, MeasurementSet) {
    loop {
        let (at, line) = agent
            .next_line(PATIENCE)
            .expect("a set within the patience");
        if let Some(set) = parse_set(&line) {
            return (at, set);
        }
    }
}

/// The set of a replay line (`None` for a descriptor line).
fn parse_set(line: &str) -> Option<MeasurementSet> {
    match serde_json::from_str::<ReplayLine>(line).expect("a replay line") {
        ReplayLine::Measurements(set) => Some(set),
        _ => None,
    }
}

#[test]
fn mot_lines_from_a_slow_writer_give_one_set_per_frame_as_the_next_frame_starts() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut agent = start(dir.path());
    let mut latencies = Vec::new();
    let mut sets = Vec::new();
    // Frames 1..=8 with two boxes each, frame 6 without any (no line): the set of frame k comes when the
    // first line of the next frame arrives, and not before.
    let frames: Vec<usize> = (1..=8).filter(|&k| k != 6).collect();
    for (i, &k) in frames.iter().enumerate() {
        let x = 20 + 10 * k;
        let started = now();
        send(&mut agent, &format!("{k},-1,{x},30,20,60,0.9\n"));
        std::thread::sleep(PAUSE / 2);
        send(&mut agent, &format!("{k},-1,{},40,20,60,0.8\n", x + 100));
        if i > 0 {
            let (at, set) = next_set(&agent);
            latencies.push(at - started);
            sets.push(set);
            if k == 7 {
                let (_, empty) = next_set(&agent);
                assert!(empty.measurements.is_empty(), "frame 6 is an empty set");
                sets.push(empty);
            }
        }
        assert!(
            agent.next_line(Duration::ZERO).is_none(),
            "a set before its frame was complete"
        );
        std::thread::sleep(PAUSE);
    }
    let run = agent.finish(PATIENCE);
    assert!(run.success, "{}", run.log);
    sets.extend(run.lines.iter().filter_map(|(_, line)| parse_set(line)));
    assert_eq!(
        sets.len(),
        8,
        "one set per frame, frame 6 empty, frame 8 at the end of the input"
    );
    assert_eq!(
        sets[0].measurements,
        vec![vec![40.0, 30.0], vec![140.0, 40.0]]
    );
    for pair in sets.windows(2) {
        let step = pair[1].stamp - pair[0].stamp;
        assert!(step > 0.0, "stamps go forward");
    }
    let worst = latencies.iter().cloned().fold(0.0, f64::max);
    println!(
        "MOT lines: {} sets; a completed frame's set came {:.1} ms after the next frame's first line on average, {:.1} ms at worst",
        sets.len(),
        latencies.iter().sum::<f64>() / latencies.len() as f64 * 1e3,
        worst * 1e3
    );
}

#[test]
fn json_lines_are_one_set_each_at_once_and_garbage_lines_are_dropped() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut agent = start(dir.path());
    let mut latencies = Vec::new();
    let lines = [
        r#"{"stamp": 1712.5, "boxes": [[10, 20, 30, 60, 0.9], [100, 20, 30, 60]]}"#,
        "this is not a detection",
        r#"{"stamp": 1712.6, "boxes": []}"#,
        r#"{"boxes": [[50, 50, 20, 40, 0.95]]}"#,
        r#"{"stamp": 1.0, "boxes": []}"#,
        r#"{"boxes": [[50, 50, -20, 40]]}"#,
        r#"{"boxes": [[60, 50, 20, 40]]}"#,
    ];
    let mut sets = Vec::new();
    let before = now();
    for line in lines {
        let written = now();
        send(&mut agent, &format!("{line}\n"));
        let good = !line.contains("not a") && !line.contains("1.0,") && !line.contains("-20");
        if good {
            let (at, set) = next_set(&agent);
            latencies.push(at - written);
            sets.push(set);
        }
        std::thread::sleep(PAUSE);
    }
    send(&mut agent, "\u{1}\u{2}\u{3} binary \u{7f}\n");
    let run = agent.finish(PATIENCE);
    assert!(run.success, "{}", run.log);
    assert_eq!(
        run.lines.len(),
        0,
        "no set for the garbage lines: {:?}",
        run.lines
    );
    assert_eq!(sets.len(), 4);
    assert_eq!(sets[0].stamp, 1712.5);
    assert_eq!(
        sets[0].measurements,
        vec![vec![25.0, 20.0], vec![115.0, 20.0]]
    );
    assert!(sets[1].measurements.is_empty());
    assert!(
        sets[2].stamp >= before && sets[2].stamp <= now(),
        "no stamp: the host clock"
    );
    assert!(run.log.contains("dropped_lines=4"), "{}", run.log);
    println!(
        "JSON lines: {} sets, {:.1} ms from line to set on average; log: {}",
        sets.len(),
        latencies.iter().sum::<f64>() / latencies.len() as f64 * 1e3,
        run.log
            .lines()
            .find(|l| l.contains("detections input ended"))
            .unwrap_or_default()
    );
}

#[test]
fn garbage_alone_on_stdin_is_a_clear_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut agent = start(dir.path());
    let garbage: Vec<u8> = (0..300_000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 11) as u8)
        .collect();
    agent
        .stdin
        .as_mut()
        .expect("stdin")
        .write_all(&garbage)
        .expect("write garbage");
    let run = agent.finish(PATIENCE);
    assert!(!run.success, "garbage was accepted");
    assert!(
        run.log.contains("no detections could be read from stdin"),
        "{}",
        run.log
    );
    println!("garbage: {}", run.log.lines().last().unwrap_or_default());
}
