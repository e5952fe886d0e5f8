//! The labelled multi-sensor tracker: one [`GmPhdFilter`] plus label continuity (Pham ch. 4)
//! and track confirmation/deletion ([`TrackManager`]), stepped once per measurement set.
//!
//! One step, for a set of one sensor taken at time `t`:
//! 1. predict the intensity to `t` and update it with the sensor's model (sequential
//!    multi-sensor correction: each set's posterior is the next set's prior); a newborn
//!    component's children under different measurements get labels of their own, since
//!    they may be different objects born together;
//! 2. reduce it (prune, merge, cap), remembering the mixture before reduction so that each
//!    estimate's *inherited* labels can be recovered;
//! 3. extract estimates, plus any cluster that descends from an identity no estimate
//!    carries any more ([`report_lost_identities`]: objects that crossed or were born
//!    together), and keep identities continuous by a minimum-total-distance
//!    assignment from the previous step's estimates, predicted to `t`, restricted to the
//!    inherited labels; write the chosen labels back onto the components;
//! 4. feed the labelled intensity to the track manager, which confirms and deletes tracks on
//!    each label's weight over recent sets, so a single sensor's miss does not drop a track.
//!    A label that split off a confirmed track's is never confirmed on one set alone.

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use thiserror::Error;

use crate::error::FilterError;
use crate::extract::{ExtractError, StateExtractor, WeightThresholdExtractor};
use crate::filter::{FilterState, GmPhdFilter};
use crate::gating::chi_square_quantile;
use crate::gaussian::{Label, LabelSource};
use crate::labels::{
    apply_relabelling, associate_labels, inherited_label_sets, report_lost_identities,
    CurrentEstimate, LabelError, PreviousEstimate,
};
use crate::measurement::{Measurement, MeasurementModel};
use crate::reduce::Ancestry;
use crate::tracks::{Track, TrackError, TrackEvents, TrackManager, TrackManagerConfig};

/// Probability mass of a coasting track's predicted position within its reach: a birth
/// inside that gate continues the track's identity ([`PreviousEstimate::reach`]).
const COASTING_REACH_PROBABILITY: f64 = 0.99;

/// Why a tracker step failed. The tracker's state is unchanged when the filter rejected the
/// input (a bad measurement or a time going backwards).
#[derive(Debug, Error)]
pub enum TrackerError {
    /// The filter refused the prediction or update.
    #[error(transparent)]
    Filter(#[from] FilterError),
    /// State extraction failed.
    #[error(transparent)]
    Extract(#[from] ExtractError),
    /// Label association failed.
    #[error(transparent)]
    Labels(#[from] LabelError),
    /// The track manager refused the intensity.
    #[error(transparent)]
    Tracks(#[from] TrackError),
}

/// Settings of the labelled tracker.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrackerConfig {
    /// A label whose mass exceeds this gives an estimate (Vo & Ma: 0.5).
    pub extraction_threshold: f64,
    /// Mahalanobis distance within which a pre-reduction component counts as an ancestor of
    /// an estimate (use the reducer's merge threshold U).
    pub merge_threshold: f64,
    /// Interval assumed before the very first set, so that its prediction has births.
    pub first_interval_s: f64,
    /// Squared Mahalanobis distance beyond which a second heavy component of one label is
    /// reported as a separate object ([`WeightThresholdExtractor::separation_gate`]).
    #[serde(default = "default_separation_gate")]
    pub separation_gate: f64,
    /// Track confirmation and deletion.
    pub tracks: TrackManagerConfig,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        Self {
            extraction_threshold: 0.5,
            merge_threshold: 4.0,
            first_interval_s: 0.1,
            separation_gate: default_separation_gate(),
            tracks: TrackManagerConfig::default(),
        }
    }
}

fn default_separation_gate() -> f64 {
    WeightThresholdExtractor::default().separation_gate
}

/// A labelled estimate of the previous step, kept to carry identities to the next one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct LabelledEstimate {
    label: Label,
    mean: DVector<f64>,
    cov: DMatrix<f64>,
}

/// Everything a checkpoint needs to resume with the same identities.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackerState {
    /// The filter's intensity, time and next label.
    pub filter: FilterState,
    /// The track manager, with each label's recent weights.
    pub tracks: TrackManager,
    /// The previous step's estimates (label continuity).
    previous: Vec<LabelledEstimate>,
    /// The previous estimates' time.
    previous_time: f64,
    /// False until the first set was processed.
    started: bool,
    /// See [`LabelledTracker`]'s field of that name (absent in older checkpoints).
    #[serde(default)]
    split_offs: BTreeSet<Label>,
}

impl TrackerState {
    /// Time of the last processed set, if any.
    pub fn last_time(&self) -> Option<f64> {
        self.started.then_some(self.filter.time)
    }
}

/// The labelled tracker; see the module documentation.
#[derive(Debug)]
pub struct LabelledTracker {
    filter: GmPhdFilter,
    config: TrackerConfig,
    extractor: WeightThresholdExtractor,
    tracks: TrackManager,
    previous: Vec<LabelledEstimate>,
    previous_time: f64,
    started: bool,
    /// Tracked labels that a current estimate took while descending from another, confirmed
    /// track's label too: a clutter return beside an object, or one of two objects that
    /// were merged. They are never confirmed on one set's weight alone
    /// ([`TrackManager::update_scoped`]).
    split_offs: BTreeSet<Label>,
}

impl LabelledTracker {
    /// A tracker around `filter` (whose start time is replaced by the first set's stamp).
    pub fn new(filter: GmPhdFilter, config: TrackerConfig) -> Result<Self, TrackerError> {
        let tracks = TrackManager::new(config.tracks)?;
        Ok(Self {
            filter,
            extractor: WeightThresholdExtractor {
                threshold: config.extraction_threshold,
                separation_gate: config.separation_gate,
                ..WeightThresholdExtractor::default()
            },
            config,
            tracks,
            previous: Vec::new(),
            previous_time: 0.0,
            started: false,
            split_offs: BTreeSet::new(),
        })
    }

    /// The filter (intensity, time, motion model).
    pub fn filter(&self) -> &GmPhdFilter {
        &self.filter
    }

    /// Time of the last processed set, if any.
    pub fn last_time(&self) -> Option<f64> {
        self.started.then(|| self.filter.time())
    }

    /// Confirmed tracks, by label.
    pub fn confirmed_tracks(&self) -> impl Iterator<Item = &Track> {
        self.tracks.confirmed_tracks()
    }

    /// The track manager (all tracks, tentative ones included).
    pub fn track_manager(&self) -> &TrackManager {
        &self.tracks
    }

    /// Processes one sensor's set taken at time `t` (which must not precede the last one).
    pub fn step(
        &mut self,
        t: f64,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
    ) -> Result<TrackEvents, TrackerError> {
        if !self.started {
            let mut state = self.filter.state();
            state.time = t - self.config.first_interval_s;
            self.filter.restore(state)?;
        }
        self.filter.predict_to(t)?;
        let ancestry = self.filter.update_and_reduce(sensor, measurements)?;
        self.started = true;
        self.relabel(t, &ancestry)?;
        let motion = self.filter.motion();
        let in_view = |x: &DVector<f64>| sensor.detection_probability(&motion.position(x)) > 0.0;
        let split_offs = &self.split_offs;
        let events = self
            .tracks
            .update_scoped(t, self.filter.intensity(), &in_view, &|label| {
                !split_offs.contains(&label)
            })?;
        let tracks = &self.tracks;
        self.split_offs
            .retain(|&label| tracks.tracks().any(|track| track.label == label));
        Ok(events)
    }

    /// Label continuity (Pham ch. 4): assignment from the previous estimates to the current.
    fn relabel(&mut self, t: f64, ancestry: &Ancestry) -> Result<(), TrackerError> {
        let mut estimates = self.extractor.extract(self.filter.intensity())?;
        if let Ancestry::Recorded(sets) = ancestry {
            let identities = self
                .previous
                .iter()
                .map(|e| e.label)
                .chain(self.tracks.confirmed_tracks().map(|track| track.label))
                .collect();
            report_lost_identities(
                self.filter.intensity(),
                sets,
                &identities,
                self.config.extraction_threshold,
                &mut estimates,
            );
        }
        let inherited = match ancestry {
            // Pham's l̃ᴱ: the labels merged into the estimate's component, and its own.
            Ancestry::Recorded(sets) => estimates
                .iter()
                .map(|estimate| {
                    let mut set = sets.get(estimate.source).cloned().unwrap_or_default();
                    set.insert(estimate.label, 0.0);
                    set
                })
                .collect(),
            Ancestry::PreReduction(before_reduction) => {
                inherited_label_sets(before_reduction, &estimates, self.config.merge_threshold)?
            }
        };
        let motion = self.filter.motion();
        let dt = (t - self.previous_time).max(0.0);
        let position = |x: &DVector<f64>| DVector::from_column_slice(motion.position(x).as_slice());
        let mut previous = Vec::with_capacity(self.previous.len());
        for estimate in &self.previous {
            let predicted = motion.predict_mean(&estimate.mean, &estimate.cov, dt)?;
            previous.push(PreviousEstimate {
                label: estimate.label,
                predicted: position(&predicted),
                established: self.tracks.is_confirmed(estimate.label),
                reach: 0.0,
            });
        }
        // Confirmed tracks that gave no estimate last time (coasting through misses or a
        // pause in the data) compete too: otherwise the birth that explains the object's next
        // detection better than the weakened track would take it over under a new label.
        // They are predicted from their anchor (the label's heaviest component in the last
        // set in which it had weight enough not to be a clutter return's child) and reach as
        // far as their predicted position's validation gate (`PreviousEstimate::reach`).
        let dims = motion.position_dims();
        let gate = chi_square_quantile(COASTING_REACH_PROBABILITY, dims);
        for track in self.tracks.confirmed_tracks() {
            if self.previous.iter().any(|e| e.label == track.label) {
                continue;
            }
            let (mean, cov, since) = match self.tracks.anchor(track.label) {
                Some(anchor) => (&anchor.mean, &anchor.cov, anchor.time_s),
                None => (&track.mean, &track.cov, self.previous_time),
            };
            let (predicted, cov) = motion.predict(mean, cov, (t - since).max(0.0))?;
            let spread = largest_eigenvalue(&cov, dims);
            previous.push(PreviousEstimate {
                label: track.label,
                predicted: position(&predicted),
                established: true,
                reach: (gate * spread.max(0.0)).sqrt(),
            });
        }
        let descends_from_confirmed: Vec<bool> = inherited
            .iter()
            .map(|set| {
                set.heaviest()
                    .is_some_and(|label| self.tracks.is_confirmed(label))
            })
            .collect();
        let current: Vec<CurrentEstimate> = estimates
            .iter()
            .zip(inherited)
            .map(|(estimate, inherited)| CurrentEstimate {
                mean: position(&estimate.mean),
                weight: estimate.weight,
                inherited,
            })
            .collect();
        let mut source = LabelSource::starting_at(self.filter.next_label());
        let relabelling = associate_labels(&previous, &current, &mut source)?;
        // Relabelled in place rather than on a copy; `apply_relabelling` checks its input
        // before it changes anything, so on error the intensity goes back untouched.
        let mut mixture = self.filter.take_intensity();
        let relabelled = apply_relabelling(&mut mixture, &estimates, &relabelling, &mut source);
        self.filter.set_relabelled_intensity(mixture);
        relabelled?;
        for (&label, descends) in relabelling.labels.iter().zip(descends_from_confirmed) {
            if descends && !self.tracks.is_confirmed(label) {
                self.split_offs.insert(label);
            }
        }
        self.previous = estimates
            .into_iter()
            .zip(&relabelling.labels)
            .map(|(estimate, &label)| LabelledEstimate {
                label,
                mean: estimate.mean,
                cov: estimate.cov,
            })
            .collect();
        self.previous_time = t;
        Ok(())
    }

    /// The state to checkpoint.
    pub fn state(&self) -> TrackerState {
        TrackerState {
            filter: self.filter.state(),
            tracks: self.tracks.clone(),
            previous: self.previous.clone(),
            previous_time: self.previous_time,
            started: self.started,
            split_offs: self.split_offs.clone(),
        }
    }

    /// Resumes from a checkpointed state.
    pub fn restore(&mut self, state: TrackerState) -> Result<(), TrackerError> {
        self.filter.restore(state.filter)?;
        self.tracks = state.tracks;
        self.previous = state.previous;
        self.previous_time = state.previous_time;
        self.started = state.started;
        self.split_offs = state.split_offs;
        Ok(())
    }
}

/// The largest eigenvalue of the leading `dims` × `dims` block of the symmetric `cov`: for the
/// usual 2 or 3 position dimensions, of a fixed-size copy (nalgebra's algorithm either way,
/// so the same value, without the heap).
fn largest_eigenvalue(cov: &DMatrix<f64>, dims: usize) -> f64 {
    let block = cov.view((0, 0), (dims, dims));
    match dims {
        2 => Matrix2::from_fn(|r, c| block[(r, c)])
            .symmetric_eigenvalues()
            .max(),
        3 => Matrix3::from_fn(|r, c| block[(r, c)])
            .symmetric_eigenvalues()
            .max(),
        _ => block.clone_owned().symmetric_eigenvalues().max(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_eigenvalue_is_nalgebras_on_any_size() {
        for dims in 1..=4 {
            for seed in 0..5 {
                let a = DMatrix::from_fn(6, 6, |r, c| ((r * 5 + c * 11 + seed) % 17) as f64 * 0.3);
                let cov = &a * a.transpose();
                let dynamic = cov
                    .view((0, 0), (dims, dims))
                    .clone_owned()
                    .symmetric_eigenvalues()
                    .max();
                assert_eq!(largest_eigenvalue(&cov, dims).to_bits(), dynamic.to_bits());
            }
        }
    }
}
