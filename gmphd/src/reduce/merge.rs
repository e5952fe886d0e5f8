//! Moment-matched merging of a cluster of components (Vo & Ma 2006, Table II, step 4).
//!
//! Computed in nalgebra matrices of the state's size — fixed for the common sizes, so the
//! sums run on the stack without allocation or bounds checks; dynamic otherwise, with the
//! same code — and copied into the merged component's own vectors once at the end.

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DMatrix, DVector, DefaultAllocator, Dim, Dyn, OMatrix, OVector, U1};

use crate::gaussian::Gaussian;
use crate::linalg::symmetrize_in_place;

/// Moment-matched merge of `members` (at least two), labelled by the first (the heaviest).
pub(super) fn merge<'a>(members: impl Iterator<Item = &'a Gaussian> + Clone) -> Gaussian {
    let first = members.clone().next().expect("a cluster has a member");
    match first.dim() {
        6 => merge_sized(Const::<6>, members),
        4 => merge_sized(Const::<4>, members),
        5 => merge_sized(Const::<5>, members),
        n => merge_sized(Dyn(n), members),
    }
}

/// [`merge`] for states of size `dim`.
fn merge_sized<'a, D: Dim>(dim: D, members: impl Iterator<Item = &'a Gaussian> + Clone) -> Gaussian
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let n = dim.value();
    let first = members.clone().next().expect("a cluster has a member");
    let weight: f64 = members.clone().map(|g| g.weight).sum();
    let mut mean = OVector::<f64, D>::zeros_generic(dim, U1);
    for g in members.clone() {
        for (m, x) in mean.as_mut_slice().iter_mut().zip(&g.mean.as_slice()[..n]) {
            *m += g.weight * x;
        }
    }
    mean /= weight;
    let mut cov = OMatrix::<f64, D, D>::zeros_generic(dim, dim);
    let mut d = OVector::<f64, D>::zeros_generic(dim, U1);
    for g in members.clone() {
        for ((d, x), m) in d
            .as_mut_slice()
            .iter_mut()
            .zip(&g.mean.as_slice()[..n])
            .zip(mean.as_slice())
        {
            *d = x - m;
        }
        let w = g.weight;
        // P += w (Pᵢ + d dᵀ), column by column.
        let prior = &g.cov.as_slice()[..n * n];
        for (j, (column, prior_column)) in cov
            .as_mut_slice()
            .chunks_exact_mut(n)
            .zip(prior.chunks_exact(n))
            .enumerate()
        {
            for (c, p) in column.iter_mut().zip(prior_column) {
                *c += w * p;
            }
            let scaled = w * d[j];
            for (c, x) in column.iter_mut().zip(d.as_slice()) {
                *c += scaled * x;
            }
        }
    }
    cov /= weight;
    symmetrize_in_place(&mut cov);
    let activity = members.map(|g| g.weight * g.activity).sum::<f64>() / weight;
    Gaussian {
        activity,
        ..Gaussian::new(
            weight,
            DVector::from_column_slice(mean.as_slice()),
            DMatrix::from_column_slice(n, n, cov.as_slice()),
            first.label,
        )
    }
}
