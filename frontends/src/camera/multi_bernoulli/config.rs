//! Settings of the multi-Bernoulli image tracker, with documented defaults.
//!
//! In a camera front-end TOML file they are the `[multi_bernoulli]` table (and its `person`
//! sub-table); every field has a default.

use serde::Deserialize;

use crate::camera::config::{invalid, require_positive};
use crate::camera::error::CameraResult;

/// The shape of a standing person, in metres: what a hypothesised person covers in the image.
/// Proportions are of the person's height (anthropometric averages), breadths are absolute.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PersonShape {
    /// Smallest height (head top above the floor) a person may have; default 1.45.
    pub min_height: f64,
    /// Largest height; default 2.0.
    pub max_height: f64,
    /// Half the head's breadth; default 0.08.
    pub head_half_width: f64,
    /// The head's height (top to chin) as a share of the person's height; default 0.13 (about one
    /// seventh and a half).
    pub head_share: f64,
    /// Half the breadth at the shoulders (arms included); default 0.2.
    pub shoulder_half_width: f64,
    /// Height of the shoulders as a share of the person's height; default 0.82.
    pub shoulder_share: f64,
    /// Half the breadth at the hips; default 0.17.
    pub hip_half_width: f64,
    /// Height of the hips as a share of the person's height; default 0.53.
    pub hip_share: f64,
    /// Half the breadth at the feet; default 0.12.
    pub foot_half_width: f64,
    /// Half the breadth of the neck; default 0.06.
    pub neck_half_width: f64,
}

impl Default for PersonShape {
    fn default() -> Self {
        Self {
            min_height: 1.45,
            max_height: 2.0,
            head_half_width: 0.08,
            head_share: 0.13,
            shoulder_half_width: 0.2,
            shoulder_share: 0.82,
            hip_half_width: 0.17,
            hip_share: 0.53,
            foot_half_width: 0.12,
            neck_half_width: 0.06,
        }
    }
}

/// The multi-Bernoulli filter on the background-subtracted image (Hoseinnezhad, Vo & Vu).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MultiBernoulliConfig {
    /// The frame is binned in blocks of this many pixels a side (the rgI of each block's summed light)
    /// before background subtraction and the likelihood; 1..=8, default 2 (320 × 240 for a 640 × 480
    /// camera).
    pub downscale: u32,
    /// Height of the floor in the world frame, m; default 0.
    pub floor_z: f64,
    /// The person model.
    pub person: PersonShape,
    /// A pixel whose background likelihood `y` (eq. 10) reaches this counts as wholly background; below
    /// it the pixel's foreground value is `1 − y / foreground_saturation`; in (0, 1], default 0.1.
    pub foreground_saturation: f32,
    /// A pixel inside a hypothesised person counts for it when its foreground value exceeds this, against
    /// it below; in (0, 1), default 0.5.
    pub foreground_threshold: f32,
    /// Pixels (of the binned image) that count as one independent observation in the likelihood: the
    /// log-likelihood of a person is the sum of `foreground value − threshold` over the pixels it explains,
    /// divided by this (neighbouring pixels of the foreground are strongly correlated: its texture and
    /// noise span a few binned pixels); > 0, default 12. Smaller makes the particles surer of their fit
    /// than the person model deserves (on the rendered room, 4 gave more doubled tracks in the fusion).
    pub pixels_per_observation: f32,
    /// How much more a pixel of the head counts in the likelihood than a pixel of the body; default 3.
    pub head_weight: f32,
    /// Probability that a person is still there one second later; in (0, 1], default 0.9.
    pub survival_per_second: f64,
    /// White-noise acceleration of a person on the floor, m/s²; default 3.
    pub accel_noise: f64,
    /// Random walk of a person's height, m per √s; default 0.03.
    pub height_noise: f64,
    /// Existence probability of a newborn person; in (0, 1), default 0.1.
    pub birth_existence: f64,
    /// Spread of a newborn's velocity, m/s; default 0.5.
    pub birth_velocity_std: f64,
    /// Particles of a newborn; default 600.
    pub birth_particles: usize,
    /// Fewest particles per person; default 150.
    pub min_particles: usize,
    /// Most particles per person (taken at existence 1); default 400.
    pub max_particles: usize,
    /// A person whose existence falls below this is dropped; default 0.01.
    pub prune_existence: f64,
    /// A person whose existence is at least this is an estimate; default 0.5.
    pub report_existence: f64,
    /// Frames in a row an estimate must last, mostly in sight, before it is published; default 3.
    pub confirm_frames: u32,
    /// A newborn not confirmed within this many frames of its birth is dropped; default 12.
    pub confirm_within_frames: u32,
    /// Two estimates whose floor positions are closer than this are one person, m; default 0.25.
    pub merge_distance: f64,
    /// A foreground region not explained by the estimates seeds a newborn when its area is at least
    /// this share of the head and shoulders of a person whose head top is at the region's top; default
    /// 0.5.
    pub birth_min_share: f64,
    /// An estimate is published only when at least this share of its head is in the image and not
    /// behind a nearer person; default 0.5.
    pub min_visible_head: f64,
    /// The person model's own error at the head top, m: its variance, seen at the person's distance,
    /// is added to the particles' spread in each published covariance (the particles show how well
    /// the model fits the image, not how well the model fits the person); default 0.04. Why: a head
    /// point is now and then off by 20 px or more for a second or two (hair or clothes of the
    /// background's colour), and a fusion that expects the typical 3–5 px gates such a point out of
    /// its person's track and starts a doubled one. On the rendered room (cameras only, seeds 1–3) the
    /// right count is 100/100/88.9 % with 0.02, 100/100/92.2 % with 0.03 and 100/100/95.5 % with
    /// 0.04; the published σ is then 12–14 px.
    pub head_model_error: f64,
    /// Seed of the particles' random numbers (a run is a pure function of its frames and this).
    pub seed: u64,
}

impl Default for MultiBernoulliConfig {
    fn default() -> Self {
        Self {
            downscale: 2,
            floor_z: 0.0,
            person: PersonShape::default(),
            foreground_saturation: 0.1,
            foreground_threshold: 0.5,
            pixels_per_observation: 12.0,
            head_weight: 3.0,
            survival_per_second: 0.9,
            accel_noise: 3.0,
            height_noise: 0.03,
            birth_existence: 0.1,
            birth_velocity_std: 0.5,
            birth_particles: 600,
            min_particles: 150,
            max_particles: 400,
            prune_existence: 0.01,
            report_existence: 0.5,
            confirm_frames: 3,
            confirm_within_frames: 12,
            merge_distance: 0.25,
            birth_min_share: 0.5,
            min_visible_head: 0.5,
            head_model_error: 0.04,
            seed: 1,
        }
    }
}

fn probability(field: &'static str, value: f64) -> CameraResult<()> {
    if value > 0.0 && value < 1.0 {
        Ok(())
    } else {
        Err(invalid(field, format!("must be in (0, 1), got {value}")))
    }
}

impl PersonShape {
    /// Checks every value's range.
    pub fn validate(&self) -> CameraResult<()> {
        require_positive("multi_bernoulli.person.min_height", self.min_height)?;
        if !(self.max_height.is_finite() && self.max_height >= self.min_height) {
            return Err(invalid(
                "multi_bernoulli.person.max_height",
                format!("must be >= min_height, got {}", self.max_height),
            ));
        }
        for (field, value) in [
            (
                "multi_bernoulli.person.head_half_width",
                self.head_half_width,
            ),
            (
                "multi_bernoulli.person.shoulder_half_width",
                self.shoulder_half_width,
            ),
            ("multi_bernoulli.person.hip_half_width", self.hip_half_width),
            (
                "multi_bernoulli.person.foot_half_width",
                self.foot_half_width,
            ),
            (
                "multi_bernoulli.person.neck_half_width",
                self.neck_half_width,
            ),
        ] {
            require_positive(field, value)?;
        }
        let (hip, shoulder, chin) = (self.hip_share, self.shoulder_share, 1.0 - self.head_share);
        if !(0.0 < hip && hip < shoulder && shoulder < chin && chin < 1.0) {
            return Err(invalid(
                "multi_bernoulli.person.hip_share",
                format!("need 0 < hip_share < shoulder_share < 1 - head_share < 1, got {hip}, {shoulder} and {chin}"),
            ));
        }
        Ok(())
    }
}

impl MultiBernoulliConfig {
    /// Checks every value's range; the tracker refuses a configuration that fails this.
    pub fn validate(&self) -> CameraResult<()> {
        if !(1..=8).contains(&self.downscale) {
            return Err(invalid(
                "multi_bernoulli.downscale",
                format!("must be in 1..=8, got {}", self.downscale),
            ));
        }
        if !self.floor_z.is_finite() {
            return Err(invalid("multi_bernoulli.floor_z", "must be finite".into()));
        }
        self.person.validate()?;
        let saturation = f64::from(self.foreground_saturation);
        if !(saturation > 0.0 && saturation <= 1.0) {
            return Err(invalid(
                "multi_bernoulli.foreground_saturation",
                format!("must be in (0, 1], got {saturation}"),
            ));
        }
        probability(
            "multi_bernoulli.foreground_threshold",
            f64::from(self.foreground_threshold),
        )?;
        require_positive(
            "multi_bernoulli.pixels_per_observation",
            f64::from(self.pixels_per_observation),
        )?;
        require_positive("multi_bernoulli.head_weight", f64::from(self.head_weight))?;
        if !(self.survival_per_second > 0.0 && self.survival_per_second <= 1.0) {
            return Err(invalid(
                "multi_bernoulli.survival_per_second",
                format!("must be in (0, 1], got {}", self.survival_per_second),
            ));
        }
        require_positive("multi_bernoulli.accel_noise", self.accel_noise)?;
        require_positive("multi_bernoulli.height_noise", self.height_noise)?;
        probability("multi_bernoulli.birth_existence", self.birth_existence)?;
        require_positive(
            "multi_bernoulli.birth_velocity_std",
            self.birth_velocity_std,
        )?;
        probability("multi_bernoulli.prune_existence", self.prune_existence)?;
        probability("multi_bernoulli.report_existence", self.report_existence)?;
        if self.min_particles == 0
            || self.max_particles < self.min_particles
            || self.birth_particles == 0
        {
            return Err(invalid(
                "multi_bernoulli.min_particles",
                format!(
                    "need 1 <= min_particles <= max_particles and birth_particles >= 1, got {}, {} and {}",
                    self.min_particles, self.max_particles, self.birth_particles
                ),
            ));
        }
        require_positive("multi_bernoulli.merge_distance", self.merge_distance)?;
        require_positive("multi_bernoulli.birth_min_share", self.birth_min_share)?;
        if !(0.0..=1.0).contains(&self.min_visible_head) {
            return Err(invalid(
                "multi_bernoulli.min_visible_head",
                format!("must be in [0, 1], got {}", self.min_visible_head),
            ));
        }
        if !(self.head_model_error.is_finite() && self.head_model_error >= 0.0) {
            return Err(invalid(
                "multi_bernoulli.head_model_error",
                format!("must be finite and >= 0, got {}", self.head_model_error),
            ));
        }
        Ok(())
    }
}
