//! `--video SRC`: frames decoded by ffmpeg (see `ffmpeg.rs` and `video_reader.rs`) through the same
//! background subtraction as `--frames`.
//!
//! A file's frame i is stamped `--start + i / fps` (fps: `--fps`, else the stream's), so a run is a pure
//! function of the file, like `--frames`. A live source's frame is stamped when it arrived, on the host
//! clock less `--pipeline-delay-ms`. When the agent cannot keep up with a live source it drops whole frames
//! (the reader keeps only the newest); every 5 s in which frames were dropped it logs how many and how far
//! behind the processing runs.

use std::time::{Duration, Instant};

use frontends::camera::FrameRate;

use crate::camera_frontend::FrameProcessor;
use crate::camera_input::{CameraInput, FrontEndChoice, HeadPoints, InputItem, OpenedInput};
use crate::capture_clock::CaptureClock;
use crate::cli::CameraCommand;
use crate::error::AgentError;
use crate::ffmpeg::{probe_frame_rate, SourceKind, VideoSpec};
use crate::video_reader::{VideoMessage, VideoReader};
use transport::shutdown::signalled;

/// How often falling behind a live source is reported.
const REPORT_INTERVAL: Duration = Duration::from_secs(5);
/// How long one wait for a frame lasts before the shutdown flag is looked at again.
const POLL: Duration = Duration::from_millis(100);

/// How frames are stamped.
#[derive(Debug, Clone, Copy)]
enum VideoTiming {
    /// A file: from its frame index.
    Rate(FrameRate),
    /// A live source: on arrival.
    Live(CaptureClock),
}

/// A video source's frames, through the camera pipeline.
pub struct VideoInput {
    source: String,
    reader: VideoReader,
    /// Boxed: it holds the background model's buffers.
    processor: Box<FrameProcessor>,
    timing: VideoTiming,
    behind: Behind,
    /// The stamp of the last frame (a source going down is stamped no earlier).
    last_stamp: f64,
}

/// What the periodic report on a live source says.
struct Behind {
    since: Instant,
    dropped_before: u64,
    /// Largest time from a frame's arrival to its head points, in the current interval.
    worst_lag: f64,
}

impl VideoInput {
    /// Starts ffmpeg on `--video`; a file's frame rate is `--fps` or the stream's.
    pub fn open(
        command: &CameraCommand,
        front_end: &FrontEndChoice,
        start: f64,
    ) -> Result<OpenedInput, AgentError> {
        let source = command.video.clone().unwrap_or_default();
        let spec = VideoSpec {
            source: source.clone(),
            input_args: command
                .ffmpeg_input_args
                .as_deref()
                .unwrap_or_default()
                .split_whitespace()
                .map(str::to_owned)
                .collect(),
        };
        if command.stamps.is_some() {
            return Err(AgentError::Usage(
                "--stamps goes with --frames; --video is stamped by its frame rate or on arrival"
                    .into(),
            ));
        }
        let (timing, origin_stamp, origin_wall) = match spec.kind() {
            SourceKind::File => {
                let fps = match command.fps {
                    Some(fps) => fps,
                    None => probe_frame_rate(&source)?,
                };
                let rate = FrameRate { start, fps };
                rate.validate()?;
                (VideoTiming::Rate(rate), start, start)
            }
            SourceKind::Live | SourceKind::Network => {
                let clock = CaptureClock::new(command.pipeline_delay_ms)?;
                let origin = clock.origin_wall();
                (VideoTiming::Live(clock), origin, origin)
            }
        };
        let processor = Box::new(front_end.processor()?);
        let reader = VideoReader::start(spec)?;
        match timing {
            VideoTiming::Rate(rate) => {
                tracing::info!(source = %source, fps = rate.fps, "video file opened: frame i stamped start + i / fps")
            }
            VideoTiming::Live(_) => {
                tracing::info!(source = %source, pipeline_delay_ms = command.pipeline_delay_ms, "live video source opened: frames stamped on arrival less the pipeline delay")
            }
        }
        let input = VideoInput {
            source,
            reader,
            processor,
            timing,
            behind: Behind {
                since: Instant::now(),
                dropped_before: 0,
                worst_lag: 0.0,
            },
            last_stamp: f64::NEG_INFINITY,
        };
        Ok(OpenedInput {
            input: CameraInput::Video(Box::new(input)),
            origin_stamp,
            origin_wall,
        })
    }

    /// True unless the source is a file.
    pub fn is_live(&self) -> bool {
        matches!(self.timing, VideoTiming::Live(_))
    }

    /// The next frame's head points; `None` when the source ended or shutdown was asked for while waiting.
    pub fn next_points(&mut self) -> Result<Option<InputItem>, AgentError> {
        loop {
            let Some(message) = self.reader.next(POLL) else {
                if signalled() {
                    return Ok(None);
                }
                continue;
            };
            let frame = match message {
                VideoMessage::Frame(frame) => frame,
                VideoMessage::End(Ok(how)) => {
                    tracing::info!(source = %self.source, dropped = self.reader.dropped(), "video source ended: {how}");
                    return Ok(None);
                }
                VideoMessage::End(Err(problem)) => return Err(AgentError::Video(problem)),
                VideoMessage::Down => {
                    let now = match self.timing {
                        VideoTiming::Live(clock) => clock.now(),
                        VideoTiming::Rate(_) => f64::NEG_INFINITY,
                    };
                    return Ok(Some(InputItem::SourceDown(now.max(self.last_stamp))));
                }
            };
            let stamp = match self.timing {
                VideoTiming::Rate(rate) => rate.stamp(frame.index as usize),
                VideoTiming::Live(clock) => clock.stamp_at(frame.arrived),
            };
            let name = format!("{} frame {}", self.source, frame.index);
            let index = frame.index as usize;
            let processed = self.processor.process(&frame.image, index, stamp, &name)?;
            self.report(stamp);
            self.last_stamp = stamp;
            if let Some(processed) = processed {
                let size = [frame.image.width(), frame.image.height()];
                return Ok(Some(InputItem::Points(HeadPoints::from_processed(
                    stamp, size, processed,
                ))));
            }
        }
    }

    /// Keeps the worst lag of the interval and, at its end, logs it with the frames dropped in it (if any).
    fn report(&mut self, stamp: f64) {
        let VideoTiming::Live(clock) = self.timing else {
            return;
        };
        let behind = &mut self.behind;
        behind.worst_lag = behind.worst_lag.max(clock.lag(stamp));
        if behind.since.elapsed() < REPORT_INTERVAL {
            return;
        }
        let dropped_total = self.reader.dropped();
        let dropped = dropped_total - behind.dropped_before;
        let lag_ms = (behind.worst_lag * 1e3).round();
        if dropped > 0 {
            tracing::warn!(source = %self.source, dropped, dropped_total, lag_ms, "cannot keep up with the video source: dropped {dropped} frames in {} s", REPORT_INTERVAL.as_secs());
        } else {
            tracing::debug!(source = %self.source, lag_ms, "keeping up with the video source");
        }
        *behind = Behind {
            since: Instant::now(),
            dropped_before: dropped_total,
            worst_lag: 0.0,
        };
    }
}
