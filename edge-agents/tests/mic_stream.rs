//! `mic-pair --wav -`: a live WAV stream on stdin gives the sets of the same audio read as a file, each soon
//! after its frame's last sample arrived; bad streams end with a clear error or a clean exit, never a panic.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{check_replay, edge_agent_ok, START};

const RATE: usize = 16_000;
/// The front end's default frame: 256 ms.
const FRAME: usize = 4096;

const DESCRIPTOR: &str = r#"
sensor = "mics_s"
detection_probability = 0.7
clutter_rate = 1.0
[model]
kind = "mic_pair"
mics = [[1.25, 0.0, 1.5], [1.75, 0.0, 1.5]]
noise_std = 6.25e-5
"#;

/// Stereo 16-bit WAV bytes: noise bursts (half a second on, a quarter off) whose second channel lags the
/// first by 8 samples.
fn delayed_noise_wav(seconds: f64) -> Vec<u8> {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: RATE as u32,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let count = (seconds * RATE as f64) as usize;
    let lag = 8;
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let noise: Vec<i16> = (0..count + lag)
        .map(|n| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            let on = n % 12_000 < 8_000;
            if on {
                ((state >> 33) as i32 % 16_000 - 8_000) as i16
            } else {
                ((state >> 33) as i32 % 40 - 20) as i16
            }
        })
        .collect();
    let mut bytes = std::io::Cursor::new(Vec::new());
    let mut writer = hound::WavWriter::new(&mut bytes, spec).expect("wav writer");
    for n in 0..count {
        writer.write_sample(noise[n + lag]).expect("mic 1");
        writer.write_sample(noise[n]).expect("mic 2");
    }
    writer.finalize().expect("finish wav");
    bytes.into_inner()
}

/// Where the samples start, after setting the RIFF and data sizes to a stream writer's 0xFFFFFFFF.
fn as_stream(wav: &mut [u8]) -> usize {
    let data = wav
        .windows(4)
        .position(|w| w == b"data")
        .expect("data chunk");
    wav[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    wav[data + 4..data + 8].copy_from_slice(&u32::MAX.to_le_bytes());
    data + 8
}

/// Starts `edge-agent mic-pair --wav - --output -` with piped stdio.
fn live_agent(descriptor: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_edge-agent"))
        .args(["mic-pair", "--descriptor"])
        .arg(descriptor)
        .args(["--wav", "-", "--output", "-"])
        .env("RUST_LOG", "info")
        .env("NO_COLOR", "1")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("edge-agent starts")
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

#[test]
fn a_live_stream_gives_the_sets_of_the_file_each_within_50_ms_of_its_frame() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("pair.toml");
    std::fs::write(&descriptor, DESCRIPTOR).expect("descriptor");
    let wav = delayed_noise_wav(4.0);
    let file = dir.path().join("pair.wav");
    std::fs::write(&file, &wav).expect("wav file");
    let from_file = check_replay(&edge_agent_ok(&[
        "mic-pair",
        "--descriptor",
        descriptor.to_str().unwrap(),
        "--wav",
        file.to_str().unwrap(),
        "--start",
        START,
        "--output",
        "-",
    ]));

    let mut stream = wav.clone();
    let header = as_stream(&mut stream);
    let mut agent = live_agent(&descriptor);
    let mut stdin = agent.stdin.take().expect("stdin");
    let stdout = agent.stdout.take().expect("stdout");
    let lines = std::thread::spawn(move || {
        BufReader::new(stdout)
            .lines()
            .map(|line| (Instant::now(), line.expect("stdout line")))
            .collect::<Vec<_>>()
    });
    // Real-time pace: 10 ms pieces, each written when its last sample is due; note when each frame's last
    // sample went in.
    let piece = 160 * 4;
    stdin.write_all(&stream[..header]).expect("header");
    let began = Instant::now();
    let mut frame_ends = Vec::new();
    let samples = &stream[header..];
    for (index, chunk) in samples.chunks(piece).enumerate() {
        let due = began + Duration::from_millis(10 * (index as u64 + 1));
        std::thread::sleep(due.saturating_duration_since(Instant::now()));
        stdin.write_all(chunk).expect("audio piece");
        stdin.flush().expect("flush");
        let written = (index * piece + chunk.len()) / 4;
        while written >= (frame_ends.len() + 1) * FRAME {
            frame_ends.push(Instant::now());
        }
    }
    drop(stdin);
    let status = agent.wait().expect("agent ends");
    let mut stderr = String::new();
    agent
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    assert!(status.success(), "agent failed: {stderr}");
    assert!(stderr.contains("the audio stream ended"), "{stderr}");
    let lines = lines.join().expect("stdout reader");
    let text: String = lines.iter().map(|(_, l)| format!("{l}\n")).collect();
    let live = check_replay(text.as_bytes());

    assert_eq!(live.sets.len(), from_file.sets.len(), "one set per frame");
    for (a, b) in live.sets.iter().zip(&from_file.sets) {
        assert_eq!(a.measurements, b.measurements, "TDOAs of frame {}", a.seq);
    }
    for pair in live.sets.windows(2) {
        let step = pair[1].stamp - pair[0].stamp;
        assert!((step - 0.256).abs() < 0.05, "stamps {step} s apart");
    }
    let set_lines: Vec<Instant> = lines
        .iter()
        .filter(|(_, l)| l.starts_with("{\"measurements\""))
        .map(|(t, _)| *t)
        .collect();
    let mut latency: Vec<f64> = set_lines
        .iter()
        .zip(&frame_ends)
        .map(|(seen, end)| seen.saturating_duration_since(*end).as_secs_f64() * 1e3)
        .collect();
    latency.sort_by(f64::total_cmp);
    let (p50, p99, max) = (
        percentile(&latency, 0.5),
        percentile(&latency, 0.99),
        latency[latency.len() - 1],
    );
    println!(
        "live WAV: {} sets, from a frame's last sample written to its set on stdout: p50 {p50:.1} ms, p99 {p99:.1} ms, max {max:.1} ms",
        latency.len()
    );
    assert!(p50 < 50.0, "median latency {p50:.1} ms");
}

/// Runs the live agent on `input` (written at once, then stdin closed); returns success and stderr.
fn run_on(input: &[u8]) -> (bool, String, Vec<u8>) {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("pair.toml");
    std::fs::write(&descriptor, DESCRIPTOR).expect("descriptor");
    let mut agent = live_agent(&descriptor);
    let mut stdin = agent.stdin.take().expect("stdin");
    // The agent may stop reading at a bad header: a broken pipe here is expected.
    let _ = stdin.write_all(input);
    drop(stdin);
    let output = agent.wait_with_output().expect("agent ends");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    (output.status.success(), stderr, output.stdout)
}

#[test]
fn a_truncated_header_or_garbage_is_a_clear_error() {
    let wav = delayed_noise_wav(0.5);
    let (ok, stderr, _) = run_on(&wav[..30]);
    assert!(!ok && stderr.contains("truncated header"), "{stderr}");
    let garbage: Vec<u8> = (0..5000u32).map(|i| (i * 7919 % 251) as u8).collect();
    let (ok, stderr, _) = run_on(&garbage);
    assert!(!ok && stderr.contains("not a WAV stream"), "{stderr}");
    let (ok, stderr, _) = run_on(b"");
    assert!(!ok && stderr.contains("truncated header"), "{stderr}");
}

#[test]
fn a_stream_closed_mid_frame_ends_cleanly_after_its_whole_frames() {
    let mut wav = delayed_noise_wav(1.0);
    let header = as_stream(&mut wav);
    // Two whole frames, half of a third, and half a sample pair.
    let cut = header + (2 * FRAME + FRAME / 2) * 4 + 2;
    let (ok, stderr, stdout) = run_on(&wav[..cut]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("the audio stream ended"), "{stderr}");
    let replay = check_replay(&stdout);
    assert_eq!(replay.sets.len(), 2);
    println!(
        "stdin closed mid-frame: {}",
        stderr
            .lines()
            .find(|l| l.contains("the audio stream ended"))
            .unwrap_or_default()
    );
}

/// The number after `name=` in a log line.
fn logged_count(line: &str, name: &str) -> u64 {
    let at = line.find(&format!("{name}=")).expect("field logged") + name.len() + 1;
    line[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect::<String>()
        .parse()
        .expect("a count")
}

#[test]
fn audio_faster_than_the_analysis_is_dropped_in_whole_frames_counted_and_logged() {
    // Five minutes of audio written at once: the reader takes it in far faster than the analysis
    // runs, as a capture would outrun an overloaded agent, so its queue fills and frames are dropped.
    let mut wav = delayed_noise_wav(300.0);
    let header = as_stream(&mut wav);
    let frames = ((wav.len() - header) / 4 / FRAME) as u64;
    let (ok, stderr, stdout) = run_on(&wav);
    assert!(ok, "{stderr}");
    let replay = check_replay(&stdout);
    let drop_report = stderr
        .lines()
        .find(|l| l.contains("whole frames dropped"))
        .unwrap_or_else(|| panic!("the drops are logged: {stderr}"));
    let end = stderr
        .lines()
        .find(|l| l.contains("the audio stream ended"))
        .expect("the end is logged");
    let (analysed, dropped) = (logged_count(end, "frames"), logged_count(end, "dropped"));
    println!("{frames} frames written at once: {analysed} analysed, {dropped} dropped");
    println!("  {drop_report}");
    assert!(dropped > 0, "{end}");
    // Every whole frame is either analysed (one set each) or counted as dropped: none vanishes.
    assert_eq!(analysed + dropped, frames, "{end}");
    assert_eq!(replay.sets.len() as u64, analysed);
}
