//! The GM-PHD update (Pham eq. 3.19; Vo & Ma 2006, Prop. 2 and the unscented
//! variant of their section IV), with a state-dependent detection probability.
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
//! computed in parallel (rayon) when there is enough work (about 2 ms of it);
//! each item is computed the same way either way and results are collected in order, so
//! the output is identical, component for component, on any number of threads. Children
//! are emitted serially: that part is allocation, which does not scale across threads.

mod birth_memo;
mod candidates;
mod component;
mod correction;
mod detection;
mod dims;
mod pairs;
mod unscented;

use nalgebra::{DVector, DefaultAllocator, OMatrix, OVector};
use rayon::prelude::*;

use crate::error::FilterError;
use crate::gating::Gating;
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::measurement::{Measurement, MeasurementModel, Residual};
use crate::motion::MotionModel;
use crate::ukf::UnscentedParams;
use candidates::CandidateIndex;
use component::{Detectable, Projection};
use correction::Correction;
use dims::{Dims, Dynamic, Fixed, Storage};
use pairs::{MeasurementPairs, PairRules, Scratch};
use unscented::UnscentedScratch;

pub(crate) use birth_memo::{BirthProjections, StaticBirths};

/// Least work (in nanoseconds of one core, roughly) that is spread over the rayon pool:
/// below it, handing work to another thread costs more than it saves. On the 2-vCPU machine
/// of BENCHMARKS.md two threads were slower than one at every size measured (0.3–5 ms
/// updates, the dense step), so only updates of several milliseconds go parallel, where a
/// machine with real spare cores gains.
const PARALLEL_MIN_WORK_NS: usize = 2_000_000;
/// Rough single-core cost of the parts of the update, for [`parallel`].
const PAIR_NS: usize = 10;
const LINEAR_COMPONENT_NS: usize = 200;
const UNSCENTED_COMPONENT_NS: usize = 1_000;
const CORRECTION_NS: usize = 500;

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
/// reports each measurement's total association weight.
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
    // The missed-detection copies go first into the output, so that the children are
    // emitted behind them instead of being moved there afterwards.
    let copies = |missed: &[(usize, f64)]| {
        let copy = |&(i, weight): &(usize, f64)| Gaussian {
            weight,
            ..predicted.components[i].clone()
        };
        missed.iter().map(copy).collect()
    };
    let parts = update_parts(predicted, step, gating, measurements, copies, None)?;
    Ok(UpdateOutcome {
        posterior: GaussianMixture::from_components(parts.children),
        association: parts.association,
    })
}

/// An update's result before its missed-detection components are made: those are
/// the predicted components with a new weight, which the caller either copies (in the
/// `first` components of [`update_parts`]) or, when it no longer needs the prior, moves
/// ([`UpdateParts::moving_from`]), saving a copy of every component.
pub(crate) struct UpdateParts {
    /// (index into the predicted components, (1 − p_D) w), in input order.
    missed: Vec<(usize, f64)>,
    /// The components `update_parts` was asked to start with, then the detection
    /// children, in output order.
    children: Vec<Gaussian>,
    /// U(z) per measurement.
    association: Vec<f64>,
}

impl UpdateParts {
    /// The outcome, moving the missed-detection components out of `predicted` — the
    /// mixture [`update_parts`] was given, with no components to start with.
    pub(crate) fn moving_from(self, predicted: GaussianMixture) -> UpdateOutcome {
        let mut components = Vec::with_capacity(self.missed.len() + self.children.len());
        let mut missed = self.missed.iter().peekable();
        for (i, component) in predicted.components.into_iter().enumerate() {
            if let Some(&(_, weight)) = missed.next_if(|(index, _)| *index == i) {
                components.push(Gaussian {
                    weight,
                    ..component
                });
            }
        }
        components.extend(self.children);
        UpdateOutcome {
            posterior: GaussianMixture::from_components(components),
            association: self.association,
        }
    }
}

/// The work of [`update_gated`]: the detection children are appended to the components
/// `first` makes from the missed-detection list (index, (1 − p_D) w); the caller turns
/// that list into components, or not (see [`UpdateParts`]). `births` names the static
/// births among the predicted components, whose projections it remembers.
pub(crate) fn update_parts(
    predicted: &GaussianMixture,
    step: &UpdateStep<'_>,
    gating: &Gating,
    measurements: &[Measurement],
    first: impl FnOnce(&[(usize, f64)]) -> Vec<Gaussian>,
    mut births: Option<StaticBirths<'_>>,
) -> Result<UpdateParts, FilterError> {
    gating.validate()?;
    for measurement in measurements {
        step.sensor.validate(measurement)?;
    }
    let mut missed = Vec::with_capacity(predicted.len());
    let mut seen = Vec::with_capacity(predicted.len());
    let mut point = DVector::zeros(0);
    for (index, component) in predicted.iter().enumerate().filter(|(_, c)| c.weight > 0.0) {
        let p_d = detection::detection_probability(component, step, &mut point);
        let missed_weight = (1.0 - p_d) * component.weight;
        if missed_weight > 0.0 {
            missed.push((index, missed_weight));
        }
        if p_d > 0.0 {
            seen.push((index, component, (p_d * component.weight).ln()));
        }
    }
    let mut children = first(&missed);

    // The common sizes get the per-component work compiled for them (see `dims`).
    let n = step.motion.state_dim();
    let fixed = seen.iter().all(|(_, c, _)| c.dim() == n);
    let out = &mut children;
    let work = Work {
        step,
        gating,
        measurements,
        seen: &seen,
        births: births.as_mut(),
    };
    let association = match (fixed.then_some(n), step.sensor.dim()) {
        (Some(6), 2) => update_sized(Fixed::<6, 2>, work, out),
        (Some(6), 3) => update_sized(Fixed::<6, 3>, work, out),
        (Some(6), 1) => update_sized(Fixed::<6, 1>, work, out),
        (Some(5), 2) => update_sized(Fixed::<5, 2>, work, out),
        (Some(4), 2) => update_sized(Fixed::<4, 2>, work, out),
        (_, m) => update_sized(Dynamic(m), work, out),
    }?;
    Ok(UpdateParts {
        missed,
        children,
        association,
    })
}

/// What [`update_sized`] works on.
struct Work<'w, 'p, 'b> {
    step: &'w UpdateStep<'w>,
    gating: &'w Gating,
    measurements: &'w [Measurement],
    /// The detectable components: index in the predicted mixture, component, log(p_D w).
    seen: &'w [(usize, &'p Gaussian, f64)],
    births: Option<&'w mut StaticBirths<'b>>,
}

/// U(z) of [`update_parts`], appending the detection children to `children`, on the
/// sizes `dims`.
fn update_sized<'p, D: Dims>(
    dims: D,
    work: Work<'_, 'p, '_>,
    children: &mut Vec<Gaussian>,
) -> Result<Vec<f64>, FilterError>
where
    DefaultAllocator: Storage<D>,
    // Prepared components are shared by, and sent between, rayon's threads.
    OMatrix<f64, D::N, D::M>: Send + Sync,
    OMatrix<f64, D::M, D::M>: Send + Sync,
    OVector<f64, D::M>: Send + Sync,
{
    let Work {
        step,
        gating,
        measurements,
        seen,
        births,
    } = work;
    let noise = step.sensor.noise_cov();
    let gate = gating.distance_threshold(step.sensor.dim());
    let linear_dims = step
        .sensor
        .linear_position_dims()
        .filter(|&d| d <= step.motion.position_dims());
    let component_ns = if linear_dims.is_some() {
        LINEAR_COMPONENT_NS
    } else {
        UNSCENTED_COMPONENT_NS
    };
    let remembered = births.as_deref();
    let prepare = |scratch: &mut UnscentedScratch,
                   &(index, component, log_prior): &(usize, &'p Gaussian, f64)|
     -> Result<Detectable<'p, D>, FilterError> {
        let projection = match linear_dims {
            Some(_) => Projection::Linear,
            None => match remembered.and_then(|b| b.recall(dims, index, component)) {
                Some(moments) => Projection::Unscented(moments),
                None => Projection::Unscented(unscented::project(dims, component, step, scratch)?),
            },
        };
        Ok(Detectable::new(
            dims, component, log_prior, projection, &noise, gate,
        ))
    };
    let detectable: Vec<Detectable<'_, D>> = if parallel(seen.len() * component_ns) {
        seen.par_iter()
            .map_init(UnscentedScratch::default, prepare)
            .collect::<Result<_, FilterError>>()?
    } else {
        // Pushed into a Vec of the final size: collecting through `Result` would grow it
        // by doubling, moving every (few-hundred-byte) prepared component each time.
        let mut scratch = UnscentedScratch::default();
        let mut detectable = Vec::with_capacity(seen.len());
        for s in seen {
            detectable.push(prepare(&mut scratch, s)?);
        }
        detectable
    };
    if let Some(births) = births {
        // `seen` ascends by index: only its run of static births is visited.
        let range = births.range.clone();
        let first = seen.partition_point(|&(index, _, _)| index < range.start);
        let in_range = seen[first..].iter().zip(&detectable[first..]);
        for (&(index, component, _), d) in in_range.take_while(|(s, _)| s.0 < range.end) {
            if let Some(moments) = d.unscented_moments() {
                births.remember(index, component, moments);
            }
        }
    }

    let rules = PairRules {
        residual: Residual::of(step.sensor),
        log_clutter: step.sensor.clutter_intensity().ln(),
        gate,
        min_weight: gating.min_weight,
    };
    // With a gate, each measurement meets only the components whose gate reaches it along
    // the sensor's index dimension; the rest would fail the box test anyway.
    let index = step
        .sensor
        .index_dim()
        .filter(|_| gate < f64::INFINITY)
        .map(|dim| CandidateIndex::build(&detectable, measurements, dim));
    let nearby = |j: usize| index.as_ref().and_then(|index| index.candidates(j));
    let pair_count: usize = (0..measurements.len())
        .map(|j| nearby(j).map_or(detectable.len(), <[u32]>::len))
        .sum();
    let score = |scratch: &mut Scratch, (j, m): (usize, &Measurement)| {
        pairs::score(&detectable, nearby(j), m, &rules, scratch)
    };
    let scored: Vec<MeasurementPairs> = if parallel(pair_count * PAIR_NS) {
        measurements
            .par_iter()
            .enumerate()
            .map_init(Scratch::default, score)
            .collect()
    } else {
        let mut scratch = Scratch::default();
        measurements
            .iter()
            .enumerate()
            .map(|jm| score(&mut scratch, jm))
            .collect()
    };

    let mut needed = vec![0; detectable.len()];
    pairs::count_default_noise_children(&scored, measurements, &mut needed);
    let correct = |(d, needed): (&Detectable<'_, D>, &usize)| {
        (*needed > 0).then(|| Correction::new(d, &d.innovation, &noise))
    };
    let needed_count = needed.iter().filter(|n| **n > 0).count();
    let mut shared: Vec<Option<Correction<D>>> = if parallel(needed_count * CORRECTION_NS) {
        detectable.par_iter().zip(&needed).map(correct).collect()
    } else {
        detectable.iter().zip(&needed).map(correct).collect()
    };

    // Emission is serial: it is mostly allocation, which does not scale across threads
    // (and children freed on another thread than their allocating one cost more).
    let kept: usize = scored.iter().map(|s| s.pairs.len()).sum();
    children.reserve(kept);
    for (pairs, measurement) in scored.iter().zip(measurements) {
        pairs::emit_children(
            pairs,
            measurement,
            &detectable,
            &mut shared,
            &mut needed,
            &noise,
            children,
        );
    }
    Ok(scored.iter().map(|s| s.association).collect())
}

/// Whether `work_ns` (estimated single-core nanoseconds) is worth spreading over the
/// rayon pool: only with more than one thread and enough work.
fn parallel(work_ns: usize) -> bool {
    work_ns >= PARALLEL_MIN_WORK_NS && rayon::current_num_threads() > 1
}
