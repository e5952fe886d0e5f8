//! The pairs of one measurement with the prepared components: gating, log-space weights
//! and the normaliser, without allocating per pair (buffers live in a [`Scratch`]).

use nalgebra::{DMatrix, DefaultAllocator, Dim};

use super::component::{Detectable, Innovation};
use super::correction::Correction;
use super::dims::{Dims, Storage};
use crate::echoes::EchoShifts;
use crate::gaussian::Gaussian;
use crate::measurement::{Measurement, Residual};

/// What scoring one measurement needs besides the components.
pub(super) struct PairRules<'a> {
    /// The sensor's residual z − ẑ.
    pub(super) residual: Residual<'a>,
    /// log κ(z).
    pub(super) log_clutter: f64,
    /// γ: the largest squared Mahalanobis distance inside the gate (+∞ without a gate).
    pub(super) gate: f64,
    /// Pairs lighter than this are not emitted.
    pub(super) min_weight: f64,
    /// The side-peak hypotheses of each pair, when the sensor's are modelled.
    pub(super) echoes: Option<EchoShifts>,
}

/// Buffers reused from one measurement to the next (one per worker thread).
#[derive(Default)]
pub(super) struct Scratch {
    residual: Vec<f64>,
    whitened: Vec<f64>,
    /// In-gate candidates: component index and log(p_D w q(z)) (a side-peak hypothesis:
    /// log(p_D w ρ q(z ∓ δ))).
    candidates: Vec<(usize, f64)>,
    /// Their residuals, `dim` entries each.
    candidate_residuals: Vec<f64>,
    /// Their exp(log term − largest log term), in [`weigh`].
    relative: Vec<f64>,
}

/// The kept pairs of one measurement.
pub(super) struct MeasurementPairs {
    /// U(z), see [`UpdateOutcome::association`](super::UpdateOutcome::association).
    pub(super) association: f64,
    /// Component index (into the detectable components) and posterior weight; a component
    /// may have three pairs with one measurement, as its direct path and as either side peak.
    pub(super) pairs: Vec<(usize, f64)>,
    /// Their residuals z − ẑ (a side peak's: z ∓ δ − ẑ), `dim` entries each, in pair order.
    pub(super) residuals: Vec<f64>,
}

/// Gates, weighs and keeps the pairs of `measurement` with the detectable components:
/// those listed in `nearby` (ascending; see [`super::candidates`]), or all when `None`.
///
/// A measurement with its own noise covariance needs an innovation factor per pair; it
/// is computed only for pairs inside the gate's bounding box.
pub(super) fn score<D: Dims>(
    detectable: &[Detectable<'_, D>],
    nearby: Option<&[u32]>,
    measurement: &Measurement,
    rules: &PairRules<'_>,
    scratch: &mut Scratch,
) -> MeasurementPairs
where
    DefaultAllocator: Storage<D>,
{
    let all = || 0..detectable.len();
    match nearby {
        Some(nearby) => gate_candidates(
            detectable,
            nearby.iter().map(|&k| k as usize),
            measurement,
            rules,
            rules.gate,
            scratch,
        ),
        None => gate_candidates(detectable, all(), measurement, rules, rules.gate, scratch),
    }
    if scratch.candidates.is_empty()
        && rules.log_clutter == f64::NEG_INFINITY
        && rules.gate < f64::INFINITY
    {
        // Without clutter the model says z comes from some object: the gate must not
        // turn it into nothing, so its pairs are weighed as without a gate.
        gate_candidates(
            detectable,
            all(),
            measurement,
            rules,
            f64::INFINITY,
            scratch,
        );
    }
    weigh(measurement_size::<D>(measurement), rules, scratch)
}

/// The size of `measurement` (validated to be the sensor's): on the fixed sizes the
/// update's constant, so that the loops over a residual are unrolled and its copies
/// inlined.
fn measurement_size<D: Dims>(measurement: &Measurement) -> usize {
    D::M::try_to_usize().unwrap_or(measurement.z.len())
}

/// Fills `scratch.candidates` (and their residuals) with the pairs of `measurement`
/// with the components `indices` (ascending) that lie inside the gate `gate`, each as its
/// direct path and, with `rules.echoes`, as either of its side peaks.
fn gate_candidates<D: Dims>(
    detectable: &[Detectable<'_, D>],
    indices: impl Iterator<Item = usize>,
    measurement: &Measurement,
    rules: &PairRules<'_>,
    gate: f64,
    scratch: &mut Scratch,
) where
    DefaultAllocator: Storage<D>,
{
    scratch.candidates.clear();
    scratch.candidate_residuals.clear();
    let dim = measurement_size::<D>(measurement);
    scratch.residual.resize(dim, 0.0);
    scratch.whitened.resize(dim, 0.0);
    let (residual, whitened) = (&mut scratch.residual[..dim], &mut scratch.whitened[..dim]);
    // Slices of exactly `dim` entries (a constant on the fixed sizes): the residual's loop
    // is then unrolled.
    let z = &measurement.z.as_slice()[..dim];
    for k in indices {
        let d = &detectable[k];
        rules.residual.write(z, &d.predicted_z()[..dim], residual);
        let mut density = PairDensity::new(d, measurement, gate);
        if let Some(log_q) = density.log_q(residual, whitened) {
            scratch.candidates.push((k, d.log_prior + log_q));
            scratch.candidate_residuals.extend_from_slice(residual);
        }
        let Some(echoes) = rules.echoes.filter(|e| e.beside(d.component)) else {
            continue;
        };
        let direct = residual[echoes.entry];
        for shift in echoes.residual_shifts() {
            residual[echoes.entry] = direct + shift;
            if let Some(log_q) = density.log_q(residual, whitened) {
                scratch
                    .candidates
                    .push((k, d.log_prior + echoes.log_rate + log_q));
                scratch.candidate_residuals.extend_from_slice(residual);
            }
        }
    }
}

/// The normaliser, U(z) and the kept pairs from the candidates in `scratch`.
fn weigh(dim: usize, rules: &PairRules<'_>, scratch: &mut Scratch) -> MeasurementPairs {
    let max = scratch
        .candidates
        .iter()
        .map(|(_, t)| *t)
        .fold(rules.log_clutter, f64::max);
    if max == f64::NEG_INFINITY {
        // No clutter and no component can explain z: it contributes nothing.
        return MeasurementPairs {
            association: 0.0,
            pairs: Vec::new(),
            residuals: Vec::new(),
        };
    }
    // exp(tᵢ − max) once per candidate: the weight is its share of the sum.
    scratch.relative.clear();
    scratch
        .relative
        .extend(scratch.candidates.iter().map(|(_, t)| (t - max).exp()));
    let sum: f64 = (rules.log_clutter - max).exp() + scratch.relative.iter().sum::<f64>();
    let log_normaliser = max + sum.ln();
    // U(z) = 1 − κ/normaliser, through exp_m1 so that a barely explained measurement
    // keeps its small U exactly; round-off in the log-sum-exp can put it just below 0.
    let explained = -(rules.log_clutter - log_normaliser).exp_m1();
    let candidates = scratch.candidates.len();
    let mut kept = MeasurementPairs {
        association: explained.max(0.0),
        pairs: Vec::with_capacity(candidates),
        residuals: Vec::with_capacity(candidates * dim),
    };
    for (i, (&(k, _), relative)) in scratch.candidates.iter().zip(&scratch.relative).enumerate() {
        let weight = relative / sum;
        if weight > 0.0 && weight >= rules.min_weight {
            kept.pairs.push((k, weight));
            kept.residuals
                .extend_from_slice(&scratch.candidate_residuals[i * dim..(i + 1) * dim]);
        }
    }
    kept
}

/// log q of one component's pairs with one measurement, for any residual tried (its direct
/// path and its side peaks). A measurement with its own noise needs an innovation of its own:
/// it is factored once, when a residual first falls inside the gate's bounding box.
struct PairDensity<'a, 'p, D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    d: &'a Detectable<'p, D>,
    noise: Option<&'a DMatrix<f64>>,
    own: Option<Innovation<D>>,
    gate: f64,
}

impl<'a, 'p, D: Dims> PairDensity<'a, 'p, D>
where
    DefaultAllocator: Storage<D>,
{
    fn new(d: &'a Detectable<'p, D>, measurement: &'a Measurement, gate: f64) -> Self {
        Self {
            d,
            noise: measurement.cov.as_ref(),
            own: None,
            gate,
        }
    }

    /// log q of `residual`, or `None` outside the gate (`whitened` is scratch of its size).
    fn log_q(&mut self, residual: &[f64], whitened: &mut [f64]) -> Option<f64> {
        let innovation = match self.noise {
            None => &self.d.innovation,
            Some(noise) => {
                if self.own.is_none() {
                    let d = self.d;
                    let outside = residual.iter().enumerate().any(|(i, r)| {
                        let variance = d.z_cov(i, i) + noise[(i, i)];
                        r.abs() > (self.gate * variance).sqrt()
                    });
                    if outside {
                        return None;
                    }
                    self.own = Some(d.innovation_with(noise, self.gate));
                }
                self.own.as_ref().expect("factored above")
            }
        };
        if self.gate < f64::INFINITY && innovation.outside_box(residual) {
            return None;
        }
        innovation
            .distance_sq(residual, whitened, self.gate)
            .map(|distance| innovation.log_density(distance))
    }
}

/// Counts in `children` the kept pairs with the default noise of each component (those
/// with any need their shared correction computed).
pub(super) fn count_default_noise_children(
    scored: &[MeasurementPairs],
    measurements: &[Measurement],
    children: &mut [usize],
) {
    for (pairs, measurement) in scored.iter().zip(measurements) {
        if measurement.cov.is_none() {
            for &(k, _) in &pairs.pairs {
                children[k] += 1;
            }
        }
    }
}

/// Appends the children of one measurement's kept pairs to `out`, in pair order. `shared`
/// holds the default-noise correction of every component counted by
/// [`count_default_noise_children`] and `remaining` its children not yet emitted: the last
/// one takes the correction's posterior covariance instead of a copy.
pub(super) fn emit_children<D: Dims>(
    pairs: &MeasurementPairs,
    measurement: &Measurement,
    detectable: &[Detectable<'_, D>],
    shared: &mut [Option<Correction<D>>],
    remaining: &mut [usize],
    default_noise: &DMatrix<f64>,
    out: &mut Vec<Gaussian>,
) where
    DefaultAllocator: Storage<D>,
{
    let dim = measurement_size::<D>(measurement);
    for (i, &(k, weight)) in pairs.pairs.iter().enumerate() {
        let d = &detectable[k];
        let residual = &pairs.residuals[i * dim..(i + 1) * dim];
        let child = match (&measurement.cov, &mut shared[k]) {
            (None, Some(_)) => {
                remaining[k] -= 1;
                if remaining[k] == 0 {
                    let last = shared[k].take().expect("matched above");
                    last.last_child(d.component, weight, residual)
                } else {
                    let correction = shared[k].as_ref().expect("matched above");
                    correction.child(d.component, weight, residual)
                }
            }
            // A measurement with its own noise (rare: estimates of an agent's own filter)
            // needs a correction of its own for every pair.
            (own, _) => {
                let noise = own.as_ref().unwrap_or(default_noise);
                let innovation = d.innovation_with(noise, f64::INFINITY);
                Correction::new(d, &innovation, noise).child(d.component, weight, residual)
            }
        };
        out.push(child);
    }
}
