//! The `ffmpeg` executable as a child process: it opens whatever a camera's `--video` names (a file, an
//! RTSP/HTTP URL, a V4L2 device, or stdin) and writes the decoded frames to its stdout as a stream of binary
//! PPM images (`-f image2pipe -c:v ppm -pix_fmt rgb24`), each of which carries its own size, in the exact
//! 8-bit RGB the camera front end reads. `ffprobe` gives a video file's frame rate.
//!
//! No FFmpeg library is linked: the agent stays a static binary, and a codec or protocol problem stays in
//! the child, which the agent reports and, for network sources, starts again.

use std::collections::VecDeque;
use std::io::{BufRead, BufReader};
use std::os::unix::process::CommandExt;
use std::process::{Child, ChildStderr, ChildStdout, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use crate::error::AgentError;
use transport::LogLimiter;

/// How many of ffmpeg's last stderr lines are kept to explain a failure.
const STDERR_TAIL: usize = 4;
/// How long a network source may deliver nothing before ffmpeg gives up on it, in microseconds.
pub const STALL_TIMEOUT_US: u64 = 5_000_000;
/// At most one of ffmpeg's stderr lines is logged per this interval.
const STDERR_LOG_INTERVAL: Duration = Duration::from_millis(200);

/// What `--video` names and how ffmpeg is started on it.
#[derive(Debug, Clone)]
pub struct VideoSpec {
    /// The source as ffmpeg's `-i` takes it; `-` is the agent's stdin.
    pub source: String,
    /// Extra ffmpeg options placed before `-i` (`--ffmpeg-input-args`), e.g. `-rtsp_transport tcp`.
    pub input_args: Vec<String>,
}

/// How a source is read, from its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceKind {
    /// A file: stamped from `--start` and the frame rate, read as fast as it is processed.
    File,
    /// Stdin or a device: stamped on arrival, the newest frame wins; its end is the end of the run.
    Live,
    /// A network stream: live, and opened again (with back-off) when it ends or breaks.
    Network,
}

impl VideoSpec {
    /// The kind of source its name says it is.
    pub fn kind(&self) -> SourceKind {
        const NETWORK: [&str; 9] = [
            "rtsp://", "rtsps://", "rtmp://", "http://", "https://", "udp://", "tcp://", "srt://",
            "rtp://",
        ];
        let lower = self.source.to_ascii_lowercase();
        if NETWORK.iter().any(|scheme| lower.starts_with(scheme)) {
            SourceKind::Network
        } else if self.source == "-" || self.source.starts_with("/dev/") {
            SourceKind::Live
        } else {
            SourceKind::File
        }
    }
}

impl VideoSpec {
    /// For HTTP, TCP and UDP sources, ffmpeg's `-rw_timeout`: a stream that stalls (connected, but no data
    /// for [`STALL_TIMEOUT_US`]) is then an error, and so re-opened, instead of a wait without end. An RTSP
    /// source needs `-timeout` (ffmpeg 5 or later) in `--ffmpeg-input-args` for the same.
    fn stall_timeout(&self) -> Vec<String> {
        let lower = self.source.to_ascii_lowercase();
        let covered = ["http://", "https://", "tcp://", "udp://"]
            .iter()
            .any(|scheme| lower.starts_with(scheme));
        if covered {
            vec!["-rw_timeout".into(), STALL_TIMEOUT_US.to_string()]
        } else {
            Vec::new()
        }
    }
}

/// A running ffmpeg decoding one source.
pub struct Decoder {
    /// The process, to be killed and reaped.
    child: Child,
    /// The last lines ffmpeg wrote on stderr (each also logged as it comes).
    stderr_tail: Arc<Mutex<VecDeque<String>>>,
}

/// Starts `ffmpeg` on `spec`; returns it with its stdout, the PPM frames. A missing executable is an error
/// that says how to install it.
pub fn spawn_decoder(spec: &VideoSpec) -> Result<(Decoder, ChildStdout), AgentError> {
    let mut command = Command::new("ffmpeg");
    command
        .args(["-hide_banner", "-nostdin", "-loglevel", "error"])
        .args(spec.stall_timeout())
        .args(&spec.input_args)
        .args(["-i", &spec.source])
        .args(["-map", "0:v:0", "-an", "-sn"])
        // One output image per decoded frame: no duplicates or drops to fit a frame rate.
        .args(["-vsync", "passthrough"])
        .args(["-f", "image2pipe", "-c:v", "ppm", "-pix_fmt", "rgb24", "-"])
        .stdin(if spec.source == "-" {
            Stdio::inherit()
        } else {
            Stdio::null()
        })
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own process group: a Ctrl-C in the terminal reaches the agent, which stops ffmpeg itself.
        .process_group(0);
    let mut child = command
        .spawn()
        .map_err(|e| missing_or_failed("ffmpeg", e))?;
    let (Some(frames), Some(stderr)) = (child.stdout.take(), child.stderr.take()) else {
        // Both were asked for as pipes above; without them there is nothing to read.
        let _ = child.kill();
        let _ = child.wait();
        return Err(AgentError::Video(
            "ffmpeg started without its output pipes".into(),
        ));
    };
    let stderr_tail = Arc::new(Mutex::new(VecDeque::new()));
    drain_stderr(stderr, Arc::clone(&stderr_tail), spec.source.clone());
    Ok((Decoder { child, stderr_tail }, frames))
}

impl Decoder {
    /// Kills ffmpeg if it still runs and reaps it; returns how it ended, with its last stderr lines.
    pub fn stop(mut self) -> String {
        let _ = self.child.kill();
        let status = match self.child.wait() {
            Ok(status) => status.to_string(),
            Err(e) => format!("not reaped: {e}"),
        };
        let tail = tail_text(&self.stderr_tail);
        if tail.is_empty() {
            format!("ffmpeg {status}")
        } else {
            format!("ffmpeg {status}: {tail}")
        }
    }
}

/// Logs ffmpeg's stderr line by line on a thread of its own (a full stderr pipe would stall ffmpeg) and
/// keeps the last lines.
fn drain_stderr(stderr: ChildStderr, tail: Arc<Mutex<VecDeque<String>>>, source: String) {
    std::thread::spawn(move || {
        // A damaged stream can make ffmpeg complain about every frame: a few lines a second are enough.
        let mut limit = LogLimiter::new(STDERR_LOG_INTERVAL);
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if let Some(suppressed) = limit.allow("ffmpeg stderr") {
                tracing::warn!(source = %source, suppressed, "ffmpeg: {line}");
            }
            if let Ok(mut tail) = tail.lock() {
                if tail.len() == STDERR_TAIL {
                    tail.pop_front();
                }
                tail.push_back(line);
            }
        }
    });
}

/// The kept stderr lines joined with ` / `.
fn tail_text(tail: &Mutex<VecDeque<String>>) -> String {
    tail.lock()
        .map(|lines| lines.iter().cloned().collect::<Vec<_>>().join(" / "))
        .unwrap_or_default()
}

/// The frame rate of a video file's first video stream, asked of `ffprobe`.
pub fn probe_frame_rate(source: &str) -> Result<f64, AgentError> {
    let output = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0"])
        .args(["-show_entries", "stream=avg_frame_rate,r_frame_rate"])
        .args(["-of", "default=noprint_wrappers=1:nokey=1", source])
        .stdin(Stdio::null())
        .output()
        .map_err(|e| missing_or_failed("ffprobe", e))?;
    let text = String::from_utf8_lossy(&output.stdout);
    let rate = text.lines().find_map(parse_rational);
    match (output.status.success(), rate) {
        (true, Some(rate)) => Ok(rate),
        _ => Err(AgentError::Video(format!(
            "cannot tell the frame rate of {source} (ffprobe: {}); give --fps",
            String::from_utf8_lossy(&output.stderr).trim()
        ))),
    }
}

/// `25/1` or `30000/1001` (or a plain number) as a positive rate; `0/0` and the like as `None`.
fn parse_rational(text: &str) -> Option<f64> {
    let text = text.trim();
    let rate = match text.split_once('/') {
        Some((num, den)) => num.trim().parse::<f64>().ok()? / den.trim().parse::<f64>().ok()?,
        None => text.parse::<f64>().ok()?,
    };
    (rate.is_finite() && rate > 0.0).then_some(rate)
}

/// The error for an executable that could not be started.
fn missing_or_failed(program: &str, error: std::io::Error) -> AgentError {
    if error.kind() == std::io::ErrorKind::NotFound {
        AgentError::Video(format!(
            "`{program}` was not found on PATH: --video decodes with the ffmpeg tools; install them \
             (Debian/Ubuntu: `apt-get install ffmpeg`, macOS: `brew install ffmpeg`)"
        ))
    } else {
        AgentError::Video(format!("cannot start `{program}`: {error}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sources_are_told_apart_by_their_names() {
        let kind = |source: &str| {
            VideoSpec {
                source: source.into(),
                input_args: Vec::new(),
            }
            .kind()
        };
        assert_eq!(kind("people.mkv"), SourceKind::File);
        assert_eq!(kind("-"), SourceKind::Live);
        assert_eq!(kind("/dev/video0"), SourceKind::Live);
        assert_eq!(kind("rtsp://cam.local/stream"), SourceKind::Network);
        assert_eq!(kind("HTTP://cam/mjpeg"), SourceKind::Network);
    }

    #[test]
    fn frame_rates_are_read_as_ffprobe_writes_them() {
        assert_eq!(parse_rational("25/1"), Some(25.0));
        assert!((parse_rational("30000/1001").unwrap() - 29.97).abs() < 0.01);
        assert_eq!(parse_rational("0/0"), None);
        assert_eq!(parse_rational("N/A"), None);
        assert_eq!(parse_rational("12.5"), Some(12.5));
    }
}
