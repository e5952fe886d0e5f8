//! What the camera agent runs a decoded frame through: the multi-Bernoulli image tracker (the default,
//! `frontends::camera::multi_bernoulli`), whose published head tops come with their covariances and the
//! tracker's own account of them, or background subtraction and blobs, whose raw head points go on to
//! the single-view point tracker (`camera_tracker.rs`).

use frontends::camera::multi_bernoulli::{FrameEstimates, ImageTracker};
use frontends::camera::{CameraConfig, CameraPipeline, FrontEndKind};
use image::RgbImage;
use protocol::CameraModel;

use crate::error::AgentError;
use crate::front_end_report::FrontEndReport;

/// Head points already filtered over time: their covariances and the front end's account of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimated {
    /// One 2 × 2 covariance (rows) per point, px².
    pub covariances: Vec<Vec<Vec<f64>>>,
    /// The front end's account of the set.
    pub report: FrontEndReport,
}

/// One processed frame: head points, and for the image tracker what they are worth.
#[derive(Debug, Clone, PartialEq)]
pub struct ProcessedFrame {
    /// `[u, v]` per head, pixels.
    pub points: Vec<[f64; 2]>,
    /// `None` for raw head points (blobs).
    pub estimated: Option<Estimated>,
}

/// The front end a camera's frames go through.
pub enum FrameProcessor {
    /// Background subtraction, blobs, head points (boxed: large buffers).
    Blobs(Box<CameraPipeline>),
    /// The multi-Bernoulli filter on the background-subtracted image.
    MultiBernoulli(Box<ImageTracker>),
}

impl FrameProcessor {
    /// The front end `kind` with `config`, for the camera `camera`.
    pub fn new(
        kind: FrontEndKind,
        config: &CameraConfig,
        camera: &CameraModel,
    ) -> Result<Self, AgentError> {
        Ok(match kind {
            FrontEndKind::Blobs => Self::Blobs(Box::new(CameraPipeline::new(config.clone())?)),
            FrontEndKind::MultiBernoulli => Self::MultiBernoulli(Box::new(ImageTracker::new(
                config.multi_bernoulli.clone(),
                config.background.clone(),
                camera.projection,
                camera.image_size,
            )?)),
        })
    }

    /// Processes one frame; `None` while the background is still learning.
    pub fn process(
        &mut self,
        image: &RgbImage,
        index: usize,
        stamp: f64,
        name: &str,
    ) -> Result<Option<ProcessedFrame>, AgentError> {
        match self {
            Self::Blobs(pipeline) => {
                Ok(pipeline
                    .process_frame(image, index, stamp, name)?
                    .map(|d| ProcessedFrame {
                        points: d.points,
                        estimated: None,
                    }))
            }
            Self::MultiBernoulli(tracker) => {
                let Some(estimates) = tracker.process_frame(image, stamp, name)? else {
                    return Ok(None);
                };
                Ok(Some(published(tracker, &estimates)))
            }
        }
    }
}

/// The estimates the image tracker publishes: confirmed, head top in the image and enough of the head
/// seen (a head hidden behind a nearer person is not measured, and the report says so).
fn published(tracker: &ImageTracker, frame: &FrameEstimates) -> ProcessedFrame {
    let config = tracker.config();
    let [width, height] = tracker.filter().projector().geometry().size();
    let mut out = ProcessedFrame {
        points: Vec::new(),
        estimated: Some(Estimated {
            covariances: Vec::new(),
            report: FrontEndReport::default(),
        }),
    };
    let estimated = out.estimated.as_mut().expect("set above");
    for person in &frame.people {
        let [u, v] = person.head;
        let in_image = (0.0..width).contains(&u) && (0.0..height).contains(&v);
        if person.reported_frames < config.confirm_frames || !in_image {
            continue;
        }
        estimated.report.objects_in_view += person.existence;
        if person.visible_head < config.min_visible_head {
            continue;
        }
        estimated.report.objects_measured += person.existence;
        estimated.report.expected_false += 1.0 - person.existence;
        out.points.push(person.head);
        estimated
            .covariances
            .push(person.covariance.iter().map(|row| row.to_vec()).collect());
    }
    out
}
