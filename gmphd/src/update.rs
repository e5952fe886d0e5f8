//! The GM-PHD update (Pham eq. 3.19; Vo & Ma 2006, Prop. 2 and the unscented
//! variant of their section IV), with a state-dependent detection probability: the
//! [`Updater`] of a filter, and the same update as free functions. The plain version,
//! which the tests hold this one to, is [`crate::reference::update`].
//!
//! Weights are computed in log space: log(p_D w q(z)) for every component and a
//! log-sum-exp with log κ(z), so a likelihood peaked like a 6e-5 s TDOA (densities
//! around 1e4) or a zero clutter intensity (log κ = −∞) never overflows or divides
//! by zero.
//!
//! **Gating** ([`Gating`], on by default in the filter): a component–measurement pair
//! outside the component's χ² validation gate is not evaluated further, and a pair whose
//! posterior weight is below a floor is not emitted; [`Gating::OFF`] gives the exact update.
//! The rules and what they cost in accuracy are in [`crate::gating`].
//!
//! **Cost.** Per component, once: the projection into measurement space (a slice, or an
//! unscented transform) and the Cholesky factor of the innovation covariance. With a gate,
//! the measurements are sorted along one unwrapped dimension and each component meets only
//! those within its gate's extent there (module `update::candidates`). Per remaining pair: a
//! residual, a bounding-box test of the gate and, inside it, a forward substitution that
//! stops as soon as the distance leaves the gate — no allocation. Gain and posterior
//! covariance do not depend on z: they are computed once per component that has a kept
//! pair and shared by its children; only an emitted child allocates (its mean and its copy
//! of the covariance). Components are prepared, measurements scored and corrections
//! computed in parallel (rayon) when there is enough work (about 2 ms of it, module
//! `update::parallel`);
//! each item is computed the same way either way and results are collected in order, so
//! the output is identical, component for component, on any number of threads. Children
//! are emitted serially: that part is allocation, which does not scale across threads.

mod birth_memo;
mod candidates;
mod component;
mod correction;
pub(crate) mod detection;
mod dims;
mod pairs;
mod parallel;
mod sized;
mod unscented;
mod updater;

use crate::error::FilterError;
use crate::gating::Gating;
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::measurement::{Measurement, MeasurementModel};
use crate::motion::MotionModel;
use crate::ukf::UnscentedParams;

#[cfg(test)]
pub(crate) use birth_memo::BirthProjections;
pub use updater::Updater;

/// The models one update needs.
#[derive(Debug, Clone, Copy)]
pub struct UpdateStep<'a> {
    /// Maps a state to the world point the sensor sees.
    pub motion: &'a dyn MotionModel,
    /// The sensor that produced the measurement set.
    pub sensor: &'a dyn MeasurementModel,
    /// Parameters of the unscented transform for nonlinear sensors.
    pub unscented: &'a UnscentedParams,
}

/// The posterior of one update and how well the prior explained each measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct UpdateOutcome {
    /// The updated intensity.
    pub posterior: GaussianMixture,
    /// Per measurement, in input order: its total posterior association weight
    /// U(z) = Σ_j p_D w_j q_j(z) / (κ(z) + Σ_j p_D w_j q_j(z)), the probability that some
    /// component of the prior produced it; 1 − U(z) is the probability that it is
    /// clutter or a new object (Ristic, Clark, Vo & Vo 2012). 0 for a measurement that
    /// neither a component nor clutter can explain.
    pub association: Vec<f64>,
}

/// Updates the predicted intensity with one sensor's measurement set, exactly (no
/// gating); see [`update_gated`], of which this keeps only the posterior.
pub fn update_intensity(
    predicted: &GaussianMixture,
    step: &UpdateStep<'_>,
    measurements: &[Measurement],
) -> Result<GaussianMixture, FilterError> {
    Ok(update_gated(predicted, step, &Gating::OFF, measurements)?.posterior)
}

/// Updates the predicted intensity with one sensor's measurement set, exactly (no
/// gating), and reports each measurement's total association weight; see
/// [`update_gated`].
pub fn update_with_association(
    predicted: &GaussianMixture,
    step: &UpdateStep<'_>,
    measurements: &[Measurement],
) -> Result<UpdateOutcome, FilterError> {
    update_gated(predicted, step, &Gating::OFF, measurements)
}

/// Updates the predicted intensity with one sensor's measurement set under `gating` and
/// reports each measurement's total association weight: [`Updater::update`] of an updater
/// made for this one update.
///
/// p_D is evaluated at each component's predicted position, or averaged over its spread
/// where that is outside the view (module `update::detection`); components the sensor
/// cannot see pass through unchanged. Updated components keep their parent's
/// label. A measurement's own covariance replaces the sensor noise for it. An
/// empty set only applies the missed-detection term. Components of exactly zero
/// weight (underflow, p_D = 1 misses) are dropped since they carry no intensity.
///
/// Order of the result: the missed-detection components in input order, then, per
/// measurement in input order, its children in component order.
pub fn update_gated(
    predicted: &GaussianMixture,
    step: &UpdateStep<'_>,
    gating: &Gating,
    measurements: &[Measurement],
) -> Result<UpdateOutcome, FilterError> {
    Updater::new(*step.unscented, *gating)?.update(
        predicted,
        step.motion,
        step.sensor,
        measurements,
    )
}

/// An update's result before its missed-detection components are made: those are
/// the predicted components with a new weight, which the caller either copies (in the
/// `first` components of [`Updater::parts`]) or, when it no longer needs the prior, moves
/// ([`UpdateParts::moving_from`]), saving a copy of every component.
pub(crate) struct UpdateParts {
    /// The missed-detection weights, in input order.
    missed: Vec<Missed>,
    /// The components the update was asked to start with, then the detection children,
    /// in output order.
    children: Vec<Gaussian>,
    /// U(z) per measurement.
    association: Vec<f64>,
}

/// What a missed detection leaves of one predicted component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Missed {
    /// Index into the predicted components.
    index: usize,
    /// (1 − p_D) w, with p_D scaled by the activity for a sensor that detects only active
    /// objects.
    weight: f64,
    /// The component's activity after the miss ([`crate::activity::after_miss`] for such a
    /// sensor, unchanged for others).
    activity: f64,
}

impl Missed {
    /// The missed-detection copy of `component` (the predicted component at `index`).
    fn applied_to(&self, component: Gaussian) -> Gaussian {
        Gaussian {
            weight: self.weight,
            activity: self.activity,
            ..component
        }
    }
}

impl UpdateParts {
    /// The outcome, moving the missed-detection components out of `predicted` — the
    /// mixture the update was given, with no components to start with.
    pub(crate) fn moving_from(self, predicted: GaussianMixture) -> UpdateOutcome {
        let mut components = Vec::with_capacity(self.missed.len() + self.children.len());
        let mut missed = self.missed.iter().peekable();
        for (i, component) in predicted.components.into_iter().enumerate() {
            if let Some(miss) = missed.next_if(|miss| miss.index == i) {
                components.push(miss.applied_to(component));
            }
        }
        components.extend(self.children);
        UpdateOutcome {
            posterior: GaussianMixture::from_components(components),
            association: self.association,
        }
    }
}
