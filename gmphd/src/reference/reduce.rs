//! Vo & Ma's prune–merge–cap reduction (2006, Table II), as the paper writes it.

use nalgebra::{DMatrix, DVector};

use crate::gaussian::{Gaussian, GaussianMixture};

/// Prunes, merges and caps `mixture`:
///
/// 1. keep the components of weight above `prune_threshold` T (and finite);
/// 2. while any is left: take the heaviest one (ties: smaller label, then earlier in the
///    input) as the pivot, and merge it with every remaining component i whose mean lies
///    within `merge_threshold` U of the pivot's, (mᵢ − m)ᵀ Pᵢ⁻¹ (mᵢ − m) ≤ U ([`merge`]);
/// 3. keep the `max_components` heaviest of the merged components (same ties), heaviest
///    first.
pub fn prune_merge_cap(
    mixture: &GaussianMixture,
    prune_threshold: f64,
    merge_threshold: f64,
    max_components: usize,
) -> GaussianMixture {
    let mut remaining: Vec<(usize, &Gaussian)> = mixture
        .iter()
        .enumerate()
        .filter(|(_, g)| g.weight > prune_threshold && g.weight.is_finite())
        .collect();
    remaining.sort_by(heaviest_first);
    let mut merged: Vec<(usize, Gaussian)> = Vec::new();
    while !remaining.is_empty() {
        let pivot = remaining[0].1;
        let (members, rest): (Vec<_>, Vec<_>) = remaining
            .into_iter()
            .partition(|(_, g)| std::ptr::eq(*g, pivot) || within(g, pivot, merge_threshold));
        remaining = rest;
        let position = merged.len();
        let members: Vec<&Gaussian> = members.into_iter().map(|(_, g)| g).collect();
        merged.push((position, merge(&members)));
    }
    merged.sort_by(|a, b| heaviest_first(&(a.0, &a.1), &(b.0, &b.1)));
    merged.truncate(max_components);
    GaussianMixture::from_components(merged.into_iter().map(|(_, g)| g).collect())
}

/// Heavier first, then the smaller label, then the earlier position.
fn heaviest_first(a: &(usize, &Gaussian), b: &(usize, &Gaussian)) -> std::cmp::Ordering {
    b.1.weight
        .total_cmp(&a.1.weight)
        .then(a.1.label.cmp(&b.1.label))
        .then(a.0.cmp(&b.0))
}

/// Whether `candidate`'s mean is within squared Mahalanobis distance `threshold` of
/// `pivot`'s, under the candidate's covariance (Vo & Ma's Table II, step 3).
fn within(candidate: &Gaussian, pivot: &Gaussian, threshold: f64) -> bool {
    if candidate.dim() != pivot.dim() {
        return false;
    }
    let d = &candidate.mean - &pivot.mean;
    match candidate.cov.clone().cholesky() {
        Some(chol) => d.dot(&chol.solve(&d)) <= threshold,
        None => false,
    }
}

/// The moment-matched merge of `members` (at least one, the first the heaviest): total
/// weight w = Σ wᵢ, mean m = Σ wᵢ mᵢ / w, covariance Σ wᵢ (Pᵢ + (m − mᵢ)(m − mᵢ)ᵀ) / w,
/// labelled by the first member. A single member is returned as it is.
pub fn merge(all: &[&Gaussian]) -> Gaussian {
    let first = all[0];
    if all.len() == 1 {
        return first.clone();
    }
    let n = first.dim();
    let weight: f64 = all.iter().map(|g| g.weight).sum();
    let mut mean = DVector::zeros(n);
    for g in all {
        mean += &g.mean * g.weight;
    }
    mean /= weight;
    let mut cov = DMatrix::zeros(n, n);
    for g in all {
        let d = &mean - &g.mean;
        cov += (&g.cov + &d * d.transpose()) * g.weight;
    }
    cov /= weight;
    let cov = (&cov + cov.transpose()) * 0.5;
    Gaussian::new(weight, mean, cov, first.label)
}
