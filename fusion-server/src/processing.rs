//! What the timeline drives in the server: the site's tracker, one measurement set at a time.

use std::sync::Arc;

use gmphd::MeasurementModel;
use protocol::{MeasurementSet, SensorId, Site, TrackSet};

use crate::engine::empty_tracks;
use crate::timeline::{Processor, Timeline};
use crate::tracker::{Tracker, TrackerState};

/// Orders sets with equal stamps: by sensor, then by the sensor's `seq` (never by arrival, so
/// the order of processing does not depend on the network).
pub type Tie = (SensorId, u64);

/// The timeline of the server: sets, the track set after each, snapshots of the tracker.
pub type SetTimeline = Timeline<Tie, Pending, TrackSet, TrackerState>;

/// An admitted set.
#[derive(Debug)]
pub struct Pending {
    /// The validated set.
    pub set: MeasurementSet,
    /// The model of the sensor's descriptor the set was admitted under. A set processed again after
    /// a rollback is read with it, not with a descriptor the sensor announced since, so that the
    /// result does not depend on when the new descriptor arrived between sets of one instant.
    pub model: Arc<dyn MeasurementModel>,
    /// Arrival time on the engine's clock (for latency).
    pub arrived: f64,
}

/// The tracker with what it needs to process a set: the site.
pub struct FilterRun<'a> {
    tracker: &'a mut Tracker,
    site: &'a Site,
}

impl<'a> FilterRun<'a> {
    /// Processing with `tracker`, for `site`.
    pub fn new(tracker: &'a mut Tracker, site: &'a Site) -> Self {
        Self { tracker, site }
    }
}

impl Processor<Pending> for FilterRun<'_> {
    type State = TrackerState;
    type Output = TrackSet;

    fn snapshot(&self) -> TrackerState {
        self.tracker.state()
    }

    fn restore(&mut self, state: &TrackerState) {
        // The state came from this tracker, so it always fits; an error would be a bug.
        if let Err(e) = self.tracker.restore(state.clone()) {
            tracing::error!(error = %e, "restoring a snapshot of the tracker failed");
        }
    }

    /// The track set after `pending` (its `seq` is left 0: the engine numbers what it publishes).
    fn process(&mut self, pending: &Pending) -> Option<TrackSet> {
        let set = &pending.set;
        match self.tracker.process(set.stamp, pending.model.as_ref(), set) {
            Ok(tracks) => {
                let mut out = empty_tracks(self.site, 0, set.stamp);
                out.expected_count = self.tracker.expected_count();
                out.tracks = tracks;
                Some(out)
            }
            Err(e) => {
                tracing::warn!(sensor = %set.sensor, error = %e, "set not processed");
                None
            }
        }
    }
}
