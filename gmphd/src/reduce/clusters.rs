//! Vo & Ma's clusters: which components the reduction merges.

use nalgebra::DMatrix;

use super::{heaviest_first, rank, PruneMergeCap, Rank};
use crate::activity::MERGE_ACTIVITY_GAP;
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
    ///
    /// The loop of [`crate::reference::prune_merge_cap`]: each component not yet merged, by
    /// weight, is a pivot that takes every later unmerged one within U — but a pivot meets
    /// only the candidates a [`MergeIndex`] finds near it, and most of those fail a first
    /// test on the leading coordinates ([`Probe`]) before the full distance is computed.
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
        let mut index = MergeIndex::build(&kept, self.merge_threshold);
        // Vo & Ma measure the distance with the candidate's own covariance P_i.
        let mut gates = vec![MahalanobisGate::default(); kept.len()];
        let mut unmerged = vec![true; kept.len()];
        let (mut members, mut candidates, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
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
            index.candidates(pivot, &unmerged, &mut candidates);
            for &i in &candidates {
                // (Only the full scan of a centre off the index gets here untested by the
                // probe.)
                if !unmerged[i] || index.probes[i].outside(&index.probes[pivot]) {
                    continue;
                }
                let (candidate, gate) = (kept[i], &mut gates[i]);
                let robust = |cov: &DMatrix<f64>| Some(robust_cholesky(cov).unpack());
                // Pasha et al. merge within a mode only (see `crate::activity`).
                let same_mode =
                    (candidate.activity - kept[pivot].activity).abs() <= MERGE_ACTIVITY_GAP;
                let within = candidate.dim() == centre.len()
                    && same_mode
                    && gate.contains(
                        &candidate.cov,
                        &candidate.mean,
                        centre,
                        self.merge_threshold,
                        &mut scratch,
                        robust,
                    ) == Some(true);
                if within {
                    members.push(i);
                }
            }
            for &i in &members {
                unmerged[i] = false;
                index.remove(i);
            }
            clusters
                .members
                .extend(members.iter().map(|&i| order[i].0 .2));
            clusters.ends.push(clusters.members.len());
        }
        clusters
    }
}

/// Where a pivot finds its merge candidates without testing every later component.
///
/// The gate fails when the first coordinate alone is farther than √(U P_i,00), the
/// candidate's reach. Components are sorted by first coordinate, so a pivot looks only at
/// those within the largest reach of them; the few widest components (beyond the 90th
/// percentile of reach) would make that window wide, so they are kept aside in a list of
/// their own, searched with their own window. Merged components leave the sorted list
/// (see [`Unmerged`]), so a pivot's window holds only components still to be clustered —
/// all of them later than the pivot, as every earlier one has been a pivot or a member.
/// Only a component whose first coordinate or reach is not finite is tested against every
/// pivot.
struct MergeIndex {
    probes: Vec<Probe>,
    /// First coordinate of each kept component.
    first: Vec<f64>,
    /// (first coordinate, index) of the components of ordinary reach, sorted.
    sorted: Vec<(f64, usize)>,
    window: f64,
    /// Each sorted component's run of neighbours within `window`.
    runs: Vec<Option<(usize, usize)>>,
    /// Position of each component in `sorted` (`usize::MAX`: not there).
    position: Vec<usize>,
    in_sorted: Unmerged,
    /// The widest components, sorted likewise, and their largest reach.
    wide: Vec<(f64, usize)>,
    wide_window: f64,
    unbounded: Vec<usize>,
}

impl MergeIndex {
    /// The index of the `kept` components (in pivot order) for the merge threshold U.
    fn build(kept: &[&Gaussian], merge_threshold: f64) -> Self {
        let probes = kept
            .iter()
            .map(|g| Probe::new(g, merge_threshold))
            .collect();
        let first: Vec<f64> = kept
            .iter()
            .map(|g| g.mean.get(0).copied().unwrap_or(f64::NAN))
            .collect();
        let reach: Vec<f64> = kept
            .iter()
            .map(|g| (merge_threshold * g.cov.get((0, 0)).copied().unwrap_or(f64::NAN)).sqrt())
            .collect();
        let mut finite_reach: Vec<f64> = reach.iter().copied().filter(|r| r.is_finite()).collect();
        let window = if finite_reach.is_empty() {
            0.0
        } else {
            let at = finite_reach.len() * 9 / 10;
            *finite_reach.select_nth_unstable_by(at, f64::total_cmp).1
        };
        let mut sorted = Vec::with_capacity(kept.len());
        let (mut wide, mut unbounded) = (Vec::new(), Vec::new());
        let mut wide_window = 0.0_f64;
        for i in 0..kept.len() {
            if !(first[i].is_finite() && reach[i].is_finite()) {
                unbounded.push(i);
            } else if reach[i] <= window {
                sorted.push((first[i], i));
            } else {
                wide.push((first[i], i));
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
        Self {
            probes,
            in_sorted: Unmerged::new(sorted.len()),
            runs: sweep::runs_of_each(&sorted, window),
            first,
            sorted,
            window,
            position,
            wide,
            wide_window,
            unbounded,
        }
    }

    /// Fills `candidates` with the unmerged components after `pivot` that may lie within
    /// its merge gate, ascending (so tested, and merged, in weight order, as a full scan
    /// would); takes the pivot out of the sorted list.
    fn candidates(&mut self, pivot: usize, unmerged: &[bool], candidates: &mut Vec<usize>) {
        candidates.clear();
        let run = match self.position[pivot] {
            usize::MAX => sweep::run(&self.sorted, self.first[pivot], self.window),
            k => {
                self.in_sorted.remove(k);
                self.runs[k]
            }
        };
        let Some((start, end)) = run else {
            // A centre off the index (not finite): every later component.
            candidates.extend(pivot + 1..unmerged.len());
            return;
        };
        // The probe's test first: it rejects most, and fewer are left to sort.
        let probes = &self.probes;
        let near = |i: usize| !probes[i].outside(&probes[pivot]);
        let mut k = self.in_sorted.first_from(start);
        while k < end {
            let i = self.sorted[k].1;
            if near(i) {
                candidates.push(i);
            }
            k = self.in_sorted.first_from(k + 1);
        }
        let later = |i: usize| i > pivot && unmerged[i];
        if let Some((start, end)) = sweep::run(&self.wide, self.first[pivot], self.wide_window) {
            let wide = self.wide[start..end].iter().map(|&(_, i)| i);
            candidates.extend(wide.filter(|&i| later(i) && near(i)));
        }
        let unbounded = self.unbounded.iter().copied();
        candidates.extend(unbounded.filter(|&i| later(i) && near(i)));
        candidates.sort_unstable();
    }

    /// Takes merged component `i` out of the sorted list.
    fn remove(&mut self, i: usize) {
        if self.position[i] != usize::MAX {
            self.in_sorted.remove(self.position[i]);
        }
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
