//! `edge-agent camera`: frames or a video through the multi-Bernoulli image tracker (head tops with
//! covariances, `camera_frontend.rs`), or through background subtraction → blobs → head points, or
//! detections (`camera_input.rs`), the raw points then through the single-view tracker; one
//! measurement set per frame.

use std::path::Path;

use frontends::camera::{CameraConfig, FrontEndKind};
use protocol::{CameraModel, SensorDescriptor, SensorKind, SensorModel};

use crate::camera_input::{
    open_input, CameraInput, FrontEndChoice, HeadPoints, InputItem, OpenedInput,
};
use crate::camera_tracker::{SingleViewSettings, SingleViewTracker};
use crate::cli::{CameraCommand, FrontEndArg};
use crate::descriptor::load_descriptor;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::front_end_report::FrontEndReport;
use crate::launch::Prepared;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};
use crate::settings::read_frontend_config;
use crate::sim::prepare_simulated_sensor;

/// Prepares `edge-agent camera`.
pub fn prepare_camera(command: &CameraCommand) -> Result<Prepared, AgentError> {
    if command.simulate.simulate {
        return prepare_simulated_camera(command);
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
    let kind = front_end_kind(command, &config)?;
    let image_tracker = kind == FrontEndKind::MultiBernoulli && command.detections.is_none();
    let tracker = if tracker_is_used(command, image_tracker) {
        Some(single_view_tracker(command, camera, &descriptor)?)
    } else {
        None
    };
    let start = command.timing.start.unwrap_or_else(wall_clock);
    let choice = FrontEndChoice {
        kind,
        config: &config,
        camera,
    };
    let OpenedInput {
        input,
        origin_stamp,
        origin_wall,
    } = open_input(command, &choice, start)?;
    if input.is_live() && command.timing.speed != 1.0 {
        return Err(AgentError::Usage(
            "--speed does not apply to a live source: its frames are published as they come".into(),
        ));
    }
    let source = CameraSource {
        input,
        tracker,
        camera: camera.clone(),
        size_checked: false,
        pending_report: None,
    };
    let mut prepared =
        Prepared::single_sensor(Box::new(source), descriptor, origin_stamp, origin_wall);
    // The descriptor's figures are refined from the frames' persistence (`calibration.rs`), which
    // assumes a front end without memory: a false track of the single-view tracker persists like a
    // person, so the estimate would claim no clutter at all (measured on the rendered room: 0.00
    // per frame and p_D 0.96-0.98, worsening the fused OSPA from 0.39-0.42 m to 0.46-0.49 m).
    // The image tracker reports its own account of each set instead (`front_end_report.rs`).
    if tracker_is_used(command, image_tracker) {
        tracing::info!("descriptor refinement off: the single-view tracker's output is filtered over time; the descriptor's figures are used as given");
        prepared.calibrate = false;
    }
    Ok(prepared)
}

/// `edge-agent camera --simulate`: the camera's measurement sets from the scenario.
fn prepare_simulated_camera(command: &CameraCommand) -> Result<Prepared, AgentError> {
    if command.frames.is_some()
        || command.video.is_some()
        || command.detections.is_some()
        || command.descriptor.is_some()
    {
        return Err(AgentError::Usage(
            "--simulate takes the camera from --scenario: do not give --frames, --video, --detections or --descriptor".into(),
        ));
    }
    prepare_simulated_sensor(
        &command.simulate,
        command.common.site.as_ref(),
        &command.timing,
        SensorKind::Camera,
    )
}

/// The single-view point tracker, with the descriptor's figures and the command's settings.
fn single_view_tracker(
    command: &CameraCommand,
    camera: &CameraModel,
    descriptor: &SensorDescriptor,
) -> Result<SingleViewTracker, AgentError> {
    SingleViewTracker::new(
        camera,
        descriptor.detection_probability,
        descriptor.clutter_rate,
        SingleViewSettings {
            accel_noise: command.accel_noise,
            birth_rate: command.birth_rate,
            extraction_threshold: command.extraction_threshold,
        },
    )
}

/// Whether the raw points go through the single-view point tracker.
fn tracker_is_used(command: &CameraCommand, image_tracker: bool) -> bool {
    !command.raw && !image_tracker
}

/// The front end: `--front-end`, else the configuration's; `--raw` asks for the blobs' points.
fn front_end_kind(
    command: &CameraCommand,
    config: &CameraConfig,
) -> Result<FrontEndKind, AgentError> {
    let kind = match command.front_end {
        Some(FrontEndArg::MultiBernoulli) => FrontEndKind::MultiBernoulli,
        Some(FrontEndArg::Blobs) => FrontEndKind::Blobs,
        None if command.raw => FrontEndKind::Blobs,
        None => config.front_end,
    };
    if command.raw && kind == FrontEndKind::MultiBernoulli && command.detections.is_none() {
        return Err(AgentError::Usage(
            "--raw publishes the blobs' head points: use --front-end blobs (the multi-Bernoulli image tracker has no raw points)".into(),
        ));
    }
    Ok(kind)
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

/// Head points through the single-view tracker (or raw), as sets of the one camera.
struct CameraSource {
    input: CameraInput,
    tracker: Option<SingleViewTracker>,
    camera: CameraModel,
    size_checked: bool,
    /// The image tracker's account of the set just returned, returned next.
    pending_report: Option<(f64, FrontEndReport)>,
}

impl EventSource for CameraSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        if let Some((stamp, report)) = self.pending_report.take() {
            return Ok(Some(Event::Report {
                stream: 0,
                stamp,
                report,
            }));
        }
        let HeadPoints {
            stamp,
            frame_size,
            points,
            estimated,
        } = match self.input.next_points()? {
            None => return Ok(None),
            Some(InputItem::SourceDown(stamp)) => {
                return Ok(Some(Event::SourceDown { stream: 0, stamp }))
            }
            Some(InputItem::Points(points)) => points,
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
        if let Some(estimated) = estimated {
            self.pending_report = Some((stamp, estimated.report));
            let frame = Frame {
                stamp,
                measurements: points.iter().map(|p| p.to_vec()).collect(),
                covariances: Some(estimated.covariances),
            };
            return Ok(Some(Event::Set { stream: 0, frame }));
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

    fn is_live(&self) -> bool {
        self.input.is_live()
    }
}
