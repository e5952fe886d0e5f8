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

mod config;
mod rules;

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::gaussian::{GaussianMixture, Label};
use rules::{summarise, SetFacts, TrackState};

pub use config::{TrackError, TrackManagerConfig};

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
    ///
    /// Each set creates the tracks of labels heavy enough in view, then moves every track
    /// through its rules (module `tracks::rules`): observe, coast, confirm, delete.
    pub fn update_scoped(
        &mut self,
        time_s: f64,
        intensity: &GaussianMixture,
        in_view: &dyn Fn(&DVector<f64>) -> bool,
        may_confirm_at_once: &dyn Fn(Label) -> bool,
    ) -> Result<TrackEvents, TrackError> {
        // Both checked before anything changes: a rejected update leaves the state as it was.
        let pause_s = self.pause_before(time_s)?;
        let summaries = summarise(intensity)?;
        self.last_time = Some(time_s);
        if pause_s > 0.0 {
            self.resumed_at = Some(time_s);
        }
        let config = self.config;
        let set = SetFacts {
            time_s,
            pause_s,
            recovering: self
                .resumed_at
                .is_some_and(|at| time_s - at < config.max_coast_s),
        };
        let mut events = TrackEvents::default();
        for (label, summary) in &summaries {
            if summary.weight > config.confirm_threshold
                && !self.tracks.contains_key(label)
                && in_view(summary.mean)
            {
                self.tracks
                    .insert(*label, TrackState::new(*label, time_s, summary));
                events.created.push(*label);
            }
        }
        for (&label, state) in &mut self.tracks {
            let summary = summaries
                .binary_search_by_key(&label, |(l, _)| *l)
                .ok()
                .map(|i| &summaries[i].1);
            let is_new = events.created.contains(&label);
            let seen = state.observe(&config, &set, summary, is_new, in_view);
            state.coast(&config, &set, seen);
            if state.confirms(&config, seen, may_confirm_at_once(label)) {
                state.track.confirmed = true;
                events.confirmed.push(label);
            }
            if state.deleted(&config, &set, summary.is_some()) {
                events.deleted.push(label);
            }
        }
        for label in &events.deleted {
            self.tracks.remove(label);
        }
        Ok(events)
    }

    /// Checks `time_s` against the previous set's; returns the pause in the data before this
    /// set (0 when there was none).
    fn pause_before(&self, time_s: f64) -> Result<f64, TrackError> {
        if !time_s.is_finite() {
            return Err(TrackError::NonFiniteTime(time_s));
        }
        if let Some(previous) = self.last_time.filter(|&previous| time_s < previous) {
            return Err(TrackError::TimeWentBackwards {
                previous,
                now: time_s,
            });
        }
        let pause_s = self
            .last_time
            .map(|previous| time_s - previous)
            .filter(|&interval| interval > 0.5 * self.config.max_coast_s)
            .unwrap_or(0.0);
        Ok(pause_s)
    }
}
