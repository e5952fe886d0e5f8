//! The GM-PHD filter: intensity, clock and labels, driven by predict / update / reduce.

use serde::{Deserialize, Serialize};
use std::ops::Range;

use crate::activity::ActivityModel;
use crate::adaptive_birth::{AdaptiveBirth, AdaptiveBirthConfig};
use crate::birth::BirthModel;
use crate::echoes::Echoes;
use crate::error::FilterError;
use crate::existence;
use crate::gating::Gating;
use crate::gaussian::{GaussianMixture, LabelSource};
use crate::measurement::{Measurement, MeasurementModel};
use crate::motion::MotionModel;
use crate::newborn::separate_newborn_children;
use crate::occlusion::Occlusion;
use crate::predict::{predict_intensity, PredictionStep, Survival, SurvivalRegion};
use crate::reduce::{Ancestry, Reducer};
use crate::spawn::SpawnModel;
use crate::ukf::UnscentedParams;
use crate::update::Updater;

mod checkpoint;

pub use checkpoint::FilterState;

/// Settings of the recursion that are not models.
///
/// Gating of component–measurement pairs in the update is set apart, with
/// [`GmPhdFilter::with_gating`]: on by default ([`Gating::default`]: a 99.99 % χ²
/// validation gate and a posterior weight floor of 1e-9; see [`crate::gating`] for the
/// rules and their effect on accuracy).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FilterConfig {
    /// Probability that an object survives a prediction.
    pub survival: Survival,
    /// Unscented-transform parameters for nonlinear sensors.
    pub unscented: UnscentedParams,
}

/// A GM-PHD filter over one state space, fed by any number of sensors.
///
/// Per time stamp: [`GmPhdFilter::predict_to`] once, then [`GmPhdFilter::update`]
/// once per sensor that reported at that stamp — the sequential multi-sensor
/// update of Pham 5.3.2, where each sensor's posterior is the next one's prior —
/// then [`GmPhdFilter::reduce`].
///
/// With [`GmPhdFilter::with_adaptive_birth`], each update also leaves measurement-driven
/// births ([`AdaptiveBirth`]) that the next prediction adds to the static birth model's.
#[derive(Debug)]
pub struct GmPhdFilter {
    motion: Box<dyn MotionModel>,
    birth: Box<dyn BirthModel>,
    adaptive_birth: Option<AdaptiveBirth>,
    spawn: Option<SpawnModel>,
    reducer: Box<dyn Reducer>,
    config: FilterConfig,
    /// The update, with its gates, scratch space and remembered birth projections.
    updater: Updater,
    intensity: GaussianMixture,
    time: f64,
    labels: LabelSource,
    /// Objects outside it do not survive a prediction (none: no such limit).
    survival_region: Option<SurvivalRegion>,
    /// Least time between two additions of the static births (0: every prediction).
    birth_interval_s: f64,
    /// Prediction time elapsed since the static births were last added.
    birth_owed_s: f64,
    /// U(z) of each measurement of the last update.
    last_association: Vec<f64>,
    /// Labels handed out by the latest prediction (births, spawns): their components'
    /// children under different measurements get labels of their own
    /// ([`crate::newborn`]).
    newborn: Range<u64>,
    /// The objects' activity chain, when some sensors detect only active objects.
    activity: Option<ActivityModel>,
    /// Whether each label's weight after an update is that of a Bernoulli
    /// ([`crate::existence`]) instead of the PHD's.
    label_existence: bool,
}

impl GmPhdFilter {
    /// A filter with an empty intensity at `start_time` (s).
    pub fn new(
        motion: Box<dyn MotionModel>,
        birth: Box<dyn BirthModel>,
        reducer: Box<dyn Reducer>,
        config: FilterConfig,
        start_time: f64,
    ) -> Result<Self, FilterError> {
        config.survival.validate()?;
        if birth.state_dim() != motion.state_dim() {
            return Err(FilterError::DimensionMismatch {
                what: "birth model state",
                expected: motion.state_dim(),
                found: birth.state_dim(),
            });
        }
        if !start_time.is_finite() {
            return Err(FilterError::NonFinite { what: "start time" });
        }
        Ok(Self {
            motion,
            birth,
            adaptive_birth: None,
            spawn: None,
            reducer,
            updater: Updater::new(config.unscented, Gating::default())?,
            config,
            intensity: GaussianMixture::new(),
            time: start_time,
            labels: LabelSource::default(),
            survival_region: None,
            birth_interval_s: 0.0,
            birth_owed_s: 0.0,
            last_association: Vec::new(),
            newborn: 0..0,
            activity: None,
            label_existence: false,
        })
    }

    /// Models the objects' activity ([`crate::activity`]): sensors that detect only active
    /// objects ([`MeasurementModel::detects_only_active`]) scale p_D by each component's
    /// probability of being active, which their misses lower and the chain relaxes.
    pub fn with_activity(mut self, model: ActivityModel) -> Result<Self, FilterError> {
        model.validate()?;
        self.activity = Some(model);
        Ok(self)
    }

    /// Lowers p_D where a nearer object blocks a sensor's line of sight
    /// ([`crate::occlusion`]): a person hidden behind another from a camera or a LIDAR is
    /// not expected to be detected, so the hidden spell does not cost the track.
    pub fn with_occlusion(mut self, occlusion: Occlusion) -> Self {
        self.updater.set_occlusion(Some(occlusion));
        self
    }

    /// Models the side peaks of sensors that measure a delay ([`crate::echoes`]): a
    /// measurement δ to either side of a component's is also its detection. Meant with
    /// [`GmPhdFilter::with_label_existence`].
    pub fn with_echoes(mut self, echoes: Echoes) -> Result<Self, FilterError> {
        echoes.validate()?;
        self.updater.set_echoes(Some(echoes));
        Ok(self)
    }

    /// Updates each label's first object as a Bernoulli ([`crate::existence`]):
    /// a track the filter was sure of outlasts a run of misses, and a detected label does
    /// not keep its missed-detection copies' weight on top of its detection's.
    pub fn with_label_existence(mut self) -> Self {
        self.label_existence = true;
        self
    }

    /// Objects whose predicted position leaves `region` (the surveillance volume, perhaps with
    /// a margin) die in the prediction; see [`SurvivalRegion`] for why a tracker whose sensors
    /// do not see everywhere needs it. Births are not affected (adaptive births outside die at
    /// the next prediction).
    pub fn with_survival_region(mut self, region: SurvivalRegion) -> Result<Self, FilterError> {
        if region.dims() != self.motion.position_dims() {
            return Err(FilterError::DimensionMismatch {
                what: "survival region",
                expected: self.motion.position_dims(),
                found: region.dims(),
            });
        }
        self.survival_region = Some(region);
        Ok(self)
    }

    /// Adds the static model's births only once at least `seconds` of prediction have
    /// passed since they were last added, for all that time at once (`birth(owed)`), instead
    /// of at every prediction. For a birth model with per-second rates
    /// ([`BirthTiming::PerSecond`](crate::BirthTiming::PerSecond)) the birth intensity per
    /// second stays the same; what changes is cost: many sensors at high rates predict every
    /// few milliseconds, and each prediction's births (one component per grid cell) are
    /// updated and then almost all pruned. An object is offered a birth at most `seconds`
    /// later. 0 (the default) adds births at every prediction. Meaningless for per-step
    /// weights, whose births would just become rarer.
    pub fn with_birth_interval(mut self, seconds: f64) -> Result<Self, FilterError> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(crate::error::invalid(
                "birth interval",
                format!("{seconds} s is not a finite number >= 0"),
            ));
        }
        self.birth_interval_s = seconds;
        Ok(self)
    }

    /// Adds measurement-driven birth (Ristic et al. 2012) to the static birth model: each
    /// update's invertible measurements, weighted by how poorly the intensity explained
    /// them, become births of the next prediction.
    pub fn with_adaptive_birth(mut self, config: AdaptiveBirthConfig) -> Result<Self, FilterError> {
        self.adaptive_birth = Some(AdaptiveBirth::new(config)?);
        Ok(self)
    }

    /// Replaces the gating of component–measurement pairs in the update ([`Gating::default`]
    /// unless set; [`Gating::OFF`] for the exact update).
    pub fn with_gating(mut self, gating: Gating) -> Result<Self, FilterError> {
        self.updater = Updater::new(self.config.unscented, gating)?;
        Ok(self)
    }

    /// The gating of component–measurement pairs in the update.
    pub fn gating(&self) -> &Gating {
        self.updater.gating()
    }

    /// Adds Vo & Ma's spawning to the prediction.
    pub fn with_spawn(mut self, spawn: SpawnModel) -> Result<Self, FilterError> {
        if spawn.state_dim() != self.motion.state_dim() {
            return Err(FilterError::DimensionMismatch {
                what: "spawn model state",
                expected: self.motion.state_dim(),
                found: spawn.state_dim(),
            });
        }
        self.spawn = Some(spawn);
        Ok(self)
    }

    /// The remembered projections of the static births.
    #[cfg(test)]
    pub(crate) fn birth_projections(&self) -> &crate::update::BirthProjections {
        self.updater.birth_projections()
    }

    /// Changes the labels of the intensity's components with `relabel` (which may also
    /// split a component into equal-weight copies, each already valid); labels it used are
    /// never handed out again.
    pub(crate) fn relabel_intensity<R>(
        &mut self,
        relabel: impl FnOnce(&mut GaussianMixture) -> R,
    ) -> R {
        let result = relabel(&mut self.intensity);
        let highest = self.intensity.iter().map(|c| c.label.0).max().unwrap_or(0);
        if highest >= self.labels.peek() {
            self.labels = LabelSource::starting_at(highest + 1);
        }
        result
    }

    /// Replaces the intensity (e.g. a known initial prior). Labels already in it
    /// are never handed out again.
    pub fn set_intensity(&mut self, intensity: GaussianMixture) -> Result<(), FilterError> {
        self.validate_mixture(&intensity)?;
        self.skip_used_labels(&intensity);
        self.intensity = intensity;
        Ok(())
    }

    /// Predicts the intensity to time `t` (s): survival, spawning, births (the static
    /// model's, then the pending measurement-driven ones, which are used up).
    /// Predicting to the current time is a no-op (a second sensor at the same
    /// stamp must not add births twice); an earlier time is an error.
    pub fn predict_to(&mut self, t: f64) -> Result<(), FilterError> {
        if !t.is_finite() {
            return Err(FilterError::NonFinite {
                what: "prediction time",
            });
        }
        if t < self.time {
            return Err(FilterError::TimeWentBackwards {
                last: self.time,
                requested: t,
            });
        }
        if t == self.time {
            return Ok(());
        }
        let dt = t - self.time;
        let first_newborn = self.labels.peek();
        let owed = self.birth_owed_s + dt;
        // Relative tolerance: 25 steps of 4 ms add up to just under 0.1 s.
        let (mut births, still_owed) = if owed >= self.birth_interval_s * (1.0 - 1e-9) {
            (self.birth.birth(owed, &mut self.labels), 0.0)
        } else {
            (Vec::new(), owed)
        };
        let static_count = births.len();
        if let Some(adaptive) = &self.adaptive_birth {
            births.extend(adaptive.births(self.motion.as_ref(), dt, &mut self.labels)?);
        }
        let step = PredictionStep {
            motion: self.motion.as_ref(),
            survival_probability: self.config.survival.probability(dt),
            spawn: self.spawn.as_ref(),
            dt,
            region: self.survival_region.as_ref(),
        };
        if let Some(activity) = &self.activity {
            activity.predict_mixture(&mut self.intensity, dt);
            births
                .iter_mut()
                .for_each(|birth| birth.activity = activity.stationary());
        }
        let birth_count = births.len();
        predict_intensity(&mut self.intensity, &step, births, &mut self.labels)?;
        // Appended last, the static births first.
        let first_birth = self.intensity.len() - birth_count;
        self.updater
            .expect_static_births(first_birth..first_birth + static_count);
        self.newborn = first_newborn..self.labels.peek();
        if let Some(adaptive) = &mut self.adaptive_birth {
            adaptive.clear();
        }
        self.birth_owed_s = still_owed;
        self.time = t;
        Ok(())
    }

    /// Corrects the intensity with one sensor's measurement set at the current
    /// time; an empty set is information too (nothing was detected). Records each
    /// measurement's association weight ([`GmPhdFilter::last_association`]) and, with
    /// adaptive birth, the births it leaves for the next prediction. On error the
    /// filter is left unchanged.
    pub fn update(
        &mut self,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
    ) -> Result<(), FilterError> {
        self.update_with_floor(sensor, measurements, self.updater.gating().min_weight)
    }

    /// [`GmPhdFilter::update`] followed at once by [`GmPhdFilter::reduce`]; returns what
    /// each reduced component descends from ([`Reducer::reduce_recording`]).
    ///
    /// Since nothing sees the posterior in between, the update does not emit the pairs
    /// the reduction would prune at once: the gating weight floor is raised to the
    /// reducer's [`Reducer::prune_threshold`]. The reduced intensity is the same as with
    /// `update` then `reduce`; an [`Ancestry::PreReduction`] posterior lacks only those
    /// pairs.
    pub fn update_and_reduce(
        &mut self,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
    ) -> Result<Ancestry, FilterError> {
        let floor = self
            .updater
            .gating()
            .min_weight
            .max(self.reducer.prune_threshold());
        self.update_with_floor(sensor, measurements, floor)?;
        let posterior = std::mem::take(&mut self.intensity);
        let reduction = self.reducer.reduce_recording(posterior);
        self.intensity = reduction.mixture;
        Ok(reduction.ancestry)
    }

    fn update_with_floor(
        &mut self,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
        min_weight: f64,
    ) -> Result<(), FilterError> {
        let prior_weights = self
            .label_existence
            .then(|| existence::label_weights(&self.intensity));
        let (association, missed) = self.updater.update_moving(
            &mut self.intensity,
            self.motion.as_ref(),
            sensor,
            measurements,
            min_weight,
        )?;
        if let Some(adaptive) = &mut self.adaptive_birth {
            adaptive.record(self.motion.as_ref(), sensor, measurements, &association);
        }
        if let Some(prior) = prior_weights {
            existence::bernoulli_labels(&prior, &mut self.intensity, missed);
        }
        separate_newborn_children(&mut self.intensity, &self.newborn, &mut self.labels);
        self.last_association = association;
        Ok(())
    }

    /// U(z) of each measurement of the last update, in its order: the probability that
    /// the intensity explains it; 1 − U(z) is the probability that it is clutter or a new
    /// object. See [`UpdateOutcome`](crate::update::UpdateOutcome).
    pub fn last_association(&self) -> &[f64] {
        &self.last_association
    }

    /// The measurement-driven birth, when enabled.
    pub fn adaptive_birth(&self) -> Option<&AdaptiveBirth> {
        self.adaptive_birth.as_ref()
    }

    /// Prunes, merges and caps the intensity with the configured reducer.
    pub fn reduce(&mut self) {
        self.intensity = self.reducer.reduce(&self.intensity);
    }

    /// The current intensity.
    pub fn intensity(&self) -> &GaussianMixture {
        &self.intensity
    }

    /// The time stamp of the current intensity.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The label the next newborn component will get (labels below it are used).
    pub fn next_label(&self) -> u64 {
        self.labels.peek()
    }

    /// The motion model (maps states to world positions and velocities).
    pub fn motion(&self) -> &dyn MotionModel {
        self.motion.as_ref()
    }

    /// Expected number of objects: the total weight of the intensity.
    pub fn expected_count(&self) -> f64 {
        self.intensity.total_weight()
    }
}
