//! Vo & Ma's clusters: which components the reduction merges.

use nalgebra::DMatrix;

use super::{heaviest_first, rank, PruneMergeCap, Rank};
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::linalg::{lower_factor, robust_cholesky, MahalanobisGate};
use crate::sweep;

/// Leading coordinates a [`Probe`] holds (the position of a 3-D state).
const PROBE_DIMS: usize = 3;

/// What the first test of the merge gate reads of a component, copied next to the others':
/// testing a pivot against its candidates then walks one array instead of three heap
/// blocks per candidate (its `Gaussian`, mean and covariance), most candidates failing here.
struct Probe {
    /// The leading coordinates of the mean.
    mean: [f64; PROBE_DIMS],
    /// U · P_kk for them.
    reach_sq: [f64; PROBE_DIMS],
    dims: usize,
}

impl Probe {
    fn new(g: &Gaussian, merge_threshold: f64) -> Self {
        let dims = g.dim().min(PROBE_DIMS);
        let mut probe = Self {
            mean: [0.0; PROBE_DIMS],
            reach_sq: [0.0; PROBE_DIMS],
            dims,
        };
        for k in 0..dims {
            probe.mean[k] = g.mean[k];
            probe.reach_sq[k] = merge_threshold * g.cov[(k, k)];
        }
        probe
    }

    /// True when one leading coordinate alone puts this candidate outside the merge gate
    /// around `pivot` — the first test of [`MahalanobisGate::contains`], computed the same
    /// way, so the outcome is the same with or without it.
    fn outside(&self, pivot: &Probe) -> bool {
        (0..self.dims.min(pivot.dims)).any(|k| {
            let d = self.mean[k] - pivot.mean[k];
            d * d > self.reach_sq[k]
        })
    }
}

impl PruneMergeCap {
    /// Vo & Ma's clusters: indices into `mixture`, one cluster per reduced component in
    /// pivot (weight) order, each heaviest member first. Pruned components are in none.
    pub(super) fn clusters(&self, mixture: &GaussianMixture) -> Vec<Vec<usize>> {
        let mut order: Vec<(Rank, &Gaussian)> = mixture
            .iter()
            .enumerate()
            .filter(|(_, g)| g.weight > self.prune_threshold && g.weight.is_finite())
            .map(|(i, g)| (rank(i, g), g))
            .collect();
        // Ranks are distinct, so an unstable sort orders them as a stable one would.
        order.sort_unstable_by(|a, b| heaviest_first(&a.0, &b.0));
        let kept: Vec<&Gaussian> = order.iter().map(|(_, g)| *g).collect();
        let probes: Vec<Probe> = kept
            .iter()
            .map(|g| Probe::new(g, self.merge_threshold))
            .collect();
        // Vo & Ma measure the distance with the candidate's own covariance P_i.
        let mut gates = vec![MahalanobisGate::default(); kept.len()];
        // The gate fails when the first coordinate alone is farther than √(U P_i,00), the
        // candidate's reach. So a pivot need only look at the candidates whose reach along
        // the first coordinate covers it: stabbed into every component's first coordinate
        // at once ([`sweep`]), listed in ascending (weight) order.
        let first = |g: &Gaussian| g.mean.get(0).copied().unwrap_or(f64::NAN);
        let queries: Vec<Option<f64>> = kept
            .iter()
            .map(|g| Some(first(g)).filter(|x| x.is_finite()))
            .collect();
        let reach = kept.iter().map(|g| {
            let variance = g.cov.get((0, 0)).copied().unwrap_or(f64::NAN);
            (first(g), (self.merge_threshold * variance).sqrt())
        });
        let reaching = sweep::IntervalHits::build(&queries, reach);

        // Visited by weight: each component not yet merged is a pivot that takes every
        // later unmerged one within U.
        let mut unmerged = vec![true; kept.len()];
        let mut members = Vec::new();
        let mut candidates = Vec::new();
        let mut scratch = Vec::new();
        let mut clusters = Vec::new();
        for pivot in 0..kept.len() {
            if !unmerged[pivot] {
                continue;
            }
            let centre = &kept[pivot].mean;
            members.clear();
            members.push(pivot);
            candidates.clear();
            match queries[pivot] {
                Some(_) => {
                    // The probe's test first: it rejects most.
                    let pivot_probe = &probes[pivot];
                    candidates.extend(
                        reaching.hits(pivot).iter().copied().filter(|&i| {
                            i > pivot && unmerged[i] && !probes[i].outside(pivot_probe)
                        }),
                    );
                }
                // A centre off the index (not finite): every later component.
                None => candidates.extend(pivot + 1..kept.len()),
            }
            for &i in &candidates {
                if !unmerged[i] {
                    continue;
                }
                if probes[i].outside(&probes[pivot]) {
                    // (Only the full scan of a centre off the index gets here untested.)
                    continue;
                }
                let (candidate, gate) = (kept[i], &mut gates[i]);
                let robust = |cov: &DMatrix<f64>| {
                    lower_factor(cov).or_else(|| Some(robust_cholesky(cov).unpack()))
                };
                if candidate.dim() == centre.len()
                    && gate.contains(
                        &candidate.cov,
                        &candidate.mean,
                        centre,
                        self.merge_threshold,
                        &mut scratch,
                        robust,
                    ) == Some(true)
                {
                    members.push(i);
                }
            }
            for &i in &members {
                unmerged[i] = false;
            }
            clusters.push(members.iter().map(|&i| order[i].0 .2).collect());
        }
        clusters
    }
}
