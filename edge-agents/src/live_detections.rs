//! `--detections -`: boxes from a detector running in front of the agent, read live from stdin, one frame
//! of head points handed on as soon as it is complete.
//!
//! Two line formats, told apart by the first non-blank line (`{` starts JSON):
//! - MOT Challenge `det.txt` lines (`frame, id, left, top, width, height[, score, x, y, z]`, the parser of
//!   `frontends::camera`): a frame is complete when a line of a later frame arrives, or at the end of the
//!   input. It is stamped when its first line arrived. Frame numbers skipped in between (frames without
//!   boxes) become empty frames stamped evenly between their neighbours, up to [`MAX_GAP`] of them.
//! - JSON lines, one frame each: `{"stamp": 1712.5, "boxes": [[left, top, w, h, score], ...]}`; `stamp`
//!   (Unix seconds) may be left out, the frame is then stamped when the line arrived; `score` may be left
//!   out (the box is then kept whatever `mot_det.min_score`).
//!
//! Arrival stamps are the host clock less `--pipeline-delay-ms`. A line that cannot be read (not the
//! format, not UTF-8, longer than [`MAX_LINE`], a frame or stamp going back) is dropped, counted and logged
//! (at most one warning per 5 s); input from which no frame at all could be read is an error.

use std::collections::VecDeque;
use std::io::{BufRead, Read};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError};
use frontends::camera::{parse_mot_line, MotDetConfig, MotDetection};
use serde::Deserialize;

use crate::capture_clock::CaptureClock;
use crate::error::AgentError;
use transport::LogLimiter;

/// Longest line read, in bytes; the rest of a longer one is skipped.
pub const MAX_LINE: usize = 1 << 20;
/// Most empty frames inserted for skipped MOT frame numbers; a longer jump is taken as a renumbering.
pub const MAX_GAP: usize = 250;
/// How often a wait for input looks at the shutdown flag.
const POLL: Duration = Duration::from_millis(100);

/// One frame: its stamp and a head point per box.
pub type StampedPoints = (f64, Vec<[f64; 2]>);

/// One line as the reader thread delivers it.
enum Line {
    /// Its text (or why it is not text) and when it arrived.
    Text(Result<String, String>, Instant),
    /// The end of the input (with the read error that ended it, if any).
    End(Option<String>),
}

/// The format of the input, set by its first line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Mot,
    Json,
}

/// A JSON line.
#[derive(Debug, Deserialize)]
struct JsonFrame {
    stamp: Option<f64>,
    boxes: Vec<Vec<f64>>,
}

/// The MOT frame still collecting boxes.
struct Pending {
    frame: usize,
    stamp: f64,
    points: Vec<[f64; 2]>,
}

/// Frames of head points read from a line stream.
pub struct LiveDetections {
    lines: Receiver<Line>,
    config: MotDetConfig,
    clock: CaptureClock,
    format: Option<Format>,
    pending: Option<Pending>,
    ready: VecDeque<StampedPoints>,
    last_stamp: f64,
    line_number: usize,
    frames: u64,
    bad: BadLines,
    ended: bool,
}

/// Lines dropped, with a rate-limited log.
struct BadLines {
    count: u64,
    first: Option<String>,
    log: LogLimiter,
}

impl LiveDetections {
    /// Reads `input` (stdin) on a thread of its own, from now on.
    pub fn start(
        input: impl Read + Send + 'static,
        config: MotDetConfig,
        clock: CaptureClock,
    ) -> Result<Self, AgentError> {
        let (sender, lines) = crossbeam_channel::bounded(1024);
        std::thread::Builder::new()
            .name("detections-reader".into())
            .spawn(move || read_lines(input, &sender))
            .map_err(|e| AgentError::Usage(format!("cannot start the detections reader: {e}")))?;
        Ok(Self {
            lines,
            config,
            clock,
            format: None,
            pending: None,
            ready: VecDeque::new(),
            last_stamp: f64::NEG_INFINITY,
            line_number: 0,
            frames: 0,
            bad: BadLines {
                count: 0,
                first: None,
                log: LogLimiter::new(Duration::from_secs(5)),
            },
            ended: false,
        })
    }

    /// The next complete frame (stamp, head points); `None` at the end of the input or when `stop` says so
    /// while waiting.
    pub fn next_frame(
        &mut self,
        stop: impl Fn() -> bool,
    ) -> Result<Option<StampedPoints>, AgentError> {
        loop {
            if let Some(frame) = self.ready.pop_front() {
                self.frames += 1;
                return Ok(Some(frame));
            }
            if self.ended {
                return self.summary();
            }
            match self.lines.recv_timeout(POLL) {
                Ok(Line::Text(text, arrived)) => self.take_line(text, arrived),
                Ok(Line::End(error)) => self.end(error),
                Err(RecvTimeoutError::Disconnected) => self.end(None),
                Err(RecvTimeoutError::Timeout) if stop() => return Ok(None),
                Err(RecvTimeoutError::Timeout) => {}
            }
        }
    }

    /// At the end: the last MOT frame is complete; the run ends, as an error if nothing could be read.
    fn end(&mut self, error: Option<String>) {
        self.ended = true;
        if let Some(error) = error {
            tracing::warn!(%error, "reading detections from stdin failed");
        }
        if let Some(pending) = self.pending.take() {
            self.ready.push_back((pending.stamp, pending.points));
        }
    }

    /// Logs what was read; an error when lines came but none made a frame.
    fn summary(&self) -> Result<Option<StampedPoints>, AgentError> {
        tracing::info!(
            frames = self.frames,
            dropped_lines = self.bad.count,
            "detections input ended"
        );
        match (&self.bad.first, self.frames) {
            (Some(first), 0) => Err(AgentError::Usage(format!(
                "no detections could be read from stdin ({} bad lines; first: {first})",
                self.bad.count
            ))),
            _ => Ok(None),
        }
    }

    /// Takes one line in.
    fn take_line(&mut self, text: Result<String, String>, arrived: Instant) {
        self.line_number += 1;
        let outcome = text.and_then(|text| {
            let line = text.trim_start_matches('\u{feff}').trim();
            if line.is_empty() {
                return Ok(());
            }
            let format = *self.format.get_or_insert(if line.starts_with("{") {
                Format::Json
            } else {
                Format::Mot
            });
            let stamp = self.clock.stamp_at(arrived);
            match format {
                Format::Json => self.take_json(line, stamp),
                Format::Mot => self.take_mot(line, stamp),
            }
        });
        if let Err(problem) = outcome {
            self.bad_line(problem);
        }
    }

    /// Counts and (rate-limited) logs a dropped line.
    fn bad_line(&mut self, problem: String) {
        let problem = format!("line {}: {problem}", self.line_number);
        self.bad.count += 1;
        if let Some(suppressed) = self.bad.log.allow("bad line") {
            tracing::warn!(
                dropped_lines = self.bad.count,
                suppressed,
                "detection line dropped: {problem}"
            );
        }
        self.bad.first.get_or_insert(problem);
    }

    /// One JSON line: one frame.
    fn take_json(&mut self, line: &str, arrived: f64) -> Result<(), String> {
        let frame: JsonFrame = serde_json::from_str(line).map_err(|e| format!("JSON: {e}"))?;
        let stamp = frame.stamp.unwrap_or(arrived);
        if !stamp.is_finite() || stamp < self.last_stamp {
            return Err(format!(
                "stamp {stamp} is not after the previous frame's {}",
                self.last_stamp
            ));
        }
        let mut points = Vec::with_capacity(frame.boxes.len());
        for values in &frame.boxes {
            let detection = json_box(values)?;
            if detection.score.is_none_or(|s| s >= self.config.min_score) {
                points.push(detection.point(self.config.anchor));
            }
        }
        self.last_stamp = stamp;
        self.ready.push_back((stamp, points));
        Ok(())
    }

    /// One MOT line: a box of the pending frame, or the first of a later one.
    fn take_mot(&mut self, line: &str, arrived: f64) -> Result<(), String> {
        let detection = parse_mot_line(line)?;
        let keep = detection.score.is_none_or(|s| s >= self.config.min_score);
        let point = detection.point(self.config.anchor);
        match &mut self.pending {
            Some(pending) if detection.frame == pending.frame => {
                if keep {
                    pending.points.push(point);
                }
                return Ok(());
            }
            Some(pending) if detection.frame < pending.frame => {
                return Err(format!(
                    "frame {} after frame {}",
                    detection.frame, pending.frame
                ));
            }
            _ => {}
        }
        if let Some(done) = self.pending.take() {
            self.complete(done, detection.frame, arrived);
        }
        self.pending = Some(Pending {
            frame: detection.frame,
            stamp: arrived,
            points: if keep { vec![point] } else { Vec::new() },
        });
        Ok(())
    }

    /// Hands on a completed MOT frame and the empty frames skipped between it and frame `next`, stamped
    /// `next_stamp`.
    fn complete(&mut self, done: Pending, next: usize, next_stamp: f64) {
        let gap = next - done.frame - 1;
        let start = done.stamp;
        self.ready.push_back((done.stamp, done.points));
        if gap > MAX_GAP {
            tracing::warn!(
                from = done.frame,
                to = next,
                "MOT frame numbers jump by more than {MAX_GAP}: no empty frames inserted"
            );
            return;
        }
        let step = (next_stamp - start) / (gap + 1) as f64;
        for k in 1..=gap {
            self.ready.push_back((start + step * k as f64, Vec::new()));
        }
    }
}

/// `[left, top, width, height]` or with a score, as a MOT box.
fn json_box(values: &[f64]) -> Result<MotDetection, String> {
    let (left, top, width, height, score) = match *values {
        [left, top, width, height] => (left, top, width, height, None),
        [left, top, width, height, score] => (left, top, width, height, Some(score)),
        _ => {
            return Err(format!(
                "a box is [left, top, width, height, score?], not {} numbers",
                values.len()
            ))
        }
    };
    if !values.iter().all(|v| v.is_finite()) || width <= 0.0 || height <= 0.0 {
        return Err(format!("box {values:?} is not finite with a positive size"));
    }
    Ok(MotDetection {
        frame: 1,
        left,
        top,
        width,
        height,
        score,
    })
}

/// The reader thread: every line with its arrival time, then the end.
fn read_lines(input: impl Read, lines: &crossbeam_channel::Sender<Line>) {
    let mut reader = std::io::BufReader::new(input);
    let mut buffer = Vec::new();
    loop {
        buffer.clear();
        let read = (&mut reader)
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut buffer);
        let arrived = Instant::now();
        let message = match read {
            Ok(0) => Line::End(None),
            Err(e) => Line::End(Some(e.to_string())),
            Ok(n) if n > MAX_LINE && buffer.last() != Some(&b'\n') => {
                skip_line(&mut reader);
                Line::Text(Err(format!("longer than {MAX_LINE} bytes")), arrived)
            }
            Ok(_) => Line::Text(
                String::from_utf8(std::mem::take(&mut buffer)).map_err(|_| "not UTF-8 text".into()),
                arrived,
            ),
        };
        let end = matches!(message, Line::End(_));
        if lines.send(message).is_err() || end {
            return;
        }
    }
}

/// Skips the rest of an over-long line, without keeping it.
fn skip_line(reader: &mut impl BufRead) {
    loop {
        let Ok(available) = reader.fill_buf() else {
            return;
        };
        if available.is_empty() {
            return;
        }
        match available.iter().position(|&b| b == b'\n') {
            Some(at) => {
                reader.consume(at + 1);
                return;
            }
            None => {
                let all = available.len();
                reader.consume(all);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(text: &'static str) -> Result<Vec<StampedPoints>, AgentError> {
        let clock = CaptureClock::new(0.0).unwrap();
        let mut live =
            LiveDetections::start(std::io::Cursor::new(text), MotDetConfig::default(), clock)?;
        let mut out = Vec::new();
        while let Some(frame) = live.next_frame(|| false)? {
            out.push(frame);
        }
        Ok(out)
    }

    #[test]
    fn mot_frames_are_grouped_and_skipped_frames_are_empty() {
        let out = frames("1,-1,10,20,30,60,0.9\n1,-1,100,20,30,60\n\n4,-1,10,20,30,60\n").unwrap();
        let points: Vec<usize> = out.iter().map(|(_, p)| p.len()).collect();
        assert_eq!(points, vec![2, 0, 0, 1]);
        assert_eq!(out[0].1, vec![[25.0, 20.0], [115.0, 20.0]]);
        assert!(out.windows(2).all(|w| w[1].0 >= w[0].0), "stamps in order");
    }

    #[test]
    fn lines_going_back_or_malformed_are_dropped_but_good_ones_kept() {
        let out =
            frames("2,-1,10,20,30,60\n1,-1,10,20,30,60\n2,-1,10,20,-3,60\n3,-1,1,2,3,4\n").unwrap();
        assert_eq!(out.len(), 2, "frames 2 and 3: {out:?}");
        let out =
            frames("{\"stamp\": 5, \"boxes\": [[1, 2, 3, 4]]}\n{\"stamp\": 4, \"boxes\": []}\n")
                .unwrap();
        assert_eq!(out, vec![(5.0, vec![[2.5, 2.0]])]);
    }

    #[test]
    fn a_jump_in_frame_numbers_inserts_no_flood_of_empty_frames() {
        let out = frames("1,-1,10,20,30,60\n900000,-1,10,20,30,60\n").unwrap();
        assert_eq!(out.len(), 2);
    }

    #[test]
    fn input_without_a_single_frame_is_an_error() {
        assert!(frames("hello\nworld\n").is_err());
        assert!(
            frames("").unwrap().is_empty(),
            "an empty input is just no frames"
        );
    }
}
