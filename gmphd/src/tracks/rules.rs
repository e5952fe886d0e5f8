//! The rules a track moves by at each set: observe (take the set's weight and state),
//! coast (count the time below the deletion threshold), confirm (M of N, or one strong
//! set) and delete (sustained low weight, a vanished label, a stale tentative track).
//! See the module documentation of [`crate::tracks`] for why each is as it is.

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::{Anchor, Track, TrackError, TrackManagerConfig};
use crate::gaussian::{GaussianMixture, Label};
use crate::linalg::copy_into;

/// Book-keeping behind one track.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct TrackState {
    pub(super) track: Track,
    /// Total weight in each of the last `N` processed sets, oldest first.
    pub(super) recent_weights: VecDeque<f64>,
    /// Consecutive sets below `delete_threshold`, and when that run started.
    below_count: usize,
    below_since: Option<f64>,
    /// Seconds of pauses in the data since `below_since` (not counted as coasting).
    #[serde(default)]
    paused_s: f64,
    /// See [`Anchor`] (absent in checkpoints written before it existed).
    #[serde(default)]
    pub(super) anchor: Option<Anchor>,
}

/// What the rules need to know of the set being processed.
pub(super) struct SetFacts {
    /// Its time stamp (s).
    pub(super) time_s: f64,
    /// The pause in the data before it (s; 0 when there was none).
    pub(super) pause_s: f64,
    /// Whether it is within `max_coast_s` of the end of the latest pause.
    pub(super) recovering: bool,
}

/// A label's total weight and heaviest component in one intensity.
pub(super) struct LabelSummary<'a> {
    pub(super) weight: f64,
    heaviest_weight: f64,
    pub(super) mean: &'a DVector<f64>,
    cov: &'a DMatrix<f64>,
}

impl TrackState {
    /// A new tentative track from its first hit.
    pub(super) fn new(label: Label, time_s: f64, summary: &LabelSummary<'_>) -> Self {
        Self {
            track: Track {
                label,
                mean: summary.mean.clone(),
                cov: summary.cov.clone(),
                weight: summary.weight,
                first_seen: time_s,
                last_update: time_s,
                confirmed: false,
            },
            recent_weights: VecDeque::from([summary.weight]),
            below_count: 0,
            below_since: None,
            paused_s: 0.0,
            anchor: Some(Anchor {
                time_s,
                mean: summary.mean.clone(),
                cov: summary.cov.clone(),
            }),
        }
    }

    /// Observe: takes the label's weight and heaviest component in this set (`summary`,
    /// `None` when no component carries the label) and, when the set counts for the track,
    /// records the weight in the confirmation window. Returns whether the set counts: the
    /// sensor could see the track, or the label is gone (then it counts as seen with weight
    /// 0, so that the track is deleted in time). A just-created track's first weight is in
    /// its window already (`is_new`).
    pub(super) fn observe(
        &mut self,
        config: &TrackManagerConfig,
        set: &SetFacts,
        summary: Option<&LabelSummary<'_>>,
        is_new: bool,
        in_view: &dyn Fn(&DVector<f64>) -> bool,
    ) -> bool {
        let weight = summary.map_or(0.0, |s| s.weight);
        if let Some(summary) = summary {
            copy_into(&mut self.track.mean, summary.mean);
            copy_into(&mut self.track.cov, summary.cov);
            if summary.weight >= config.delete_threshold {
                set_anchor(&mut self.anchor, set.time_s, summary);
            }
        }
        self.track.weight = weight;
        if weight > config.confirm_threshold {
            self.track.last_update = set.time_s;
        }
        let seen = summary.is_none() || in_view(&self.track.mean);
        if seen && !is_new {
            self.recent_weights.push_back(weight);
            if self.recent_weights.len() > config.confirm_window {
                self.recent_weights.pop_front();
            }
        }
        seen
    }

    /// Coast: counts the sets and seconds the weight has stayed below the deletion
    /// threshold (pauses in the data excluded). An unseen set is neither evidence for the
    /// track nor against it.
    pub(super) fn coast(&mut self, config: &TrackManagerConfig, set: &SetFacts, seen: bool) {
        if !seen {
            return;
        }
        if self.track.weight < config.delete_threshold {
            if self.below_since.is_some() {
                self.paused_s += set.pause_s;
            }
            self.below_count += 1;
            self.below_since.get_or_insert(set.time_s);
        } else {
            self.below_count = 0;
            self.below_since = None;
            self.paused_s = 0.0;
        }
    }

    /// Confirm: whether a tentative track is confirmed by this set: `M` hits among the last
    /// `N` sets, or one seen set heavier than the at-once threshold when the label
    /// `may_confirm_at_once`.
    pub(super) fn confirms(
        &self,
        config: &TrackManagerConfig,
        seen: bool,
        may_confirm_at_once: bool,
    ) -> bool {
        let strong = seen
            && config
                .confirm_at_once_threshold
                .is_some_and(|at_once| self.track.weight > at_once)
            && may_confirm_at_once;
        !self.track.confirmed && (self.hits(config) >= config.confirm_hits || strong)
    }

    /// Delete: whether the track ends with this set: a tentative track without a hit in a
    /// full window, a label no component carries (`carried` false) unless a confirmed track
    /// is recovering from a pause, or a weight below the deletion threshold for `K` sets or
    /// `max_coast_s` seconds.
    pub(super) fn deleted(
        &self,
        config: &TrackManagerConfig,
        set: &SetFacts,
        carried: bool,
    ) -> bool {
        let stale_tentative = !self.track.confirmed
            && self.recent_weights.len() == config.confirm_window
            && self.hits(config) == 0;
        let vanished = !(carried || (self.track.confirmed && set.recovering));
        let sustained_low = self.below_count >= config.delete_after_sets
            || self
                .below_since
                .is_some_and(|since| set.time_s - since - self.paused_s >= config.max_coast_s);
        stale_tentative || vanished || sustained_low
    }

    /// Sets among the recent ones whose weight exceeded the confirmation threshold.
    fn hits(&self, config: &TrackManagerConfig) -> usize {
        self.recent_weights
            .iter()
            .filter(|&&w| w > config.confirm_threshold)
            .count()
    }
}

/// Sets `anchor` to the summary's state at `time_s`, reusing its storage (this runs for
/// every track at every set).
fn set_anchor(anchor: &mut Option<Anchor>, time_s: f64, summary: &LabelSummary<'_>) {
    match anchor {
        Some(a)
            if a.mean.shape() == summary.mean.shape() && a.cov.shape() == summary.cov.shape() =>
        {
            a.time_s = time_s;
            copy_into(&mut a.mean, summary.mean);
            copy_into(&mut a.cov, summary.cov);
        }
        _ => {
            *anchor = Some(Anchor {
                time_s,
                mean: summary.mean.clone(),
                cov: summary.cov.clone(),
            })
        }
    }
}

/// Total weight and heaviest component per label, ascending by label (one sort of the
/// components instead of a map; each label's weights are added in component order).
pub(super) fn summarise(
    intensity: &GaussianMixture,
) -> Result<Vec<(Label, LabelSummary<'_>)>, TrackError> {
    if let Some(bad) = intensity.first_invalid_weight() {
        return Err(TrackError::InvalidWeight {
            label: bad.label.0,
            weight: bad.weight,
        });
    }
    let summaries = intensity
        .indices_by_label()
        .chunk_by(|a, b| a.0 == b.0)
        .map(|group| {
            let first = &intensity.components[group[0].1];
            let mut summary = LabelSummary {
                weight: 0.0,
                heaviest_weight: f64::NEG_INFINITY,
                mean: &first.mean,
                cov: &first.cov,
            };
            for &(_, index) in group {
                let component = &intensity.components[index];
                summary.weight += component.weight;
                if component.weight > summary.heaviest_weight {
                    summary.heaviest_weight = component.weight;
                    summary.mean = &component.mean;
                    summary.cov = &component.cov;
                }
            }
            (group[0].0, summary)
        })
        .collect();
    Ok(summaries)
}
