//! The labelled multi-sensor tracker: one [`GmPhdFilter`] plus label continuity (Pham ch. 4,
//! module `continuity`) and track confirmation/deletion ([`TrackManager`]), stepped once
//! per measurement set.
//!
//! One step, for a set of one sensor taken at time `t`:
//! 1. **predict** the intensity to `t`;
//! 2. **update** it with the sensor's model (sequential multi-sensor correction: each set's
//!    posterior is the next set's prior); a newborn component's children under different
//!    measurements get labels of their own, since they may be different objects born
//!    together;
//! 3. **reduce** it (prune, merge, cap), recording which labels each component inherited;
//! 4. **extract** estimates, plus any cluster that descends from an identity no estimate
//!    carries any more (objects that crossed or were born together);
//! 5. **associate** them with the previous step's estimates, predicted to `t`, by a
//!    minimum-total-distance assignment restricted to the inherited labels, and write the
//!    chosen labels back onto the components;
//! 6. **manage** the tracks: the track manager confirms and deletes tracks on each label's
//!    weight over recent sets, so a single sensor's miss does not drop a track. A label that
//!    split off a confirmed track's is never confirmed on one set alone.

use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use thiserror::Error;

use crate::continuity::{LabelContinuity, LabelledEstimate};
use crate::error::FilterError;
use crate::extract::{ExtractError, WeightThresholdExtractor};
use crate::filter::{FilterState, GmPhdFilter};
use crate::gaussian::Label;
use crate::labels::LabelError;
use crate::measurement::{Measurement, MeasurementModel};
use crate::tracks::{Track, TrackError, TrackEvents, TrackManager, TrackManagerConfig};

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
    /// Labels split off confirmed tracks (module `continuity`; absent in older checkpoints).
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
    continuity: LabelContinuity,
    tracks: TrackManager,
    started: bool,
}

impl LabelledTracker {
    /// A tracker around `filter` (whose start time is replaced by the first set's stamp).
    pub fn new(filter: GmPhdFilter, config: TrackerConfig) -> Result<Self, TrackerError> {
        let tracks = TrackManager::new(config.tracks)?;
        let continuity = LabelContinuity::new(&config, filter.motion().position_dims());
        Ok(Self {
            filter,
            config,
            continuity,
            tracks,
            started: false,
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
            // The first set's prediction covers `first_interval_s`, so that it has births.
            let mut state = self.filter.state();
            state.time = t - self.config.first_interval_s;
            self.filter.restore(state)?;
        }
        self.filter.predict_to(t)?;
        let ancestry = self.filter.update_and_reduce(sensor, measurements)?;
        self.started = true;
        let extracted =
            self.continuity
                .extract(self.filter.intensity(), &ancestry, &self.tracks)?;
        self.continuity
            .associate(t, extracted, &mut self.filter, &self.tracks)?;
        self.manage(t, sensor)
    }

    /// Feeds the labelled intensity of `sensor`'s set at `t` to the track manager.
    fn manage(
        &mut self,
        t: f64,
        sensor: &dyn MeasurementModel,
    ) -> Result<TrackEvents, TrackerError> {
        let motion = self.filter.motion();
        let in_view = |x: &DVector<f64>| sensor.detection_probability(&motion.position(x)) > 0.0;
        let split_offs = &self.continuity.split_offs;
        let events = self
            .tracks
            .update_scoped(t, self.filter.intensity(), &in_view, &|label| {
                !split_offs.contains(&label)
            })?;
        self.continuity.forget_split_offs(&self.tracks);
        Ok(events)
    }

    /// The state to checkpoint.
    pub fn state(&self) -> TrackerState {
        TrackerState {
            filter: self.filter.state(),
            tracks: self.tracks.clone(),
            previous: self.continuity.previous.clone(),
            previous_time: self.continuity.previous_time,
            started: self.started,
            split_offs: self.continuity.split_offs.clone(),
        }
    }

    /// Resumes from a checkpointed state.
    pub fn restore(&mut self, state: TrackerState) -> Result<(), TrackerError> {
        self.filter.restore(state.filter)?;
        self.tracks = state.tracks;
        self.continuity.previous = state.previous;
        self.continuity.previous_time = state.previous_time;
        self.started = state.started;
        self.continuity.split_offs = state.split_offs;
        Ok(())
    }
}
