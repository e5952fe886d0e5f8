//! Measurement-driven (adaptive) birth after Ristic, Clark, Vo & Vo, "Adaptive target
//! birth intensity for PHD and CPHD filters", IEEE Trans. AES 48(2), 2012.
//!
//! A static birth intensity has to cover everywhere an object may appear, so each of its
//! components is weak and wide and a new object takes several sets to be picked up —
//! and never if it appears outside the covered volume. Here the birth intensity of the
//! next prediction is built from the measurements of the last update instead: each
//! measurement z that an invertible sensor ([`MeasurementModel::invert_with_noise`])
//! maps back to a world point gets a Gaussian there, weighted by how poorly the prior
//! explained it.
//!
//! With U(z) the total posterior association weight of z (see
//! [`UpdateOutcome::association`](crate::update::UpdateOutcome::association)) and ν_b the
//! expected number of births per measurement set, the paper's birth weight is
//!
//! w(z) = ν_b · (1 − U(z)) / Σ_{ζ ∈ Z} (1 − U(ζ)).
//!
//! We floor the denominator at 1. The paper's normalisation always hands out the whole
//! ν_b, so when every measurement of a set is explained by a track (Σ ≪ 1) it would pour
//! ν_b onto the residues of explained measurements — a birth on top of every track, every
//! set. With the floor a well-explained measurement gets ≈ ν_b · (1 − U(z)) ≈ 0, and the
//! paper's form holds unchanged as soon as one measurement's worth is unexplained (a set
//! with a new object or with clutter). Only the measurements that can be inverted take
//! part in the sum; a set of a non-invertible sensor (camera, microphone pair) adds no
//! births, so the static birth model stays in charge of those.
//!
//! The birth Gaussian is placed at the measurement's time: position from the inverse map
//! with its covariance scaled by `position_inflation`, zero-mean velocity with
//! `velocity_std`, extra components (a turn rate) zero-mean with `extra_std`. The next
//! prediction carries it through the motion model over the elapsed interval (no survival
//! factor: it stands for an object that exists now), labels it freshly and adds it to the
//! static births.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{invalid, FilterError};
use crate::gaussian::{Gaussian, LabelSource};
use crate::linalg::{check_finite_vector, check_spd, nearest_spd};
use crate::measurement::{Measurement, MeasurementModel};
use crate::motion::MotionModel;

/// Variances of unspread state components are floored at this fraction of the largest
/// variance of the component, so that a zero `velocity_std` does not make it singular.
const VARIANCE_FLOOR: f64 = 1e-12;

/// Settings of measurement-driven birth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveBirthConfig {
    /// ν_b: expected number of new objects per measurement set of an invertible sensor,
    /// shared among the set's measurements in proportion to 1 − U(z) (≥ 0).
    pub rate: f64,
    /// Factor (≥ 1) on the inverted position covariance: room for the first-order
    /// inverse map's error and for objects that are larger than a point.
    pub position_inflation: f64,
    /// Standard deviation (m/s) of the newborn's zero-mean velocity, per axis (≥ 0).
    pub velocity_std: f64,
    /// Standard deviation of the newborn's extra state components (e.g. a turn rate in
    /// rad/s), zero mean (≥ 0).
    pub extra_std: f64,
    /// Births lighter than this are not created (the reducer would prune them; they
    /// would only cost time in the next update). ≥ 0.
    pub min_weight: f64,
}

impl Default for AdaptiveBirthConfig {
    /// ν_b = 0.1 per set, the covariance as inverted, 1 m/s velocity spread (walking
    /// pace), 0.1 rad/s turn-rate spread, births below 1e-6 dropped.
    fn default() -> Self {
        Self {
            rate: 0.1,
            position_inflation: 1.0,
            velocity_std: 1.0,
            extra_std: 0.1,
            min_weight: 1e-6,
        }
    }
}

impl AdaptiveBirthConfig {
    /// Checks every value; the error names the offending setting.
    pub fn validate(&self) -> Result<(), FilterError> {
        for (value, name) in [
            (self.rate, "adaptive birth rate"),
            (self.velocity_std, "adaptive birth velocity std"),
            (self.extra_std, "adaptive birth extra std"),
            (self.min_weight, "adaptive birth minimum weight"),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(invalid(
                    name,
                    format!("{value} is not a finite number >= 0"),
                ));
            }
        }
        let inflation = self.position_inflation;
        if !(inflation >= 1.0 && inflation.is_finite()) {
            return Err(invalid(
                "adaptive birth position inflation",
                format!("{inflation} is not a finite number >= 1"),
            ));
        }
        Ok(())
    }
}

/// A birth waiting for the next prediction: a Gaussian over the state at the time of the
/// measurement it came from, not yet labelled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BirthCandidate {
    /// Expected number of new objects it stands for.
    pub weight: f64,
    /// Mean state.
    pub mean: DVector<f64>,
    /// State covariance.
    pub cov: DMatrix<f64>,
}

/// Birth weights of one set's measurements from their association weights U(z):
/// ν_b (1 − U(z)) / max(1, Σ_ζ (1 − U(ζ))), `rate` = ν_b (finite, ≥ 0). See the module
/// documentation for the floor. U outside [0, 1] is clamped, and a NaN U counts as
/// explained (no birth from a measurement whose weight is unknown). The weights are
/// finite, ≥ 0 and sum to at most `rate`.
pub fn birth_weights(rate: f64, association: &[f64]) -> Result<Vec<f64>, FilterError> {
    if !(rate >= 0.0 && rate.is_finite()) {
        return Err(invalid(
            "adaptive birth rate",
            format!("{rate} is not a finite number >= 0"),
        ));
    }
    let unexplained: Vec<f64> = association
        .iter()
        .map(|u| {
            if u.is_nan() {
                0.0
            } else {
                1.0 - u.clamp(0.0, 1.0)
            }
        })
        .collect();
    let total = unexplained.iter().sum::<f64>().max(1.0);
    Ok(unexplained.iter().map(|v| rate * v / total).collect())
}

/// The births made from the last update(s), waiting for the next prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveBirth {
    config: AdaptiveBirthConfig,
    pending: Vec<BirthCandidate>,
}

impl AdaptiveBirth {
    /// Measurement-driven birth with `config`, nothing pending yet.
    pub fn new(config: AdaptiveBirthConfig) -> Result<Self, FilterError> {
        config.validate()?;
        Ok(Self {
            config,
            pending: Vec::new(),
        })
    }

    /// The settings.
    pub fn config(&self) -> &AdaptiveBirthConfig {
        &self.config
    }

    /// The births waiting for the next prediction, in the order they were made.
    pub fn pending(&self) -> &[BirthCandidate] {
        &self.pending
    }

    /// Total weight of the pending births.
    pub fn pending_weight(&self) -> f64 {
        self.pending.iter().map(|c| c.weight).sum()
    }

    /// Adds the births of one update: `association[i]` is U(z) of `measurements[i]` as
    /// returned by [`update_with_association`](crate::update::update_with_association).
    /// Births of several sensors at one stamp accumulate until the next prediction.
    pub fn record(
        &mut self,
        motion: &dyn MotionModel,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
        association: &[f64],
    ) {
        // The inverted points and their U(z); measurements that cannot be inverted take no
        // part, not even in the normaliser.
        let mut points = Vec::with_capacity(measurements.len());
        let mut associations = Vec::with_capacity(measurements.len());
        let default_noise = sensor.noise_cov();
        for (measurement, &u) in measurements.iter().zip(association) {
            let noise = measurement.cov.as_ref().unwrap_or(&default_noise);
            if let Some(point) = sensor.invert_with_noise(&measurement.z, noise) {
                points.push(point);
                associations.push(u);
            }
        }
        // The rate was validated with the configuration, so the weights always exist.
        let weights = birth_weights(self.config.rate, &associations).unwrap_or_default();
        for ((position, position_cov), weight) in points.into_iter().zip(weights) {
            if weight > 0.0 && weight >= self.config.min_weight {
                let (mean, cov) = self.newborn_state(motion, &position, &position_cov);
                self.pending.push(BirthCandidate { weight, mean, cov });
            }
        }
    }

    /// The pending births predicted over `dt` seconds (the time from their measurement to
    /// the prediction), each with a fresh label from `labels`. They stay pending until
    /// [`AdaptiveBirth::clear`], so that a failed prediction loses nothing.
    pub fn births(
        &self,
        motion: &dyn MotionModel,
        dt: f64,
        labels: &mut LabelSource,
    ) -> Result<Vec<Gaussian>, FilterError> {
        self.pending
            .iter()
            .map(|candidate| {
                let (mean, cov) = motion.predict(&candidate.mean, &candidate.cov, dt)?;
                Ok(Gaussian::new(candidate.weight, mean, cov, labels.fresh()))
            })
            .collect()
    }

    /// Drops the pending births (after a prediction has used them).
    pub fn clear(&mut self) {
        self.pending.clear();
    }

    /// Replaces the pending births with checkpointed ones, after checking each against
    /// the state size `state_dim`. On error nothing changes.
    pub fn restore(
        &mut self,
        pending: Vec<BirthCandidate>,
        state_dim: usize,
    ) -> Result<(), FilterError> {
        for candidate in &pending {
            if !(candidate.weight >= 0.0 && candidate.weight.is_finite()) {
                return Err(invalid(
                    "pending birth weight",
                    format!("{} is not a finite number >= 0", candidate.weight),
                ));
            }
            if candidate.mean.len() != state_dim {
                return Err(FilterError::DimensionMismatch {
                    what: "pending birth mean",
                    expected: state_dim,
                    found: candidate.mean.len(),
                });
            }
            check_finite_vector(&candidate.mean, "pending birth mean")?;
            check_spd(&candidate.cov, state_dim, "pending birth covariance")?;
        }
        self.pending = pending;
        Ok(())
    }

    /// The newborn's state Gaussian: the inverted position (as many coordinates as the
    /// motion model has), then a zero velocity if the model has one, then zero extras.
    fn newborn_state(
        &self,
        motion: &dyn MotionModel,
        position: &Vector3<f64>,
        position_cov: &Matrix3<f64>,
    ) -> (DVector<f64>, DMatrix<f64>) {
        let n = motion.state_dim();
        let d = motion.position_dims().min(3).min(n);
        let velocity_dims = if motion.velocity(&DVector::zeros(n)).is_some() {
            d.min(n - d)
        } else {
            0
        };
        let mut mean = DVector::zeros(n);
        let mut cov = DMatrix::zeros(n, n);
        for r in 0..d {
            mean[r] = position[r];
            for c in 0..d {
                cov[(r, c)] = self.config.position_inflation * position_cov[(r, c)];
            }
        }
        let velocity_var = self.config.velocity_std.powi(2);
        let extra_var = self.config.extra_std.powi(2);
        let floor = cov.diagonal().amax().max(velocity_var).max(extra_var) * VARIANCE_FLOOR;
        for i in d..n {
            let variance = if i < d + velocity_dims {
                velocity_var
            } else {
                extra_var
            };
            cov[(i, i)] = variance.max(floor);
        }
        // The inverse map's covariance can be singular (a LIDAR return along its axis).
        (mean, nearest_spd(&cov))
    }
}
