//! Labelled track management with hysteresis: confirm M-of-N, delete after a
//! sustained low weight.
//!
//! With asynchronous sensors each measurement set updates the intensity on its own
//! (Pham ch. 5.3). When a camera misses an object, or cannot see it, that set
//! multiplies the object's weight by `1 − p_D`; with `p_D = 0.8` a weight of 1
//! drops to 0.2, and a plain per-set extraction (weight > 0.5) loses the object
//! until another sensor sees it again — the track flickers. The manager instead
//! keeps, per label, the label's total weight over the last `N` processed sets and
//!
//! * creates a *tentative* track when the label's weight first exceeds
//!   `confirm_threshold`, and confirms it once that happened in `M` of the last
//!   `N` sets, or at once when one set's weight exceeds `confirm_at_once_threshold` (off by
//!   default; cf. MATLAB `trackerPHD` `ConfirmationThreshold`);
//! * deletes a track only when its weight has stayed below `delete_threshold` for
//!   `K` consecutive sets or for `max_coast_s` seconds, whichever comes first
//!   (cf. `DeletionThreshold`). A pause in the data — an interval between two sets longer
//!   than half of `max_coast_s`, as when the server restarts or the network splits — does
//!   not count toward those seconds: no sensor reported, so nothing spoke against the track.
//!   A track whose label no component carries any more is dropped at once — nothing can
//!   give it mass again — except a confirmed one within `max_coast_s` after a pause: a
//!   pause makes every prediction wide, merging then easily takes a label, and label
//!   association hands the identity on to the object's next birth (see
//!   [`crate::labels::associate_labels`]), so such a track coasts (with weight 0) like any
//!   other. A tentative track is also dropped once none of the last `N` sets exceeded
//!   `confirm_threshold`.
//!
//! A track's state is the mean and covariance of its label's heaviest component
//! in the latest set that still contains the label (during a missed detection
//! that is the predicted state, so the track coasts). For label association the manager
//! also keeps each track's [`Anchor`]: that state in the latest set in which the label's
//! weight was at least `delete_threshold` — below it the heaviest component can be any
//! clutter return's child. All state is serde serialisable so a server can checkpoint it.

use crate::gaussian::{GaussianMixture, Label};
use crate::linalg::copy_into;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, VecDeque};
use thiserror::Error;

/// Why the track manager rejected a configuration or an update.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TrackError {
    /// A configuration value is out of range.
    #[error("invalid track manager configuration: {0}")]
    InvalidConfig(&'static str),
    /// The time stamp is NaN or infinite.
    #[error("time stamp {0} is not finite")]
    NonFiniteTime(f64),
    /// Sets must be processed in time order.
    #[error("time stamp {now} s is earlier than the previous set's {previous} s")]
    TimeWentBackwards {
        /// The previous set's time.
        previous: f64,
        /// The offending time.
        now: f64,
    },
    /// A component weight was NaN, infinite or negative.
    #[error("component with label {label} has invalid weight {weight}")]
    InvalidWeight {
        /// Label of the offending component.
        label: u64,
        /// Its weight.
        weight: f64,
    },
}

/// Thresholds of the track manager.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrackManagerConfig {
    /// A set "hits" a label when the label's total weight exceeds this. Default
    /// 0.5, the usual extraction threshold.
    pub confirm_threshold: f64,
    /// `N`: the number of recent sets looked at for confirmation. Default 4.
    pub confirm_window: usize,
    /// `M`: hits among the last `N` sets that confirm a track. Default 2, so two
    /// sensors seeing the object, or one seeing it twice, confirm it.
    pub confirm_hits: usize,
    /// A single set whose weight for the label exceeds this confirms its track at once,
    /// without waiting for `M` hits (MATLAB `trackerPHD` confirms on one such weight, its
    /// `ConfirmationThreshold`, default 0.8). Only a sensor that sees the track counts.
    /// Default: `None` (off), confirmation by `M` of `N` only.
    #[serde(default)]
    pub confirm_at_once_threshold: Option<f64>,
    /// A label's weight below this counts toward deletion. Default 0.15: above one
    /// miss at `p_D = 0.8` (weight 0.2), below two consecutive misses (0.04).
    pub delete_threshold: f64,
    /// `K`: consecutive sets below `delete_threshold` that delete a track.
    /// Default 6.
    pub delete_after_sets: usize,
    /// Seconds below `delete_threshold` that delete a track even if fewer than `K`
    /// sets arrived (slow sensors). An interval between two sets longer than half of this
    /// is a pause in the data and does not count. Default 2.0 s.
    pub max_coast_s: f64,
}

impl Default for TrackManagerConfig {
    fn default() -> Self {
        Self {
            confirm_threshold: 0.5,
            confirm_window: 4,
            confirm_hits: 2,
            confirm_at_once_threshold: None,
            delete_threshold: 0.15,
            delete_after_sets: 6,
            max_coast_s: 2.0,
        }
    }
}

impl TrackManagerConfig {
    /// Checks that the thresholds are consistent.
    pub fn validate(&self) -> Result<(), TrackError> {
        let invalid = |reason| Err(TrackError::InvalidConfig(reason));
        if !(self.confirm_threshold.is_finite() && self.confirm_threshold > 0.0) {
            return invalid("confirm_threshold must be finite and > 0");
        }
        if !(self.delete_threshold.is_finite() && self.delete_threshold >= 0.0) {
            return invalid("delete_threshold must be finite and >= 0");
        }
        if self.delete_threshold > self.confirm_threshold {
            return invalid("delete_threshold must not exceed confirm_threshold");
        }
        if let Some(at_once) = self.confirm_at_once_threshold {
            if !(at_once.is_finite() && at_once >= self.confirm_threshold) {
                return invalid(
                    "confirm_at_once_threshold must be finite and >= confirm_threshold",
                );
            }
        }
        if self.confirm_hits == 0 || self.confirm_hits > self.confirm_window {
            return invalid("confirm_hits must be in 1..=confirm_window");
        }
        if self.delete_after_sets == 0 {
            return invalid("delete_after_sets must be >= 1");
        }
        if self.max_coast_s.is_nan() || self.max_coast_s <= 0.0 {
            return invalid("max_coast_s must be > 0 (may be infinite)");
        }
        Ok(())
    }
}

/// A labelled track as reported to users.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Track {
    /// The label (identity).
    pub label: Label,
    /// Mean of the label's heaviest component in the latest set containing it.
    pub mean: DVector<f64>,
    /// Covariance of that component.
    pub cov: DMatrix<f64>,
    /// The label's total weight in the latest processed set (0 if absent).
    pub weight: f64,
    /// Time (s) of the set that created the track.
    pub first_seen: f64,
    /// Time (s) of the latest set whose weight exceeded `confirm_threshold`.
    pub last_update: f64,
    /// Whether the track has been confirmed (M of N); tentative otherwise.
    pub confirmed: bool,
}

/// A track's state in the latest set in which its label's weight was at least
/// `delete_threshold`, and that set's time: what a coasting track is predicted from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// Time (s) of the set.
    pub time_s: f64,
    /// Mean of the label's heaviest component then.
    pub mean: DVector<f64>,
    /// Its covariance.
    pub cov: DMatrix<f64>,
}

/// Book-keeping behind one track.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct TrackState {
    track: Track,
    /// Total weight in each of the last `N` processed sets, oldest first.
    recent_weights: VecDeque<f64>,
    /// Consecutive sets below `delete_threshold`, and when that run started.
    below_count: usize,
    below_since: Option<f64>,
    /// Seconds of pauses in the data since `below_since` (not counted as coasting).
    #[serde(default)]
    paused_s: f64,
    /// See [`Anchor`] (absent in checkpoints written before it existed).
    #[serde(default)]
    anchor: Option<Anchor>,
}

/// What one update changed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TrackEvents {
    /// Labels whose tentative track was created in this set.
    pub created: Vec<Label>,
    /// Labels confirmed in this set.
    pub confirmed: Vec<Label>,
    /// Labels whose track was deleted in this set.
    pub deleted: Vec<Label>,
}

/// Per-label track manager; see the module documentation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackManager {
    config: TrackManagerConfig,
    tracks: BTreeMap<Label, TrackState>,
    last_time: Option<f64>,
    /// Time of the first set after the latest pause in the data.
    #[serde(default)]
    resumed_at: Option<f64>,
}

/// A label's total weight and heaviest component in one intensity.
struct LabelSummary<'a> {
    weight: f64,
    heaviest_weight: f64,
    mean: &'a DVector<f64>,
    cov: &'a DMatrix<f64>,
}

impl TrackManager {
    /// A manager with no tracks.
    pub fn new(config: TrackManagerConfig) -> Result<Self, TrackError> {
        config.validate()?;
        Ok(Self {
            config,
            tracks: BTreeMap::new(),
            last_time: None,
            resumed_at: None,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &TrackManagerConfig {
        &self.config
    }

    /// Time (s) of the latest processed set.
    pub fn last_time(&self) -> Option<f64> {
        self.last_time
    }

    /// All tracks, tentative and confirmed, by label.
    pub fn tracks(&self) -> impl Iterator<Item = &Track> {
        self.tracks.values().map(|state| &state.track)
    }

    /// Confirmed tracks, by label.
    pub fn confirmed_tracks(&self) -> impl Iterator<Item = &Track> {
        self.tracks().filter(|track| track.confirmed)
    }

    /// True when `label` has a confirmed track.
    pub fn is_confirmed(&self, label: Label) -> bool {
        self.tracks
            .get(&label)
            .is_some_and(|state| state.track.confirmed)
    }

    /// The [`Anchor`] of `label`'s track.
    pub fn anchor(&self, label: Label) -> Option<&Anchor> {
        self.tracks.get(&label)?.anchor.as_ref()
    }

    /// The label's total weight over its last `N` processed sets, oldest first.
    pub fn recent_weights(&self, label: Label) -> Option<Vec<f64>> {
        let state = self.tracks.get(&label)?;
        Some(state.recent_weights.iter().copied().collect())
    }

    /// Processes the intensity after one measurement set taken at `time_s` by a sensor
    /// that sees every track; see [`TrackManager::update_in_view`].
    pub fn update(
        &mut self,
        time_s: f64,
        intensity: &GaussianMixture,
    ) -> Result<TrackEvents, TrackError> {
        self.update_in_view(time_s, intensity, &|_| true)
    }

    /// Processes the intensity after one measurement set taken at `time_s` by a sensor
    /// that can observe a state `x` when `in_view(x)`.
    ///
    /// A set only counts for a track whose state the sensor could observe: a set of a
    /// camera looking elsewhere neither confirms a track (its weight there is mass that no
    /// measurement contradicted, not evidence — a clutter return's child drifting out of
    /// every view would otherwise be confirmed on it) nor fills its confirmation window,
    /// nor counts toward its deletion. Tracks are created only in view.
    pub fn update_in_view(
        &mut self,
        time_s: f64,
        intensity: &GaussianMixture,
        in_view: &dyn Fn(&DVector<f64>) -> bool,
    ) -> Result<TrackEvents, TrackError> {
        self.update_scoped(time_s, intensity, in_view, &|_| true)
    }

    /// [`TrackManager::update_in_view`], where only labels for which
    /// `may_confirm_at_once(label)` holds can be confirmed on a single set's weight
    /// ([`TrackManagerConfig::confirm_at_once_threshold`]). A caller that knows a label
    /// split off from a confirmed track's — a clutter return beside an object gets its
    /// weight from the object's — excludes it, so that it needs `M` hits like any other.
    pub fn update_scoped(
        &mut self,
        time_s: f64,
        intensity: &GaussianMixture,
        in_view: &dyn Fn(&DVector<f64>) -> bool,
        may_confirm_at_once: &dyn Fn(Label) -> bool,
    ) -> Result<TrackEvents, TrackError> {
        if !time_s.is_finite() {
            return Err(TrackError::NonFiniteTime(time_s));
        }
        if let Some(previous) = self.last_time.filter(|&previous| time_s < previous) {
            return Err(TrackError::TimeWentBackwards {
                previous,
                now: time_s,
            });
        }
        let summaries = summarise(intensity)?;
        let pause_s = self
            .last_time
            .map(|previous| time_s - previous)
            .filter(|&interval| interval > 0.5 * self.config.max_coast_s)
            .unwrap_or(0.0);
        self.last_time = Some(time_s);
        if pause_s > 0.0 {
            self.resumed_at = Some(time_s);
        }
        let config = self.config;
        let recovering = self
            .resumed_at
            .is_some_and(|at| time_s - at < config.max_coast_s);
        let mut events = TrackEvents::default();

        for (label, summary) in &summaries {
            let label = *label;
            if summary.weight > config.confirm_threshold
                && !self.tracks.contains_key(&label)
                && in_view(summary.mean)
            {
                self.tracks.insert(label, new_state(label, time_s, summary));
                events.created.push(label);
            }
        }
        for (&label, state) in &mut self.tracks {
            let summary = summaries
                .binary_search_by_key(&label, |(l, _)| *l)
                .ok()
                .map(|i| &summaries[i].1);
            let weight = summary.map_or(0.0, |s| s.weight);
            if let Some(summary) = summary {
                copy_into(&mut state.track.mean, summary.mean);
                copy_into(&mut state.track.cov, summary.cov);
                if summary.weight >= config.delete_threshold {
                    set_anchor(&mut state.anchor, time_s, summary);
                }
            }
            state.track.weight = weight;
            if weight > config.confirm_threshold {
                state.track.last_update = time_s;
            }
            // A label that no component carries any more has nothing left to be seen or
            // missed: it counts as seen with weight 0, so that it is deleted in time.
            let seen = summary.is_none() || in_view(&state.track.mean);
            let is_new = events.created.contains(&label);
            if seen && !is_new {
                state.recent_weights.push_back(weight);
                if state.recent_weights.len() > config.confirm_window {
                    state.recent_weights.pop_front();
                }
            }
            // An unseen set is neither evidence for the track nor against it.
            if seen && weight < config.delete_threshold {
                if state.below_since.is_some() {
                    state.paused_s += pause_s;
                }
                state.below_count += 1;
                state.below_since.get_or_insert(time_s);
            } else if seen {
                state.below_count = 0;
                state.below_since = None;
                state.paused_s = 0.0;
            }
            let hits = state
                .recent_weights
                .iter()
                .filter(|&&w| w > config.confirm_threshold)
                .count();
            let strong = seen
                && config
                    .confirm_at_once_threshold
                    .is_some_and(|at_once| weight > at_once)
                && may_confirm_at_once(label);
            if !state.track.confirmed && (hits >= config.confirm_hits || strong) {
                state.track.confirmed = true;
                events.confirmed.push(label);
            }
            let stale_tentative = !state.track.confirmed
                && state.recent_weights.len() == config.confirm_window
                && hits == 0;
            // See the module documentation.
            let vanished = summary.is_none() && !(state.track.confirmed && recovering);
            let sustained_low = vanished
                || state.below_count >= config.delete_after_sets
                || state
                    .below_since
                    .is_some_and(|since| time_s - since - state.paused_s >= config.max_coast_s);
            if stale_tentative || sustained_low {
                events.deleted.push(label);
            }
        }
        for label in &events.deleted {
            self.tracks.remove(label);
        }
        Ok(events)
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

/// A new tentative track from its first hit.
fn new_state(label: Label, time_s: f64, summary: &LabelSummary<'_>) -> TrackState {
    TrackState {
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

/// Total weight and heaviest component per label, ascending by label (one sort of the
/// components instead of a map; each label's weights are added in component order).
fn summarise(intensity: &GaussianMixture) -> Result<Vec<(Label, LabelSummary<'_>)>, TrackError> {
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
