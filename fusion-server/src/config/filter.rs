//! `[filter]`: the GM-PHD filter's motion model, birth, survival and mixture reduction.

use gmphd::occlusion::Occlusion;
use gmphd::{ActivityModel, Echoes};
use serde::Deserialize;

use super::{invalid, non_negative, positive, probability, ConfigError};

/// `filter.motion`: how an object's state evolves between two sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionKind {
    /// 3-D constant velocity, state [x y z vx vy vz], driven by white-noise acceleration
    /// (`filter.accel_noise_std`).
    ConstantVelocity,
    /// 3-D random walk, state [x y z], diffusing at `filter.position_noise_std`.
    RandomWalk,
}

/// `filter.birth`: where new objects are expected to appear.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BirthKind {
    /// Components on a `filter.birth_grid` over the site volume.
    Grid,
    /// Components at `filter.birth_means`.
    Mixture,
}

/// Default `filter.adaptive_birth_rate`: ν_b per LIDAR set (10 Hz in the room), tuned on the
/// room replay (`tests/replay_room.rs`).
const ADAPTIVE_BIRTH_RATE: f64 = 0.05;
/// Default `filter.adaptive_birth_velocity_std`, m/s: walking pace.
const ADAPTIVE_BIRTH_VELOCITY_STD: f64 = 1.0;

/// Default `filter.birth_interval_s`: 50 additions per second, as many as sets arrive from one
/// fast camera. In the room replay (`tests/replay_room.rs`, 7 sensors) 0.02 s gives the same
/// OSPA and count as births at every set, while 0.05–0.2 s cost 1–2 % of right counts: each
/// addition then carries more mass, and its children near tracked people weigh more.
const BIRTH_INTERVAL_S: f64 = 0.02;

/// Default `filter.tdoa_side_peak_offset_s`: where the agents' GCC side peaks sit on two-talker
/// rooms synthesized outside the project (`tools/speech_scene/`), 4–4.5 samples at 16 kHz to
/// either side of the direct path: the reflection off a wall 5 cm behind the pair.
const TDOA_SIDE_PEAK_OFFSET_S: f64 = 2.7e-4;
/// Default `filter.tdoa_side_peak_rate`: on the same rooms the agents send 1.2 side peaks a
/// frame while someone talks, and find a talking talker's direct path 62 % of the time, which
/// puts ρ between about 0.5 and 1; 0.5 gave 75 % right counts there, 0.25 70 % and 1 75 %.
const TDOA_SIDE_PEAK_RATE: f64 = 0.5;

/// `[filter]`: motion model, birth, survival and mixture reduction.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FilterConfig {
    /// `constant_velocity` (3-D, state [x y z vx vy vz]) or `random_walk` (3-D, state [x y z]).
    pub motion: MotionKind,
    /// Continuous white-noise acceleration, m/s² (constant velocity).
    pub accel_noise_std: f64,
    /// Random-walk diffusion, m/√s (random walk).
    pub position_noise_std: f64,
    /// Probability that an object survives one second (p_S over Δt is this to the power Δt).
    pub survival_probability: f64,
    /// Objects whose predicted position lies farther than this (metres) outside the site
    /// volume do not survive. Without such a limit a component that drifts out of every
    /// sensor's view keeps its weight for ever (p_D = 0 there) and becomes a false track or
    /// spoils a real one (`gmphd::SurvivalRegion`). Set it large to track outside the volume.
    pub survival_margin_m: f64,
    /// `grid` (components over the site volume) or `mixture` (`birth_means`).
    pub birth: BirthKind,
    /// Expected number of new objects per second over the whole volume. Default 0.2; a room tracked by
    /// microphone pairs alone does better with 0.05, as each birth component there is a candidate ghost
    /// where two talkers' hyperbolas cross (README: from raw signals).
    pub birth_rate: f64,
    /// Grid size along x, y, z (grid birth).
    pub birth_grid: [usize; 3],
    /// Means of the birth components (mixture birth), metres.
    pub birth_means: Vec<[f64; 3]>,
    /// Standard deviation of a birth component's position, metres.
    pub birth_position_std: f64,
    /// Standard deviation of a birth component's velocity, m/s.
    pub birth_velocity_std: f64,
    /// Least time between two additions of `birth`'s components, seconds: they are added for
    /// all the time owed at once, so the birth rate is unchanged while sets arriving every
    /// few milliseconds do not each carry (and prune) a full grid of births. 0: every set.
    pub birth_interval_s: f64,
    /// Measurement-driven birth (Ristic et al. 2012) in addition to `birth`: each measurement
    /// of a sensor that can be inverted to a world point (LIDAR, position, bearing–range) and
    /// that the tracks do not explain becomes a birth of the next prediction, anywhere.
    pub adaptive_birth: bool,
    /// Expected new objects per measurement set of an invertible sensor, shared among its
    /// measurements by how poorly the tracks explain them.
    pub adaptive_birth_rate: f64,
    /// Standard deviation of an adaptive birth's velocity, m/s.
    pub adaptive_birth_velocity_std: f64,
    /// Prune components below this weight (Vo & Ma's T).
    pub prune_threshold: f64,
    /// Merge components within this Mahalanobis distance (Vo & Ma's U).
    pub merge_threshold: f64,
    /// Keep at most this many components (Vo & Ma's J_max).
    pub max_components: usize,
    /// A component (label) with weight above this is an estimate.
    pub extraction_threshold: f64,
    /// Model talkers' pauses (`gmphd::activity`): a microphone pair's set without a talker is
    /// weak evidence against the talker while the talker may be silent, and a silent talker's
    /// component is not merged into a talking one's. No effect without microphone pairs.
    pub speech_activity: bool,
    /// Mean talk spurt, seconds (ITU-T P.59: 1.004).
    pub mean_talk_s: f64,
    /// Mean pause between talk spurts, seconds (ITU-T P.59: 1.587).
    pub mean_pause_s: f64,
    /// Where a microphone pair's side peaks lie from a talker's direct-path TDOA, seconds
    /// (`gmphd::echoes`): a TDOA this far to either side of a track's is also taken as the
    /// track's detection, not as another talker or clutter. 0 turns the model off. No effect
    /// without microphone pairs.
    pub tdoa_side_peak_offset_s: f64,
    /// Expected side peaks on each side per detected direct path (`gmphd::echoes`).
    pub tdoa_side_peak_rate: f64,
    /// Each label's first object is updated as a Bernoulli (`gmphd::existence`, as in the
    /// labelled multi-Bernoulli filter) rather than the PHD's: a track the filter was sure of
    /// outlasts a run of misses, and a detected label keeps no missed-detection weight on top.
    pub label_existence: bool,
    /// Half-width in metres of what blocks a camera's or a LIDAR's view: a person within
    /// twice this of the line of sight to another, and nearer, hides the other, whose p_D
    /// for that sensor is lowered accordingly (`gmphd::occlusion`), so that a spell behind
    /// someone does not cost the hidden person's track. 0 turns it off. Default 0.25 (about
    /// half a person's shoulder width).
    pub occlusion_radius_m: f64,
}

impl Default for FilterConfig {
    fn default() -> Self {
        Self {
            motion: MotionKind::ConstantVelocity,
            accel_noise_std: 1.0,
            position_noise_std: 0.5,
            survival_probability: 0.99,
            survival_margin_m: 0.25,
            birth: BirthKind::Grid,
            birth_rate: 0.2,
            birth_grid: [4, 3, 1],
            birth_means: Vec::new(),
            birth_position_std: 0.6,
            birth_velocity_std: 0.5,
            birth_interval_s: BIRTH_INTERVAL_S,
            adaptive_birth: true,
            adaptive_birth_rate: ADAPTIVE_BIRTH_RATE,
            adaptive_birth_velocity_std: ADAPTIVE_BIRTH_VELOCITY_STD,
            prune_threshold: 1e-5,
            merge_threshold: 4.0,
            max_components: 100,
            extraction_threshold: 0.5,
            speech_activity: false,
            mean_talk_s: ActivityModel::default().mean_active_s,
            mean_pause_s: ActivityModel::default().mean_inactive_s,
            tdoa_side_peak_offset_s: TDOA_SIDE_PEAK_OFFSET_S,
            tdoa_side_peak_rate: TDOA_SIDE_PEAK_RATE,
            label_existence: true,
            occlusion_radius_m: 0.25,
        }
    }
}

impl FilterConfig {
    /// Checks every value; the error names the first offending key.
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        positive("filter.accel_noise_std", self.accel_noise_std)?;
        positive("filter.position_noise_std", self.position_noise_std)?;
        probability("filter.survival_probability", self.survival_probability)?;
        non_negative("filter.survival_margin_m", self.survival_margin_m)?;
        match self.birth {
            BirthKind::Grid if self.birth_grid.contains(&0) => {
                return Err(invalid(
                    "filter.birth_grid",
                    "every count must be at least 1",
                ));
            }
            BirthKind::Mixture if self.birth_means.is_empty() => {
                return Err(invalid(
                    "filter.birth_means",
                    "mixture birth needs at least one mean",
                ));
            }
            BirthKind::Mixture if self.birth_means.iter().flatten().any(|v| !v.is_finite()) => {
                return Err(invalid(
                    "filter.birth_means",
                    "contains a non-finite number",
                ));
            }
            BirthKind::Grid | BirthKind::Mixture => {}
        }
        positive("filter.birth_rate", self.birth_rate)?;
        positive("filter.birth_position_std", self.birth_position_std)?;
        positive("filter.birth_velocity_std", self.birth_velocity_std)?;
        non_negative("filter.birth_interval_s", self.birth_interval_s)?;
        positive("filter.adaptive_birth_rate", self.adaptive_birth_rate)?;
        positive(
            "filter.adaptive_birth_velocity_std",
            self.adaptive_birth_velocity_std,
        )?;
        positive("filter.prune_threshold", self.prune_threshold)?;
        positive("filter.merge_threshold", self.merge_threshold)?;
        if self.max_components == 0 {
            return Err(invalid("filter.max_components", "must be at least 1"));
        }
        positive("filter.mean_talk_s", self.mean_talk_s)?;
        positive("filter.mean_pause_s", self.mean_pause_s)?;
        non_negative(
            "filter.tdoa_side_peak_offset_s",
            self.tdoa_side_peak_offset_s,
        )?;
        positive("filter.tdoa_side_peak_rate", self.tdoa_side_peak_rate)?;
        non_negative("filter.occlusion_radius_m", self.occlusion_radius_m)?;
        positive("filter.extraction_threshold", self.extraction_threshold)
    }

    /// The occlusion model, when `occlusion_radius_m` is positive.
    pub fn occlusion(&self) -> Option<Result<Occlusion, gmphd::FilterError>> {
        (self.occlusion_radius_m > 0.0).then(|| Occlusion::new(self.occlusion_radius_m))
    }

    /// The microphone pairs' side peaks, when `tdoa_side_peak_offset_s` is positive.
    pub fn echoes(&self) -> Option<Echoes> {
        (self.tdoa_side_peak_offset_s > 0.0).then_some(Echoes {
            offset: self.tdoa_side_peak_offset_s,
            rate: self.tdoa_side_peak_rate,
        })
    }

    /// The talkers' activity chain, when `speech_activity` is on.
    pub fn activity_model(&self) -> Option<ActivityModel> {
        self.speech_activity.then_some(ActivityModel {
            mean_active_s: self.mean_talk_s,
            mean_inactive_s: self.mean_pause_s,
        })
    }
}
