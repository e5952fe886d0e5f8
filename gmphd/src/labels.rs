//! Label continuity by minimum-total-distance assignment (Pham's thesis, ch. 4).
//!
//! After each update, the previous step's estimates, predicted to now, are matched
//! to the current estimates. A current estimate may only take the label of a
//! previous estimate if that label is among the labels it *inherited* — the labels
//! of the components it descends from, which after merging can be several (Pham's
//! hypothesis label set `l̃ᴱ`). Among those allowed pairs the matching has the
//! largest number of pairs and, among those, the least total distance (Hungarian
//! algorithm), so two crossing objects keep their identities even where greedy
//! nearest-neighbour pairing would swap them (Pham Fig. 4.3).
//!
//! A current estimate left unmatched takes the heaviest label of its inherited set
//! that no other estimate took (a new object born from a birth component keeps the
//! birth component's label), or a fresh label when all are taken. Labels in the
//! result are therefore unique.
//!
//! Everything here is a pure function over plain data. [`apply_relabelling`] turns
//! the result into labels on the mixture's components. The inherited label sets come
//! from the reducer, which records each cluster it merges
//! ([`crate::reduce::Ancestry::Recorded`]); for a reducer that does not,
//! [`inherited_label_sets`] derives them from the mixture before reduction.

mod lost;
mod writeback;

pub use lost::report_lost_identities;
pub use writeback::{apply_relabelling, inherited_label_sets};

use crate::assignment::{min_cost_matching_sparse, AssignmentError, SparseCosts};
use crate::gaussian::{Label, LabelSource};
use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use smallvec::{smallvec, SmallVec};
use std::collections::BTreeSet;
use thiserror::Error;

/// Why label association failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LabelError {
    /// A previous and a current estimate (or two estimates) differ in dimension.
    #[error("state vectors differ in dimension: {expected} and {found}")]
    DimensionMismatch {
        /// Dimension of the first vector seen.
        expected: usize,
        /// Dimension of the offending vector.
        found: usize,
    },
    /// A mean had a NaN or infinite entry.
    #[error("an estimate has a non-finite state entry")]
    NonFiniteState,
    /// Two previous estimates carried the same label.
    #[error("label {0} appears on more than one previous estimate")]
    DuplicatePreviousLabel(u64),
    /// A covariance could not be inverted when deriving inherited labels.
    #[error("covariance of the component labelled {0} is not positive definite")]
    SingularCovariance(u64),
    /// An estimate points at a component that is not in the mixture.
    #[error("estimate refers to component {index} but the mixture has {len}")]
    SourceOutOfRange {
        /// The offending component index.
        index: usize,
        /// Number of components in the mixture.
        len: usize,
    },
    /// Estimates and relabelling have different lengths.
    #[error("{estimates} estimates but {labels} new labels")]
    LengthMismatch {
        /// Number of estimates.
        estimates: usize,
        /// Number of labels in the relabelling.
        labels: usize,
    },
    /// The optimal assignment rejected its cost matrix.
    #[error(transparent)]
    Assignment(#[from] AssignmentError),
}

/// The labels a current estimate may inherit, each with the weight it contributed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LabelSet {
    /// Distinct labels with their summed contributing weight; most sets hold one or two
    /// (a component and what merged into it), which are kept without an allocation.
    members: SmallVec<[(Label, f64); 2]>,
}

impl LabelSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// The set of one label.
    pub fn single(label: Label, weight: f64) -> Self {
        Self {
            members: smallvec![(label, weight)],
        }
    }

    /// Adds `weight` to `label`'s contribution, inserting the label if absent.
    pub fn insert(&mut self, label: Label, weight: f64) {
        match self.members.iter_mut().find(|(l, _)| *l == label) {
            Some((_, w)) => *w += weight,
            None => self.members.push((label, weight)),
        }
    }

    /// True when `label` is in the set.
    pub fn contains(&self, label: Label) -> bool {
        self.members.iter().any(|(l, _)| *l == label)
    }

    /// Number of distinct labels.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when the set holds no label.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The labels, in insertion order.
    pub fn labels(&self) -> impl Iterator<Item = Label> + '_ {
        self.members.iter().map(|&(label, _)| label)
    }

    /// The heaviest label (ties: the smaller label), without sorting the set.
    pub fn heaviest(&self) -> Option<Label> {
        self.members
            .iter()
            .min_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)))
            .map(|&(label, _)| label)
    }

    /// Labels with their weights, heaviest first (ties: smaller label first).
    pub fn heaviest_first(&self) -> Vec<(Label, f64)> {
        let mut sorted = self.members.to_vec();
        sorted.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        sorted
    }
}

impl FromIterator<(Label, f64)> for LabelSet {
    fn from_iter<I: IntoIterator<Item = (Label, f64)>>(iter: I) -> Self {
        let mut set = Self::new();
        for (label, weight) in iter {
            set.insert(label, weight);
        }
        set
    }
}

/// A previous step's estimate, predicted to the current time by the caller.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PreviousEstimate {
    /// Its label.
    pub label: Label,
    /// Its state predicted to the current time (`x̂_{k|k-1}`).
    pub predicted: DVector<f64>,
    /// True for an established identity (a confirmed track). Where a current estimate
    /// could continue either an established label or a tentative one, it continues the
    /// established one; see [`associate_labels`].
    #[serde(default)]
    pub established: bool,
    /// For an established identity that is coasting (it gave no estimate last time): how
    /// far from `predicted` (Euclidean, in the coordinates compared) a current estimate
    /// that descends only from tentative or newborn labels may be and still continue this
    /// identity. 0 (the default) for none; see [`associate_labels`].
    #[serde(default)]
    pub reach: f64,
}

/// A current estimate awaiting its label.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurrentEstimate {
    /// Its state `x̂_k`.
    pub mean: DVector<f64>,
    /// Its weight: heavier unmatched estimates choose their inherited label first.
    pub weight: f64,
    /// Labels it may take (the labels of the components it descends from).
    pub inherited: LabelSet,
}

/// Where an estimate's new label came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LabelOrigin {
    /// Matched to the previous estimate with this index; took its label.
    Matched {
        /// Index into the `previous` slice.
        previous: usize,
    },
    /// Unmatched; took the heaviest inherited label no one else took.
    Inherited,
    /// Unmatched and every inherited label was taken; got a fresh label.
    Fresh,
}

/// The result of label association: one label per current estimate, unique.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Relabelling {
    /// `labels[i]` is the new label of current estimate `i`.
    pub labels: Vec<Label>,
    /// `origins[i]` says how `labels[i]` was chosen.
    pub origins: Vec<LabelOrigin>,
}

/// Assigns labels to `current` estimates so that identities continue from
/// `previous` (Pham ch. 4.2–4.3).
///
/// Distances are Euclidean over the full vectors given; pass positions only if
/// velocities should not count. Fresh labels are drawn from `source`.
///
/// Among the matchings with the most pairs, those that continue the most *established*
/// labels ([`PreviousEstimate::established`]) win, and only then the least total distance
/// decides. Without that order, an object seen again after a pause in the data is taken
/// over by a newborn label: its confirmed track has coasted with a covariance of metres,
/// so the birth at its first new detection is nearer, and when the two components merge
/// the nearer, tentative label would win and the person's identity would change.
///
/// A coasting established identity may also continue into a current estimate it is not
/// an ancestor of, if that estimate descends only from tentative or newborn labels and
/// lies within the identity's [`reach`](PreviousEstimate::reach): after a pause, or a run
/// of misses, the object's mass can be gone from its track (merged into a wide component,
/// or decayed), and the birth at its next detection is the same object, not a new one.
pub fn associate_labels(
    previous: &[PreviousEstimate],
    current: &[CurrentEstimate],
    source: &mut LabelSource,
) -> Result<Relabelling, LabelError> {
    check_states(
        previous
            .iter()
            .map(|p| &p.predicted)
            .chain(current.iter().map(|c| &c.mean)),
    )?;
    let rows = rows_by_label(previous)?;
    let costs = SparseCosts::new(
        previous.len(),
        current.len(),
        allowed_pairs(previous, current, &rows),
    )?;
    let mut labels: Vec<Option<Label>> = vec![None; current.len()];
    let mut origins = vec![LabelOrigin::Fresh; current.len()];
    let mut taken = BTreeSet::new();
    for pair in min_cost_matching_sparse(&costs) {
        labels[pair.col] = Some(previous[pair.row].label);
        origins[pair.col] = LabelOrigin::Matched { previous: pair.row };
        taken.insert(previous[pair.row].label);
    }
    label_unmatched(current, &mut labels, &mut origins, &mut taken, source);
    Ok(Relabelling {
        labels: labels.into_iter().flatten().collect(),
        origins,
    })
}

/// The previous labels, sorted, with their rows (looked up by binary search); an error
/// for a repeated label (the one repeated first in `previous`'s order).
fn rows_by_label(previous: &[PreviousEstimate]) -> Result<Vec<(Label, usize)>, LabelError> {
    let mut rows: Vec<(Label, usize)> = previous.iter().map(|p| p.label).zip(0..).collect();
    rows.sort_unstable();
    if let Some(dup) = rows
        .windows(2)
        .filter(|pair| pair[0].0 == pair[1].0)
        .min_by_key(|pair| pair[1].1)
    {
        return Err(LabelError::DuplicatePreviousLabel(dup[0].0 .0));
    }
    Ok(rows)
}

/// (previous j, current i, cost) of each pair the matching may choose.
///
/// Pham (4.2): an edge exists only where the previous label is inherited — or where a
/// coasting established identity reaches an estimate of newborn or tentative descent. Only
/// allowed pairs are visited: each estimate's inherited labels, looked up among the
/// previous labels (`rows`), and the few coasting identities that may reach. The cost is
/// the distance, plus, for a pair continuing a tentative label, more than any total
/// distance, so that fewer tentative (more established) continuations always win; see
/// [`associate_labels`].
fn allowed_pairs(
    previous: &[PreviousEstimate],
    current: &[CurrentEstimate],
    rows: &[(Label, usize)],
) -> Vec<(usize, usize, f64)> {
    let row_of = |label: Label| label_position(rows, label).map(|k| rows[k].1);
    let newborn = |c: &CurrentEstimate| {
        !c.inherited
            .labels()
            .any(|label| row_of(label).is_some_and(|j| previous[j].established))
    };
    let reaching: Vec<usize> = (0..previous.len())
        .filter(|&j| previous[j].established && previous[j].reach > 0.0)
        .collect();
    let mut allowed = Vec::with_capacity(current.len() + reaching.len());
    for (i, to) in current.iter().enumerate() {
        let first = allowed.len();
        for j in to.inherited.labels().filter_map(row_of) {
            allowed.push((j, i, euclidean(&to.mean, &previous[j].predicted)));
        }
        if newborn(to) {
            for &j in &reaching {
                let from = &previous[j];
                let d = euclidean(&to.mean, &from.predicted);
                let listed = allowed[first..].iter().any(|&(row, _, _)| row == j);
                if !listed && d <= from.reach {
                    allowed.push((j, i, d));
                }
            }
        }
    }
    let longest = allowed.iter().fold(0.0_f64, |a, &(_, _, d)| a.max(d));
    let tentative_cost = 1.0 + longest * previous.len().min(current.len()) as f64;
    for (j, _, d) in &mut allowed {
        if !previous[*j].established {
            *d += tentative_cost;
        }
    }
    allowed
}

/// Labels the estimates the matching left without one, heaviest first: the heaviest
/// inherited label no one took, or a fresh one from `source`.
fn label_unmatched(
    current: &[CurrentEstimate],
    labels: &mut [Option<Label>],
    origins: &mut [LabelOrigin],
    taken: &mut BTreeSet<Label>,
    source: &mut LabelSource,
) {
    let mut unmatched: Vec<usize> = (0..current.len())
        .filter(|&i| labels[i].is_none())
        .collect();
    unmatched.sort_by(|&a, &b| {
        current[b]
            .weight
            .total_cmp(&current[a].weight)
            .then(a.cmp(&b))
    });
    for i in unmatched {
        let inherited = current[i]
            .inherited
            .heaviest_first()
            .into_iter()
            .map(|(label, _)| label)
            .find(|label| !taken.contains(label));
        let label = match inherited {
            Some(label) => {
                origins[i] = LabelOrigin::Inherited;
                label
            }
            None => fresh_unused(source, |label| taken.contains(&label)),
        };
        taken.insert(label);
        labels[i] = Some(label);
    }
}

/// |a − b| without allocating (the vectors have one dimension, checked by the caller).
fn euclidean(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// Where `label` is in `sorted` (ascending by label), by binary search: the lookups of one
/// set are among a few dozen labels, where a sorted vector does better than a tree.
fn label_position<T>(sorted: &[(Label, T)], label: Label) -> Option<usize> {
    sorted.binary_search_by_key(&label, |(l, _)| *l).ok()
}

/// A fresh label that is not already in use (a restored source could lag behind).
fn fresh_unused(source: &mut LabelSource, taken: impl Fn(Label) -> bool) -> Label {
    loop {
        let label = source.fresh();
        if !taken(label) {
            return label;
        }
    }
}

/// Checks that all vectors share one dimension and are finite.
fn check_states<'a>(states: impl Iterator<Item = &'a DVector<f64>>) -> Result<(), LabelError> {
    let mut expected = None;
    for state in states {
        let dim = *expected.get_or_insert(state.len());
        if state.len() != dim {
            return Err(LabelError::DimensionMismatch {
                expected: dim,
                found: state.len(),
            });
        }
        if state.iter().any(|v| !v.is_finite()) {
            return Err(LabelError::NonFiniteState);
        }
    }
    Ok(())
}
