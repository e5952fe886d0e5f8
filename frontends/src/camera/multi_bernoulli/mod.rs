//! People tracked directly on the background-subtracted image by a multi-Bernoulli filter, after
//! R. Hoseinnezhad, B.-N. Vo and T. N. Vu, "Visual tracking of multiple targets by multi-Bernoulli
//! filtering of background subtracted image data" (ICSI 2011): no blobs and no detection step.
//!
//! - `tracker.rs`: frame → shrunk rgI → kernel-density background likelihood per pixel (the paper's grey
//!   image, sec. 3.1) → the filter; the background learns where neither foreground nor a person is.
//! - `foreground.rs`: the grey image as foreground values and their row sums.
//! - `filter.rs`: the recursion (sec. 4): prediction, update, resampling, pruning, merging, estimates,
//!   births; `bernoulli.rs`: one component and its particles (eqs. 21–24).
//! - `likelihood.rs`: the separable likelihood (eq. 20) of a person's region; `cover.rs`: a pixel that
//!   another person already explains counts for neither, so people overlapping in the view are tracked
//!   through the overlap and a hidden head is not a miss.
//! - `region.rs`: the person model (head ellipsoid over a tapering body) projected through the camera
//!   at the person's floor position and height; `geometry.rs`: the camera's projection; `outline.rs`:
//!   the rows of a projected ellipsoid's outline.
//! - `birth.rs`: newborns from foreground the estimates leave unexplained.
//! - `estimate.rs`: the published head top, its covariance and its visibility.
//!
//! The state is the person's floor position, velocity and height in the world frame, not a rectangle on
//! the image as in the paper: the calibrated camera then fixes the region's size and shape from the
//! position, so two people merging in the view keep their own sizes and a person split by clothes of
//! the background's colour stays one.

mod bernoulli;
mod birth;
mod config;
mod cover;
mod estimate;
mod filter;
mod foreground;
mod geometry;
mod likelihood;
mod outline;
mod region;
mod tracker;

pub use bernoulli::{Bernoulli, Motion, PersonState};
pub use config::{MultiBernoulliConfig, PersonShape};
pub use cover::Cover;
pub use estimate::PersonEstimate;
pub use filter::MultiBernoulliFilter;
pub use foreground::ForegroundMap;
pub use geometry::CameraGeometry;
pub use likelihood::Likelihood;
pub use region::{PersonProjector, Region, RowSpan};
pub use tracker::{FrameEstimates, ImageTracker};
