//! Label continuity of an estimated track set against ground truth (Pham ch. 4.4).
//!
//! Each step, every true object is associated with at most one labelled estimate
//! (optimal assignment within a cut-off distance). Over a run we count, per true
//! object, the distinct labels it was associated with — Pham's "mean number of
//! labels for tracks", 1 when identities never change — and the label switches:
//! steps where a truth's label differs from the label it last had.

use super::MetricError;
use crate::assignment::{min_cost_matching, CostMatrix};
use crate::gaussian::Label;
use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// What one true object has been associated with so far.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
struct TruthHistory {
    labels: BTreeSet<Label>,
    last: Option<Label>,
}

/// Accumulates (truth id, estimate label) associations over the steps of a run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LabelContinuity {
    truths: BTreeMap<u64, TruthHistory>,
    switches: usize,
}

impl LabelContinuity {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records that true object `truth_id` was estimated by `label` this step.
    pub fn record(&mut self, truth_id: u64, label: Label) {
        let history = self.truths.entry(truth_id).or_default();
        if history.last.is_some_and(|last| last != label) {
            self.switches += 1;
        }
        history.last = Some(label);
        history.labels.insert(label);
    }

    /// Associates this step's truths and estimates and records the pairs.
    ///
    /// The association is the maximum-cardinality, minimum-total-distance matching
    /// among pairs closer than `cutoff` (Euclidean, over the given vectors). Returns
    /// the recorded `(truth id, label)` pairs.
    pub fn associate_step(
        &mut self,
        truths: &[(u64, DVector<f64>)],
        estimates: &[(Label, DVector<f64>)],
        cutoff: f64,
    ) -> Result<Vec<(u64, Label)>, MetricError> {
        if !(cutoff.is_finite() && cutoff > 0.0) {
            return Err(MetricError::InvalidCutoff(cutoff));
        }
        super::check_points(
            truths
                .iter()
                .map(|t| &t.1)
                .chain(estimates.iter().map(|e| &e.1)),
        )?;
        let costs = CostMatrix::from_fn(truths.len(), estimates.len(), |i, j| {
            let distance = (&truths[i].1 - &estimates[j].1).norm();
            (distance < cutoff).then_some(distance)
        })?;
        let pairs: Vec<(u64, Label)> = min_cost_matching(&costs)
            .into_iter()
            .map(|pair| (truths[pair.row].0, estimates[pair.col].0))
            .collect();
        for &(truth_id, label) in &pairs {
            self.record(truth_id, label);
        }
        Ok(pairs)
    }

    /// Mean over true objects (those associated at least once) of the number of
    /// distinct labels each was given; `None` before any association.
    pub fn mean_labels_per_track(&self) -> Option<f64> {
        if self.truths.is_empty() {
            return None;
        }
        let total: usize = self.truths.values().map(|h| h.labels.len()).sum();
        Some(total as f64 / self.truths.len() as f64)
    }

    /// Number of times a true object's label differed from its previous label.
    pub fn label_switches(&self) -> usize {
        self.switches
    }

    /// Number of true objects associated at least once.
    pub fn tracks_seen(&self) -> usize {
        self.truths.len()
    }

    /// Total distinct labels summed over true objects (numerator of the mean), so
    /// accumulators of several runs can be pooled.
    pub fn total_labels(&self) -> usize {
        self.truths.values().map(|h| h.labels.len()).sum()
    }
}
