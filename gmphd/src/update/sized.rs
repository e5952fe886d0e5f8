//! The update's stages on one pair of sizes (state n, measurement m; see [`super::dims`]):
//! prepare each detectable component (projection and innovation factor), score each
//! measurement's pairs, compute the shared corrections, emit the children.

use nalgebra::{DMatrix, DefaultAllocator, OMatrix, OVector};

use super::birth_memo::StaticBirths;
use super::candidates::CandidateIndex;
use super::component::{Detectable, Projection};
use super::correction::Correction;
use super::dims::{Dims, Storage};
use super::pairs::{self, MeasurementPairs, PairRules, Scratch};
use super::parallel::{self, CORRECTION_NS, LINEAR_COMPONENT_NS, PAIR_NS, UNSCENTED_COMPONENT_NS};
use super::unscented::{self, UnscentedScratch};
use super::UpdateStep;
use crate::echoes::EchoShifts;
use crate::error::FilterError;
use crate::gaussian::Gaussian;
use crate::measurement::{Measurement, Residual};

/// The buffers one thread's update reuses from one component or measurement to the next.
#[derive(Default)]
pub(super) struct UpdateScratch {
    unscented: UnscentedScratch,
    pairs: Scratch,
}

/// What one update works on.
pub(super) struct Work<'w, 'p> {
    pub(super) step: &'w UpdateStep<'w>,
    /// γ of the sensor's measurement size (+∞ without a gate).
    pub(super) gate: f64,
    /// Pairs lighter than this are not emitted.
    pub(super) min_weight: f64,
    pub(super) measurements: &'w [Measurement],
    /// The measurement entry to index the measurements along (not an angle).
    pub(super) index_dim: Option<usize>,
    /// The detectable components: index in the predicted mixture, component, log(p_D w).
    pub(super) seen: &'w [(usize, &'p Gaussian, f64)],
    /// The sensor's side peaks, when modelled.
    pub(super) echoes: Option<EchoShifts>,
}

/// U(z) of every measurement, appending the detection children to `children`, on the
/// sizes `dims`. `births` are the static births among the components, whose projections
/// are recalled or remembered.
pub(super) fn update_sized<'p, D: Dims>(
    dims: D,
    work: &Work<'_, 'p>,
    mut births: Option<StaticBirths<'_>>,
    scratch: &mut UpdateScratch,
    children: &mut Vec<Gaussian>,
) -> Result<Vec<f64>, FilterError>
where
    DefaultAllocator: Storage<D>,
    // Prepared components are shared by, and sent between, rayon's threads.
    OMatrix<f64, D::N, D::M>: Send + Sync,
    OMatrix<f64, D::M, D::M>: Send + Sync,
    OVector<f64, D::M>: Send + Sync,
{
    let noise = work.step.sensor.noise_cov();
    let detectable = prepare(dims, work, births.as_ref(), &noise, &mut scratch.unscented)?;
    if let Some(births) = &mut births {
        remember_births(work.seen, &detectable, births);
    }
    let scored = score(work, &detectable, &mut scratch.pairs);
    let mut needed = vec![0; detectable.len()];
    pairs::count_default_noise_children(&scored, work.measurements, &mut needed);
    let mut shared = corrections(&detectable, &needed, &noise);
    // Emission is serial: it is mostly allocation, which does not scale across threads
    // (and children freed on another thread than their allocating one cost more).
    let kept: usize = scored.iter().map(|s| s.pairs.len()).sum();
    children.reserve(kept);
    for (pairs, measurement) in scored.iter().zip(work.measurements) {
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

/// Each detectable component projected into measurement space (a slice for a linear
/// sensor; an unscented transform, or a static birth's remembered one, otherwise) with its
/// innovation factored.
fn prepare<'p, D: Dims>(
    dims: D,
    work: &Work<'_, 'p>,
    births: Option<&StaticBirths<'_>>,
    noise: &DMatrix<f64>,
    scratch: &mut UnscentedScratch,
) -> Result<Vec<Detectable<'p, D>>, FilterError>
where
    DefaultAllocator: Storage<D>,
    OMatrix<f64, D::N, D::M>: Send + Sync,
    OMatrix<f64, D::M, D::M>: Send + Sync,
    OVector<f64, D::M>: Send + Sync,
{
    let step = work.step;
    let linear = step
        .sensor
        .linear_position_dims()
        .is_some_and(|d| d <= step.motion.position_dims());
    let component_ns = if linear {
        LINEAR_COMPONENT_NS
    } else {
        UNSCENTED_COMPONENT_NS
    };
    let prepare_one = |scratch: &mut UnscentedScratch,
                       _: usize,
                       &(index, component, log_prior): &(usize, &'p Gaussian, f64)|
     -> Result<Detectable<'p, D>, FilterError> {
        let projection = if linear {
            Projection::Linear
        } else {
            let recalled = births.and_then(|b| b.recall(dims, index, component));
            match recalled {
                Some(moments) => Projection::Unscented(moments),
                None => Projection::Unscented(unscented::project(dims, component, step, scratch)?),
            }
        };
        Ok(Detectable::new(
            dims, component, log_prior, projection, noise, work.gate,
        ))
    };
    parallel::try_map(
        work.seen,
        work.seen.len() * component_ns,
        scratch,
        UnscentedScratch::default,
        prepare_one,
    )
}

/// Remembers the unscented projections of the static births among `detectable`.
fn remember_births<D: Dims>(
    seen: &[(usize, &Gaussian, f64)],
    detectable: &[Detectable<'_, D>],
    births: &mut StaticBirths<'_>,
) where
    DefaultAllocator: Storage<D>,
{
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

/// The kept pairs of every measurement, with its U(z).
fn score<D: Dims>(
    work: &Work<'_, '_>,
    detectable: &[Detectable<'_, D>],
    scratch: &mut Scratch,
) -> Vec<MeasurementPairs>
where
    DefaultAllocator: Storage<D>,
    OMatrix<f64, D::N, D::M>: Send + Sync,
    OMatrix<f64, D::M, D::M>: Send + Sync,
    OVector<f64, D::M>: Send + Sync,
{
    let sensor = work.step.sensor;
    let rules = PairRules {
        residual: Residual::of(sensor),
        log_clutter: sensor.clutter_intensity().ln(),
        gate: work.gate,
        min_weight: work.min_weight,
        echoes: work.echoes,
    };
    // With a gate, each measurement meets only the components whose gate reaches it along
    // the sensor's index dimension; the rest would fail the box test anyway. (Not so for
    // side peaks, which lie δ away: with them every pair is tested.)
    let index = work
        .index_dim
        .filter(|_| work.gate < f64::INFINITY && work.echoes.is_none())
        .map(|dim| CandidateIndex::build(detectable, work.measurements, dim));
    let nearby = |j: usize| index.as_ref().and_then(|index| index.candidates(j));
    let pair_count: usize = (0..work.measurements.len())
        .map(|j| nearby(j).map_or(detectable.len(), <[u32]>::len))
        .sum();
    let score_one = |scratch: &mut Scratch, j: usize, m: &Measurement| {
        pairs::score(detectable, nearby(j), m, &rules, scratch)
    };
    parallel::map(
        work.measurements,
        pair_count * PAIR_NS,
        scratch,
        Scratch::default,
        score_one,
    )
}

/// The default-noise gain and posterior covariance of every component with a kept pair.
fn corrections<D: Dims>(
    detectable: &[Detectable<'_, D>],
    needed: &[usize],
    noise: &DMatrix<f64>,
) -> Vec<Option<Correction<D>>>
where
    DefaultAllocator: Storage<D>,
    OMatrix<f64, D::N, D::M>: Send + Sync,
    OMatrix<f64, D::M, D::M>: Send + Sync,
    OVector<f64, D::M>: Send + Sync,
{
    let needed_count = needed.iter().filter(|n| **n > 0).count();
    let correct = |_: &mut (), k: usize, d: &Detectable<'_, D>| {
        (needed[k] > 0).then(|| Correction::new(d, &d.innovation, noise))
    };
    parallel::map(
        detectable,
        needed_count * CORRECTION_NS,
        &mut (),
        || (),
        correct,
    )
}
