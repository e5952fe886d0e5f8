//! The update step of a filter, with what it keeps from one update to the next.

use std::ops::Range;

use nalgebra::DVector;

use super::birth_memo::{BirthProjections, StaticBirths};
use super::detection::detection_probability;
use super::dims::{Dynamic, Fixed};
use super::sized::{update_sized, UpdateScratch, Work};
use super::{Missed, UpdateOutcome, UpdateParts, UpdateStep};
use crate::activity;
use crate::echoes::{EchoShifts, Echoes};
use crate::error::FilterError;
use crate::gating::Gating;
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::measurement::{Measurement, MeasurementModel};
use crate::motion::MotionModel;
use crate::occlusion::{Blockers, Occlusion};
use crate::ukf::UnscentedParams;

/// The GM-PHD update of one filter (see the module documentation for the algorithm and
/// [`crate::reference::update`] for its plain form), with what it keeps between updates:
///
/// * its scratch buffers (per-pair and per-sigma-point work allocates nothing);
/// * the gates γ of [`Gating`], one χ² quantile per measurement size, computed once;
/// * the unscented projections of the static births through each sensor (module
///   `update::birth_memo`): the births named by [`Updater::expect_static_births`] are the
///   same components at every birth, and their projection through a sensor whose
///   [`projection_key`](crate::UpdateHints::projection_key) is the same is recalled instead
///   of recomputed — only where the component is, bit for bit, the one projected, so the
///   result is the same either way.
///
/// It picks the sizes the per-component work is compiled for (module `update::dims`).
#[derive(Debug)]
pub struct Updater {
    unscented: UnscentedParams,
    gating: Gating,
    /// γ by measurement size (index), once computed.
    gates: Vec<Option<f64>>,
    scratch: ScratchCell,
    projections: BirthProjections,
    /// Indices of the static births in the next prior (empty: none, or not known).
    static_births: Range<usize>,
    /// How nearer objects lower p_D behind them, when modelled.
    occlusion: Option<Occlusion>,
    /// The side peaks of sensors that measure a delay, when modelled.
    echoes: Option<Echoes>,
}

/// The serial path's buffers (not part of the updater's debug output).
#[derive(Default)]
struct ScratchCell(UpdateScratch);

impl std::fmt::Debug for ScratchCell {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("UpdateScratch")
    }
}

impl Updater {
    /// An updater with the unscented transform `unscented` and the gating `gating`.
    pub fn new(unscented: UnscentedParams, gating: Gating) -> Result<Self, FilterError> {
        gating.validate()?;
        Ok(Self {
            unscented,
            gating,
            gates: Vec::new(),
            scratch: ScratchCell::default(),
            projections: BirthProjections::default(),
            static_births: 0..0,
            occlusion: None,
            echoes: None,
        })
    }

    /// Lowers each component's p_D by the share of it that nearer objects hide from a
    /// sensor with a line of sight ([`crate::occlusion`]).
    pub fn set_occlusion(&mut self, occlusion: Option<Occlusion>) {
        self.occlusion = occlusion;
    }

    /// Gives each component of a sensor that measures a delay
    /// ([`MeasurementModel::delay_entry`]) the side peaks `echoes` beside its direct path
    /// ([`crate::echoes`]).
    pub fn set_echoes(&mut self, echoes: Option<Echoes>) {
        self.echoes = echoes;
    }

    /// The gating of component–measurement pairs.
    pub fn gating(&self) -> &Gating {
        &self.gating
    }

    /// The parameters of the unscented transform.
    pub fn unscented(&self) -> &UnscentedParams {
        &self.unscented
    }

    /// Says that components `range` of the next update's prior are the static births,
    /// whose projections are then recalled or remembered (for that update only: the
    /// indices mean nothing after it).
    pub fn expect_static_births(&mut self, range: Range<usize>) {
        self.static_births = range;
    }

    /// The posterior of `prior` after `sensor`'s `measurements` (the prior mapped to the
    /// world by `motion`), and each measurement's U(z).
    pub fn update(
        &mut self,
        prior: &GaussianMixture,
        motion: &dyn MotionModel,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
    ) -> Result<UpdateOutcome, FilterError> {
        // The missed-detection copies go first into the output, so that the children are
        // emitted behind them instead of being moved there afterwards.
        let copies = |missed: &[Missed]| {
            let copy = |miss: &Missed| miss.applied_to(prior.components[miss.index].clone());
            missed.iter().map(copy).collect()
        };
        let floor = self.gating.min_weight;
        let parts = self.parts(prior, motion, sensor, measurements, floor, copies)?;
        Ok(UpdateOutcome {
            posterior: GaussianMixture::from_components(parts.children),
            association: parts.association,
        })
    }

    /// [`Updater::update`] of a prior the caller gives up, whose components are moved
    /// into the posterior rather than copied, with the weight floor `min_weight` instead of
    /// the gating's. Returns each measurement's U(z) and how many of the posterior's
    /// components, at its start, are missed-detection copies (the rest are detection
    /// children). On error `prior` is left as it was.
    pub(crate) fn update_moving(
        &mut self,
        prior: &mut GaussianMixture,
        motion: &dyn MotionModel,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
        min_weight: f64,
    ) -> Result<(Vec<f64>, usize), FilterError> {
        let no_first = |_: &[Missed]| Vec::new();
        let parts = self.parts(prior, motion, sensor, measurements, min_weight, no_first)?;
        let missed = parts.missed.len();
        let outcome = parts.moving_from(std::mem::take(prior));
        *prior = outcome.posterior;
        Ok((outcome.association, missed))
    }

    /// The work of an update: the detection children are appended to the components
    /// `first` makes from the missed-detection list (index, (1 − p_D) w); the caller turns
    /// that list into components, or not (see [`UpdateParts`]).
    fn parts(
        &mut self,
        predicted: &GaussianMixture,
        motion: &dyn MotionModel,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
        min_weight: f64,
        first: impl FnOnce(&[Missed]) -> Vec<Gaussian>,
    ) -> Result<UpdateParts, FilterError> {
        for measurement in measurements {
            sensor.validate(measurement)?;
        }
        let step = UpdateStep {
            motion,
            sensor,
            unscented: &self.unscented,
        };
        let blockers = self
            .occlusion
            .and_then(|occlusion| occlusion.blockers(predicted, motion, sensor));
        let (missed, seen) = split_by_detection(predicted, &step, blockers.as_ref());
        let mut children = first(&missed);
        let first_child = children.len();
        let hints = sensor.update_hints();
        let index_dim = hints
            .index_dim
            .filter(|d| *d < sensor.dim() && !sensor.angular_entries().contains(d));
        let work = Work {
            step: &step,
            gate: gate(&mut self.gates, &self.gating, sensor.dim()),
            min_weight,
            measurements,
            index_dim,
            seen: &seen,
            echoes: self
                .echoes
                .zip(sensor.delay_entry())
                .map(|(echoes, entry)| EchoShifts::new(echoes, entry)),
        };
        // (The remembered projections are checked against each component, so a stale range
        // costs only the check.)
        let range = std::mem::take(&mut self.static_births);
        let births = match hints.projection_key {
            Some(key) if !range.is_empty() => Some(StaticBirths {
                range,
                memo: self.projections.for_sensor(key),
            }),
            _ => None,
        };
        let scratch = &mut self.scratch.0;
        let out = &mut children;
        // The common sizes get the per-component work compiled for them (see `dims`).
        let n = motion.state_dim();
        let fixed = seen.iter().all(|(_, c, _)| c.dim() == n);
        let association = match (fixed.then_some(n), sensor.dim()) {
            (Some(6), 2) => update_sized(Fixed::<6, 2>, &work, births, scratch, out),
            (Some(6), 3) => update_sized(Fixed::<6, 3>, &work, births, scratch, out),
            (Some(6), 1) => update_sized(Fixed::<6, 1>, &work, births, scratch, out),
            (Some(5), 2) => update_sized(Fixed::<5, 2>, &work, births, scratch, out),
            (Some(4), 2) => update_sized(Fixed::<4, 2>, &work, births, scratch, out),
            (_, m) => update_sized(Dynamic(m), &work, births, scratch, out),
        }?;
        if sensor.detects_only_active() {
            // Heard, so active.
            children[first_child..]
                .iter_mut()
                .for_each(|child| child.activity = 1.0);
        }
        Ok(UpdateParts {
            missed,
            children,
            association,
        })
    }

    /// The remembered projections of the static births.
    #[cfg(test)]
    pub(crate) fn birth_projections(&self) -> &BirthProjections {
        &self.projections
    }
}

/// The missed-detection weights ((1 − p_D) w) of the components of `predicted`, and those
/// the sensor can detect (index, component, log(p_D w)); components of zero weight are in
/// neither. For a sensor that detects only active objects p_D is scaled by the component's
/// activity, and a miss lowers the activity ([`crate::activity`]); with `blockers` it is
/// scaled by the share of the component they leave in view ([`crate::occlusion`]).
#[allow(clippy::type_complexity)]
fn split_by_detection<'p>(
    predicted: &'p GaussianMixture,
    step: &UpdateStep<'_>,
    blockers: Option<&Blockers>,
) -> (Vec<Missed>, Vec<(usize, &'p Gaussian, f64)>) {
    let mut missed = Vec::with_capacity(predicted.len());
    let mut seen = Vec::with_capacity(predicted.len());
    let mut point = DVector::zeros(0);
    let only_active = step.sensor.detects_only_active();
    for (index, component) in predicted.iter().enumerate().filter(|(_, c)| c.weight > 0.0) {
        let mut p_seen = detection_probability(component, step, &mut point);
        if let Some(blockers) = blockers.filter(|_| p_seen > 0.0) {
            let position = step.motion.position(&component.mean);
            p_seen *= blockers.visible_share(component.label, &position);
        }
        let (p_d, activity) = if only_active {
            let a = component.activity;
            (p_seen * a, activity::after_miss(a, p_seen))
        } else {
            (p_seen, component.activity)
        };
        let weight = (1.0 - p_d) * component.weight;
        if weight > 0.0 {
            missed.push(Missed {
                index,
                weight,
                activity,
            });
        }
        if p_d > 0.0 {
            seen.push((index, component, (p_d * component.weight).ln()));
        }
    }
    (missed, seen)
}

/// γ for measurements of `dim` entries, from `gates` or computed into it.
fn gate(gates: &mut Vec<Option<f64>>, gating: &Gating, dim: usize) -> f64 {
    if gates.len() <= dim {
        gates.resize(dim + 1, None);
    }
    *gates[dim].get_or_insert_with(|| gating.distance_threshold(dim))
}
