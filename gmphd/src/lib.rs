//! Gaussian-mixture probability hypothesis density (GM-PHD) filter.
//!
//! Pure math: no I/O, no async. The recursion follows Vo & Ma 2006 and Pham's
//! thesis (ch. 3.5, 4, 5.3): prediction with survival, birth and spawning;
//! update with state-dependent detection probability and uniform clutter,
//! linear (Kalman) or unscented; sequential multi-sensor correction; mixture
//! reduction; labelled state extraction; optional measurement-driven birth
//! (Ristic, Clark, Vo & Vo 2012) next to the static birth intensity.

pub mod activity;
pub mod adaptive_birth;
pub mod assignment;
pub mod birth;
mod continuity;
pub mod echoes;
pub mod error;
pub mod existence;
pub mod extract;
pub mod filter;
pub mod gating;
pub mod gaussian;
pub mod labels;
pub mod linalg;
pub mod measurement;
pub mod metrics;
pub mod motion;
mod newborn;
pub mod occlusion;
pub mod predict;
pub mod reduce;
pub mod reference;
pub mod spawn;
mod sweep;
pub mod tracker;
pub mod tracks;
pub mod ukf;
pub mod update;

pub use activity::ActivityModel;
pub use adaptive_birth::{AdaptiveBirth, AdaptiveBirthConfig, BirthCandidate};
pub use birth::{BirthModel, BirthTiming, GridBirth, GridBirthConfig, MixtureBirth};
pub use echoes::Echoes;
pub use error::FilterError;
pub use filter::{FilterConfig, FilterState, GmPhdFilter};
pub use gating::Gating;
pub use gaussian::{Gaussian, GaussianMixture, Label, LabelSource};
pub use measurement::{
    BearingRange, Detection, HeightPrior, Lidar, Measurement, MeasurementModel, MicPair,
    PinholeCamera, PositionSensor, UpdateHints,
};
pub use motion::{ConstantVelocity, CoordinatedTurn, MotionModel, RandomWalk};
pub use predict::{Survival, SurvivalRegion};
pub use reduce::{PruneMergeCap, Reducer};
pub use spawn::{SpawnComponent, SpawnModel};
pub use tracker::{LabelledTracker, TrackerConfig, TrackerError, TrackerState};
pub use ukf::UnscentedParams;
