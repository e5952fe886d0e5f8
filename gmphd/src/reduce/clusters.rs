//! Vo & Ma's clusters: which components the reduction merges.

use nalgebra::DMatrix;

use super::{heaviest_first, rank, PruneMergeCap, Rank};
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::linalg::{robust_cholesky, MahalanobisGate};
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
    pub(super) fn clusters(&self, mixture: &GaussianMixture) -> Clusters {
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
        // candidate's reach. Components are sorted by first coordinate, so a pivot looks only
        // at those within the largest reach of them; the few widest components (beyond the
        // 90th percentile of reach) would make that window wide, so they are kept aside in a
        // list of their own, searched with their own window. Merged components leave the
        // sorted list (see `Unmerged`), so a pivot's window holds only components still to be
        // clustered — all of them later than the pivot, as every earlier one has been a pivot
        // or a member.
        let first = |g: &Gaussian| g.mean.get(0).copied().unwrap_or(f64::NAN);
        let reach: Vec<f64> = kept
            .iter()
            .map(|g| (self.merge_threshold * g.cov.get((0, 0)).copied().unwrap_or(f64::NAN)).sqrt())
            .collect();
        let mut finite_reach: Vec<f64> = reach.iter().copied().filter(|r| r.is_finite()).collect();
        let window = if finite_reach.is_empty() {
            0.0
        } else {
            let at = finite_reach.len() * 9 / 10;
            *finite_reach.select_nth_unstable_by(at, f64::total_cmp).1
        };
        // Only a component whose first coordinate or reach is not finite is tested against
        // every pivot.
        let mut sorted = Vec::with_capacity(kept.len());
        let (mut wide, mut unbounded) = (Vec::new(), Vec::new());
        let mut wide_window = 0.0_f64;
        for (i, g) in kept.iter().enumerate() {
            if !(first(g).is_finite() && reach[i].is_finite()) {
                unbounded.push(i);
            } else if reach[i] <= window {
                sorted.push((first(g), i));
            } else {
                wide.push((first(g), i));
                wide_window = wide_window.max(reach[i]);
            }
        }
        // Distinct pairs: the unstable sort orders them as a stable one would.
        let along_first =
            |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        sorted.sort_unstable_by(along_first);
        wide.sort_unstable_by(along_first);
        let mut position = vec![usize::MAX; kept.len()];
        for (k, &(_, i)) in sorted.iter().enumerate() {
            position[i] = k;
        }
        let mut in_sorted = Unmerged::new(sorted.len());
        let runs = sweep::runs_of_each(&sorted, window);

        // Visited by weight: each component not yet merged is a pivot that takes every
        // later unmerged one within U.
        let mut unmerged = vec![true; kept.len()];
        let mut members = Vec::new();
        let mut candidates = Vec::new();
        let mut scratch = Vec::new();
        let mut clusters = Clusters {
            members: Vec::with_capacity(kept.len()),
            ends: Vec::with_capacity(kept.len()),
        };
        for pivot in 0..kept.len() {
            if !unmerged[pivot] {
                continue;
            }
            let centre = &kept[pivot].mean;
            members.clear();
            members.push(pivot);
            candidates.clear();
            let run = match position[pivot] {
                usize::MAX => sweep::run(&sorted, first(kept[pivot]), window),
                k => {
                    in_sorted.remove(k);
                    runs[k]
                }
            };
            match run {
                Some((start, end)) => {
                    // The probe's test first: it rejects most, and fewer are left to sort.
                    let pivot_probe = &probes[pivot];
                    let mut k = in_sorted.first_from(start);
                    while k < end {
                        let i = sorted[k].1;
                        if !probes[i].outside(pivot_probe) {
                            candidates.push(i);
                        }
                        k = in_sorted.first_from(k + 1);
                    }
                    let later = |i: usize| i > pivot && unmerged[i];
                    if let Some((start, end)) = sweep::run(&wide, first(kept[pivot]), wide_window) {
                        candidates.extend(
                            wide[start..end]
                                .iter()
                                .map(|&(_, i)| i)
                                .filter(|&i| later(i) && !probes[i].outside(pivot_probe)),
                        );
                    }
                    candidates.extend(
                        unbounded
                            .iter()
                            .copied()
                            .filter(|&i| later(i) && !probes[i].outside(pivot_probe)),
                    );
                    // Tested (and merged) in weight order, as a full scan would.
                    candidates.sort_unstable();
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
                let robust = |cov: &DMatrix<f64>| Some(robust_cholesky(cov).unpack());
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
                if position[i] != usize::MAX {
                    in_sorted.remove(position[i]);
                }
            }
            clusters
                .members
                .extend(members.iter().map(|&i| order[i].0 .2));
            clusters.ends.push(clusters.members.len());
        }
        clusters
    }
}

/// The clusters of [`PruneMergeCap::clusters`], one after the other in a single list (most
/// are a single component, which would otherwise take an allocation each).
pub(super) struct Clusters {
    /// Every cluster's members.
    members: Vec<usize>,
    /// Where each cluster ends in `members` (it starts where the previous one ends).
    ends: Vec<usize>,
}

impl Clusters {
    /// The members of cluster `c`.
    pub(super) fn get(&self, c: usize) -> &[usize] {
        let start = c.checked_sub(1).map_or(0, |previous| self.ends[previous]);
        &self.members[start..self.ends[c]]
    }

    /// The clusters in order, each as its members.
    pub(super) fn iter(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        (0..self.ends.len()).map(|c| self.get(c))
    }
}

/// The positions of a list still in it, as they are removed: skipping removed runs costs
/// amortised almost nothing (each position points past its removed successors, and the
/// pointers are shortened as they are followed).
struct Unmerged {
    /// `next[k] == k` while position k is in; otherwise a position after it to look from.
    /// `next[len]` is the end.
    next: Vec<usize>,
}

impl Unmerged {
    /// All of `len` positions in.
    fn new(len: usize) -> Self {
        Self {
            next: (0..=len).collect(),
        }
    }

    /// Takes position `k` out.
    fn remove(&mut self, k: usize) {
        self.next[k] = k + 1;
    }

    /// The first position at or after `k` still in (the length when none is).
    fn first_from(&mut self, mut k: usize) -> usize {
        while self.next[k] != k {
            // Path halving: point each visited position two steps on.
            let after = self.next[self.next[k]];
            self.next[k] = after;
            k = after;
        }
        k
    }
}
