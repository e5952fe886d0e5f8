//! Where a camera's head points come from: a frame directory, a video source, a `det.txt` file, or
//! detections on stdin; each yields one frame of head points at a time, with the pacing origin of the run.

use std::path::Path;

use frontends::camera::{
    read_mot_detections, CameraConfig, FrameDirectory, FrameRate, FrameTiming, FrontEndKind,
};
use protocol::CameraModel;

use crate::camera_frontend::{Estimated, FrameProcessor, ProcessedFrame};
use crate::capture_clock::CaptureClock;
use crate::cli::CameraCommand;
use crate::error::AgentError;
use crate::live_detections::LiveDetections;
use crate::pacing::wall_clock;
use crate::video_input::VideoInput;
use transport::shutdown::signalled;

/// One frame's head points.
pub struct HeadPoints {
    /// Capture time of the frame.
    pub stamp: f64,
    /// Width and height of a decoded image (none for detections).
    pub frame_size: Option<[u32; 2]>,
    /// `[u, v]` per detected head, pixels.
    pub points: Vec<[f64; 2]>,
    /// For points the front end already filtered over time (the image tracker): their covariances and
    /// its account of them; `None` for raw points.
    pub estimated: Option<Estimated>,
}

impl HeadPoints {
    /// A processed frame's points, stamped, from an image of `frame_size`.
    pub fn from_processed(stamp: f64, frame_size: [u32; 2], processed: ProcessedFrame) -> Self {
        Self {
            stamp,
            frame_size: Some(frame_size),
            points: processed.points,
            estimated: processed.estimated,
        }
    }
}

/// Which front end decoded frames go through, and for which camera.
pub struct FrontEndChoice<'a> {
    /// The front end.
    pub kind: FrontEndKind,
    /// Its configuration.
    pub config: &'a CameraConfig,
    /// The camera (the image tracker projects people through it).
    pub camera: &'a CameraModel,
}

impl FrontEndChoice<'_> {
    /// The frame processor.
    pub fn processor(&self) -> Result<FrameProcessor, AgentError> {
        FrameProcessor::new(self.kind, self.config, self.camera)
    }
}

/// What an input yields next.
pub enum InputItem {
    /// A frame's head points.
    Points(HeadPoints),
    /// The live source is down (being re-opened), since this stamp.
    SourceDown(f64),
}

/// An opened input and the pacing origin (stamp, wall time) of its run.
pub struct OpenedInput {
    /// The input.
    pub input: CameraInput,
    /// The stamp of the run's time 0.
    pub origin_stamp: f64,
    /// The wall time at which `origin_stamp` is due.
    pub origin_wall: f64,
}

/// The camera's frames of head points, decoded one at a time.
pub enum CameraInput {
    /// Image frames through background subtraction.
    Frames {
        /// The directory.
        frames: FrameDirectory,
        /// Boxed: it holds the background model's buffers, much larger than the other variants.
        processor: Box<FrameProcessor>,
        /// Index of the next frame to load.
        next: usize,
        /// Added to every stamp (see `--stamps` with `--start`).
        offset: f64,
    },
    /// Frames decoded by ffmpeg, through background subtraction.
    Video(Box<VideoInput>),
    /// Precomputed detections, already grouped by frame.
    Detections {
        /// The frames, stamped.
        frames: std::vec::IntoIter<(f64, Vec<[f64; 2]>)>,
    },
    /// Detections read live from stdin.
    LiveDetections(Box<LiveDetections>),
}

/// Opens the one input the flags name.
pub fn open_input(
    command: &CameraCommand,
    front_end: &FrontEndChoice,
    start: f64,
) -> Result<OpenedInput, AgentError> {
    let config = front_end.config;
    match (&command.frames, &command.video, &command.detections) {
        (Some(dir), None, None) => open_frames(command, dir, front_end, start),
        (None, Some(_), None) => VideoInput::open(command, front_end, start),
        (None, None, Some(path)) if path.as_os_str() == "-" => {
            if command.fps.is_some() || command.stamps.is_some() {
                return Err(AgentError::Usage(
                    "--detections - is stamped on arrival or by its JSON lines: drop --fps/--stamps"
                        .into(),
                ));
            }
            let clock = CaptureClock::new(command.pipeline_delay_ms)?;
            let live = LiveDetections::start(std::io::stdin(), config.mot_det.clone(), clock)?;
            Ok(OpenedInput {
                input: CameraInput::LiveDetections(Box::new(live)),
                origin_stamp: clock.origin_wall(),
                origin_wall: clock.origin_wall(),
            })
        }
        (None, None, Some(path)) => open_detections_file(command, path, config, start),
        _ => Err(AgentError::Usage(
            "camera needs one input: --frames DIR, --video SRC, --detections det.txt|- or --simulate"
                .into(),
        )),
    }
}

/// `--frames DIR` with `--fps` or `--stamps`.
fn open_frames(
    command: &CameraCommand,
    dir: &Path,
    front_end: &FrontEndChoice,
    start: f64,
) -> Result<OpenedInput, AgentError> {
    let (timing, shift) = match (&command.stamps, command.fps) {
        (Some(stamps), None) => (FrameTiming::StampsFile(stamps.clone()), true),
        (None, Some(fps)) => (FrameTiming::Rate(FrameRate { start, fps }), false),
        _ => {
            return Err(AgentError::Usage(
                "--frames needs exactly one of --fps or --stamps".into(),
            ))
        }
    };
    let frames = FrameDirectory::open(dir, &timing)?;
    let first = frames.stamps()[0];
    // Recorded stamps keep their values unless --start moves the first one there; either way they are
    // replayed at their own spacing from launch.
    let offset = match (shift, command.timing.start) {
        (true, Some(start)) => start - first,
        _ => 0.0,
    };
    let origin_wall = if shift && command.timing.start.is_none() {
        wall_clock()
    } else {
        first + offset
    };
    let processor = Box::new(front_end.processor()?);
    Ok(OpenedInput {
        input: CameraInput::Frames {
            frames,
            processor,
            next: 0,
            offset,
        },
        origin_stamp: first + offset,
        origin_wall,
    })
}

/// `--detections det.txt` with `--fps`.
fn open_detections_file(
    command: &CameraCommand,
    path: &Path,
    config: &CameraConfig,
    start: f64,
) -> Result<OpenedInput, AgentError> {
    let fps = command
        .fps
        .ok_or_else(|| AgentError::Usage("--detections needs --fps".into()))?;
    if command.stamps.is_some() {
        return Err(AgentError::Usage(
            "--stamps goes with --frames; use --fps with --detections".into(),
        ));
    }
    let frames = read_mot_detections(path, &config.mot_det, &FrameRate { start, fps })?;
    let frames = frames
        .into_iter()
        .map(|f| (f.stamp, f.points))
        .collect::<Vec<_>>()
        .into_iter();
    Ok(OpenedInput {
        input: CameraInput::Detections { frames },
        origin_stamp: start,
        origin_wall: start,
    })
}

impl CameraInput {
    /// The next frame's head points; `None` at the end. Frames that only train the background yield nothing
    /// and are skipped.
    pub fn next_points(&mut self) -> Result<Option<InputItem>, AgentError> {
        let points = match self {
            CameraInput::Video(video) => return video.next_points(),
            _ => self.next_recorded()?,
        };
        Ok(points.map(InputItem::Points))
    }

    /// The next frame of the inputs that are never down.
    fn next_recorded(&mut self) -> Result<Option<HeadPoints>, AgentError> {
        match self {
            CameraInput::Frames {
                frames,
                processor,
                next,
                offset,
            } => {
                while *next < frames.len() {
                    let frame = frames.load(*next)?;
                    *next += 1;
                    let name = frame.path.display().to_string();
                    let stamp = frame.stamp + *offset;
                    if let Some(processed) =
                        processor.process(&frame.image, frame.index, stamp, &name)?
                    {
                        let size = [frame.image.width(), frame.image.height()];
                        return Ok(Some(HeadPoints::from_processed(stamp, size, processed)));
                    }
                }
                Ok(None)
            }
            CameraInput::Video(_) => Ok(None),
            CameraInput::Detections { frames } => {
                Ok(frames.next().map(|(stamp, points)| HeadPoints {
                    stamp,
                    frame_size: None,
                    points,
                    estimated: None,
                }))
            }
            CameraInput::LiveDetections(live) => {
                Ok(live
                    .next_frame(signalled)?
                    .map(|(stamp, points)| HeadPoints {
                        stamp,
                        frame_size: None,
                        points,
                        estimated: None,
                    }))
            }
        }
    }

    /// True for inputs stamped on arrival.
    pub fn is_live(&self) -> bool {
        match self {
            CameraInput::Video(video) => video.is_live(),
            CameraInput::LiveDetections(_) => true,
            CameraInput::Frames { .. } | CameraInput::Detections { .. } => false,
        }
    }
}
