//! `edge-agent camera`: frames (background subtraction → blobs → head points) or MOT detections, then the
//! single-view tracker, one measurement set per frame.

use std::path::Path;

use frontends::camera::{
    read_mot_detections, CameraConfig, CameraPipeline, FrameDirectory, FrameRate, FrameTiming,
};
use protocol::{CameraModel, SensorKind, SensorModel};

use crate::camera_tracker::{SingleViewSettings, SingleViewTracker};
use crate::cli::CameraCommand;
use crate::descriptor::load_descriptor;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::launch::Prepared;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};
use crate::settings::read_frontend_config;
use crate::sim::prepare_simulated_sensor;

/// Prepares `edge-agent camera`.
pub fn prepare_camera(command: &CameraCommand) -> Result<Prepared, AgentError> {
    if command.simulate.simulate {
        if command.frames.is_some() || command.detections.is_some() || command.descriptor.is_some()
        {
            return Err(AgentError::Usage(
                "--simulate takes the camera from --scenario: do not give --frames, --detections or --descriptor".into(),
            ));
        }
        return prepare_simulated_sensor(
            &command.simulate,
            command.common.site.as_ref(),
            &command.timing,
            SensorKind::Camera,
        );
    }
    let descriptor_path = command.descriptor.as_deref().ok_or_else(|| {
        AgentError::Usage("camera needs --descriptor FILE (or --simulate)".into())
    })?;
    let descriptor = load_descriptor(
        descriptor_path,
        command.common.site.as_ref(),
        SensorKind::Camera,
    )?;
    let SensorModel::Camera(camera) = &descriptor.model else {
        return Err(AgentError::Usage("the descriptor is not a camera".into()));
    };
    let config = frontend_config(command.frontend_config.as_deref())?;
    let tracker = if command.raw {
        None
    } else {
        Some(SingleViewTracker::new(
            camera,
            descriptor.detection_probability,
            descriptor.clutter_rate,
            SingleViewSettings {
                accel_noise: command.accel_noise,
                birth_rate: command.birth_rate,
                extraction_threshold: command.extraction_threshold,
            },
        )?)
    };
    let start = command.timing.start.unwrap_or_else(wall_clock);
    let (input, origin_stamp, origin_wall) = open_input(command, &config, start)?;
    let source = CameraSource {
        input,
        tracker,
        camera: camera.clone(),
        size_checked: false,
    };
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        origin_stamp,
        origin_wall,
    ))
}

/// The camera front end's configuration: the TOML file, or its documented defaults.
fn frontend_config(path: Option<&Path>) -> Result<CameraConfig, AgentError> {
    let Some(path) = path else {
        return Ok(CameraConfig::default());
    };
    let config: CameraConfig = read_frontend_config(path)?;
    config.validate()?;
    Ok(config)
}

/// Where the head points come from, and the pacing origin (stamp, wall time) of the run.
fn open_input(
    command: &CameraCommand,
    config: &CameraConfig,
    start: f64,
) -> Result<(CameraInput, f64, f64), AgentError> {
    match (&command.frames, &command.detections) {
        (Some(dir), None) => {
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
            let pipeline = Box::new(CameraPipeline::new(config.clone())?);
            let input = CameraInput::Frames {
                frames,
                pipeline,
                next: 0,
                offset,
            };
            Ok((input, first + offset, origin_wall))
        }
        (None, Some(path)) => {
            let fps = command
                .fps
                .ok_or_else(|| AgentError::Usage("--detections needs --fps".into()))?;
            if command.stamps.is_some() {
                return Err(AgentError::Usage(
                    "--stamps goes with --frames; use --fps with --detections".into(),
                ));
            }
            let frames = read_mot_detections(path, &config.mot_det, &FrameRate { start, fps })?;
            let input = CameraInput::Detections {
                frames: frames
                    .into_iter()
                    .map(|f| (f.stamp, f.points))
                    .collect::<Vec<_>>()
                    .into_iter(),
            };
            Ok((input, start, start))
        }
        _ => Err(AgentError::Usage(
            "camera needs one input: --frames DIR, --detections det.txt or --simulate".into(),
        )),
    }
}

/// One frame's head points.
struct HeadPoints {
    /// Capture time of the frame.
    stamp: f64,
    /// Width and height of a decoded image (none for detections).
    frame_size: Option<[u32; 2]>,
    /// `[u, v]` per detected head, pixels.
    points: Vec<[f64; 2]>,
}

/// The camera's frames of head points, decoded one at a time.
enum CameraInput {
    /// Image frames through background subtraction.
    Frames {
        frames: FrameDirectory,
        /// Boxed: it holds the background model's buffers, much larger than the other variant.
        pipeline: Box<CameraPipeline>,
        next: usize,
        /// Added to every stamp (see `--stamps` with `--start`).
        offset: f64,
    },
    /// Precomputed detections, already grouped by frame.
    Detections {
        frames: std::vec::IntoIter<(f64, Vec<[f64; 2]>)>,
    },
}

impl CameraInput {
    /// The next frame's head points; `None` at the end. Frames that only train the background yield nothing
    /// and are skipped.
    fn next_points(&mut self) -> Result<Option<HeadPoints>, AgentError> {
        match self {
            CameraInput::Frames {
                frames,
                pipeline,
                next,
                offset,
            } => {
                while *next < frames.len() {
                    let frame = frames.load(*next)?;
                    *next += 1;
                    let name = frame.path.display().to_string();
                    let stamp = frame.stamp + *offset;
                    if let Some(detections) =
                        pipeline.process_frame(&frame.image, frame.index, stamp, &name)?
                    {
                        return Ok(Some(HeadPoints {
                            stamp,
                            frame_size: Some([frame.image.width(), frame.image.height()]),
                            points: detections.points,
                        }));
                    }
                }
                Ok(None)
            }
            CameraInput::Detections { frames } => {
                Ok(frames.next().map(|(stamp, points)| HeadPoints {
                    stamp,
                    frame_size: None,
                    points,
                }))
            }
        }
    }
}

/// Head points through the single-view tracker (or raw), as sets of the one camera.
struct CameraSource {
    input: CameraInput,
    tracker: Option<SingleViewTracker>,
    camera: CameraModel,
    size_checked: bool,
}

impl EventSource for CameraSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        let Some(HeadPoints {
            stamp,
            frame_size,
            points,
        }) = self.input.next_points()?
        else {
            return Ok(None);
        };
        if let (Some(size), false) = (frame_size, self.size_checked) {
            self.size_checked = true;
            if size != self.camera.image_size {
                tracing::warn!(
                    frames = ?size,
                    descriptor = ?self.camera.image_size,
                    "frame size differs from the descriptor's image_size: check the calibration"
                );
            }
        }
        let frame = match &mut self.tracker {
            Some(tracker) => {
                let estimates = tracker.step(stamp, &points)?;
                Frame {
                    stamp,
                    measurements: estimates.points,
                    covariances: Some(estimates.covariances),
                }
            }
            None => Frame {
                stamp,
                measurements: points.iter().map(|p| p.to_vec()).collect(),
                covariances: None,
            },
        };
        Ok(Some(Event::Set { stream: 0, frame }))
    }
}
