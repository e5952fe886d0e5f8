//! Camera front end: image frames to per-frame image-plane point measurements.
//!
//! Three sources of measurements:
//! - Background subtraction (`CameraPipeline`): each frame is converted to rgI chromaticity, compared
//!   with a per-pixel background model (kernel density over recent background samples as in
//!   Hoseinnezhad, Vo and Vu, or running mean/variance), the foreground mask is opened and closed,
//!   its connected components are joined into bodies (pieces stacked within a body's width), and
//!   each body gives its head points (the peaks of its top outline, one per person it holds), the
//!   measurement of Pham's single-view stage (thesis ch. 7), or its centroid or feet.
//! - Precomputed detections (`read_mot_detections`): a MOT Challenge `det.txt`, one point per box.
//! - The multi-Bernoulli image tracker (`multi_bernoulli`, Hoseinnezhad, Vo and Vu): people tracked
//!   directly on the background-subtracted image, no blobs; it yields head tops with covariances.
//!
//! The first two yield `Vec<FrameDetections>`, one point set per frame, ready for a 2-D GM-PHD update
//! (`FrameDetections::measurement_vectors`).

#![warn(missing_docs)]

mod background;
mod blobs;
mod bodies;
mod chromaticity;
mod config;
mod detections;
mod error;
mod frames;
mod kde_background;
mod morphology;
mod mot_det;
pub mod multi_bernoulli;
mod pipeline;
mod running_background;
mod shadows;
mod top_profile;

pub use background::{new_background_model, BackgroundModel, FOREGROUND};
pub use blobs::{Blob, BlobDetector};
pub use chromaticity::{rgb_to_rgi, Rgi, RgiImage, RGI_SCALE};
pub use config::{
    BackgroundConfig, BackgroundModelKind, BlobConfig, CameraConfig, FrontEndKind, KdeConfig,
    MotDetConfig, RunningStatsConfig, ShadowConfig,
};
pub use detections::{FrameDetections, PointAnchor};
pub use error::{CameraError, CameraResult};
pub use frames::{read_stamps_file, Frame, FrameDirectory, FrameRate, FrameTiming};
pub use kde_background::KdeBackground;
pub use morphology::clean_mask;
pub use mot_det::{
    group_by_frame, parse_mot_line, parse_mot_text, read_mot_detections, MotDetection, MAX_FRAME,
};
pub use pipeline::CameraPipeline;
pub use running_background::RunningStatsBackground;
pub use shadows::suppress_shadows;
