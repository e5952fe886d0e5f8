//! The engine: admission of incoming sets (`engine/admission.rs`), the timeline that processes
//! them in stamp order at once (rolling back for late ones), counters and the current
//! `TrackSet`/`Status`.
//!
//! Synchronous and driven by the clock its caller passes in, so the live service (wall clock)
//! and `replay` (the largest stamp seen) run exactly the same code.

use std::sync::Arc;
use std::time::Instant;

use protocol::{
    Rejected, SensorDescriptor, SensorId, ServerRole, Site, Status, TrackSet, WireFormat,
    PROTOCOL_VERSION,
};

use crate::config::{IngestConfig, ServerConfig};
use crate::latency::SharedLatency;
use crate::pacing::RollbackPacing;
use crate::processing::{FilterRun, Pending, SetTimeline, Tie};
pub use crate::rejection::Rejection;
use crate::sensors::{Learned, SensorRegistry};
use crate::timeline::{BatchReport, Incoming, Key, TimelineConfig};
use crate::tracker::{Tracker, TrackerState};

mod admission;

/// What one [`Engine::step`] produced.
#[derive(Debug, Default)]
pub struct StepOutput {
    /// The track set after each (re)processed set, in stamp order; after a rollback it starts
    /// with the corrected answers for sets processed before.
    pub tracks: Vec<TrackSet>,
    /// Arrival times (caller's clock) of the sets admitted since the last step that were
    /// processed: their latency ends when `tracks` is published.
    pub arrivals: Vec<f64>,
}

/// Admission, ordering and filtering of measurement sets for one site.
pub struct Engine {
    ingest: IngestConfig,
    site: Site,
    /// True for the live service: sets stamped too far ahead of the clock are refused.
    live: bool,
    started: f64,
    sensors: SensorRegistry,
    /// Admitted sets not processed yet: processed together by the next `step`.
    waiting: Vec<Incoming<Tie, Pending>>,
    /// Late sets waiting for the next rollback.
    pacing: RollbackPacing,
    timeline: SetTimeline,
    tracker: Tracker,
    rejected: Rejected,
    latency: SharedLatency,
    last_tracks: TrackSet,
    track_seq: u64,
    /// Sequence number of the next settled track set (offline replay).
    settled_seq: u64,
}

impl Engine {
    /// An engine for `config`, starting at `now`; `live` enables the future-stamp check.
    pub fn new(config: ServerConfig, now: f64, live: bool) -> anyhow::Result<Self> {
        let site = Site::new(&config.site.name)?;
        let tracker = Tracker::new(&config)?;
        let mut engine = Self {
            last_tracks: empty_tracks(&site, 0, 0.0),
            site,
            live,
            started: now,
            sensors: SensorRegistry::new(),
            waiting: Vec::new(),
            pacing: RollbackPacing::new(
                config.ingest.max_rollback_share,
                config.ingest.max_lateness_s,
                now,
            ),
            timeline: SetTimeline::new(timeline_config(&config.ingest), !live),
            tracker,
            rejected: Rejected::default(),
            latency: SharedLatency::new(1024),
            track_seq: 0,
            settled_seq: 0,
            ingest: config.ingest,
        };
        for (i, descriptor) in config.sensors.into_iter().enumerate() {
            engine
                .learn_descriptor(descriptor, true)
                .map_err(|e| anyhow::anyhow!("configuration key `sensors[{i}]`: {e}"))?;
        }
        Ok(engine)
    }

    /// The site this engine serves.
    pub fn site(&self) -> &Site {
        &self.site
    }

    /// Decodes and learns a published descriptor.
    pub fn admit_descriptor(
        &mut self,
        payload: &[u8],
        format: WireFormat,
    ) -> Result<Learned, Rejection> {
        let descriptor: SensorDescriptor = protocol::decode(payload, format)
            .map_err(|e| self.reject_undecodable(None, e.to_string()))?;
        self.learn_descriptor(descriptor, false)
    }

    /// Validates and learns a descriptor (from the network or the configuration).
    pub fn learn_descriptor(
        &mut self,
        descriptor: SensorDescriptor,
        from_config: bool,
    ) -> Result<Learned, Rejection> {
        let invalid = |reason: String| Rejection::Invalid {
            what: "descriptor",
            sensor: descriptor.sensor.to_string(),
            reason,
        };
        if descriptor.site != self.site {
            self.rejected.invalid += 1;
            return Err(invalid(format!(
                "site {} is not {}",
                descriptor.site, self.site
            )));
        }
        if let Err(e) = descriptor.validate() {
            self.rejected.invalid += 1;
            return Err(invalid(e.to_string()));
        }
        let model = sensor_models::measurement_model(&descriptor).map_err(|e| {
            self.rejected.invalid += 1;
            invalid(e.to_string())
        })?;
        Ok(self
            .sensors
            .learn(descriptor, Arc::from(model), from_config))
    }

    /// Marks a sensor's liveliness.
    pub fn set_alive(&mut self, sensor: &SensorId, alive: bool) {
        self.sensors.set_alive(sensor, alive);
    }

    /// Processes every set admitted since the last step, in stamp order, rolling the filter back
    /// first if one of them is older than what was processed (one rollback for the whole batch;
    /// late sets wait while rollbacks have used up `ingest.max_rollback_share` of the time).
    pub fn step(&mut self, now: f64) -> StepOutput {
        self.step_with(now, false)
    }

    /// Processes everything admitted, late sets included, without waiting for the pacing
    /// (shutdown, end of a replay).
    pub fn flush(&mut self, now: f64) -> StepOutput {
        self.step_with(now, true)
    }

    fn step_with(&mut self, now: f64, force: bool) -> StepOutput {
        let waiting = std::mem::take(&mut self.waiting);
        let newest = self.timeline.newest_key();
        let batch = self.pacing.select(waiting, newest, now, force);
        if batch.is_empty() {
            return StepOutput::default();
        }
        let mut arrivals: Vec<(Key<Tie>, f64)> = batch
            .iter()
            .map(|i| (i.key.clone(), i.item.arrived))
            .collect();
        arrivals.sort_by(|a, b| a.0.cmp(&b.0));
        let mut processed = Vec::with_capacity(batch.len());
        let mut run = FilterRun::new(&mut self.tracker, &self.site);
        let began = Instant::now();
        let report = self.timeline.process_batch(batch, &mut run, |p| {
            processed.push((p.key.clone(), p.output.cloned(), p.fresh));
        });
        if report.rollback_cause.is_some() {
            self.pacing.charge(began.elapsed().as_secs_f64());
        }
        self.count_batch(&report);
        let mut out = StepOutput::default();
        for (key, output, fresh) in processed {
            if fresh {
                self.count_fresh(&key, output.is_some());
                if let Ok(i) = arrivals.binary_search_by(|(k, _)| k.cmp(&key)) {
                    out.arrivals.push(arrivals[i].1);
                }
            }
            if let Some(mut tracks) = output {
                self.track_seq += 1;
                tracks.seq = self.track_seq;
                out.tracks.push(tracks);
            }
        }
        if let Some(latest) = self.timeline.latest_output() {
            self.last_tracks = latest.clone();
            self.last_tracks.seq = self.track_seq;
        }
        out
    }

    fn count_fresh(&mut self, key: &Key<Tie>, used: bool) {
        let (name, _) = &key.tie;
        if !used {
            self.count_invalid(name);
        } else if let Some(sensor) = self.sensors.get_mut(name) {
            sensor.counters.processed += 1;
            let stamp = key.stamp();
            sensor.last_stamp = Some(sensor.last_stamp.map_or(stamp, |s| s.max(stamp)));
        }
    }

    fn count_batch(&mut self, report: &BatchReport<Tie>) {
        if let Some(cause) = &report.rollback_cause {
            if let Some(sensor) = self.sensors.get_mut(&cause.tie.0) {
                sensor.counters.rollbacks += 1;
            }
        }
        for key in &report.reprocessed {
            if let Some(sensor) = self.sensors.get_mut(&key.tie.0) {
                sensor.counters.reprocessed += 1;
            }
        }
        for key in &report.too_late {
            self.count_late(&key.tie.0);
        }
        for key in &report.duplicates {
            tracing::warn!(sensor = %key.tie.0, seq = key.tie.1, "duplicate set dropped");
            self.count_invalid(&key.tie.0);
        }
    }

    /// The final track sets that no late set can change any more, in stamp order and numbered
    /// in that order (offline replay: the answer does not depend on the order sets were read in).
    pub fn take_settled(&mut self) -> Vec<TrackSet> {
        let settled = self.timeline.take_settled();
        self.number_settled(settled)
    }

    /// Settles everything (end of a replay): every remaining final track set, as
    /// [`Engine::take_settled`].
    pub fn settle_all(&mut self) -> Vec<TrackSet> {
        let settled = self.timeline.settle_all();
        self.number_settled(settled)
    }

    fn number_settled(&mut self, mut settled: Vec<TrackSet>) -> Vec<TrackSet> {
        for tracks in &mut settled {
            self.settled_seq += 1;
            tracks.seq = self.settled_seq;
        }
        settled
    }

    /// Where the publisher records each set's latency at publication (reported in `Status`).
    pub fn latency(&self) -> SharedLatency {
        self.latency.clone()
    }

    /// Counts `dropped` sets that never reached the engine because its ingest queue was full
    /// (reported in `Status` as invalid: the server could not take them).
    pub fn count_overflow(&mut self, dropped: u64) {
        self.rejected.invalid += dropped;
    }

    /// The latest track set.
    pub fn tracks(&self) -> &TrackSet {
        &self.last_tracks
    }

    /// The server's health at `now`.
    pub fn status(&self, now: f64) -> Status {
        Status {
            version: PROTOCOL_VERSION,
            site: self.site.clone(),
            uptime_s: (now - self.started).max(0.0),
            stamp: self.last_tracks.stamp,
            components: self.tracker.component_count() as u64,
            tracks: self.last_tracks.tracks.len() as u64,
            sensors: self.sensors.iter().map(|s| s.status()).collect(),
            rejected: self.rejected.clone(),
            latency_ms: self.latency.summary(),
            // The service fills in its role when it answers.
            role: ServerRole::Active,
        }
    }

    /// The filter state to checkpoint.
    pub fn checkpoint(&self) -> TrackerState {
        self.tracker.state()
    }

    /// Restores a checkpointed filter state; sets older than its last stamp count as late.
    pub fn restore(&mut self, state: TrackerState) -> anyhow::Result<()> {
        let last = state.last_time();
        self.tracker.restore(state)?;
        if let Some(stamp) = last {
            self.timeline.reset_at(stamp);
        }
        Ok(())
    }
}

fn timeline_config(ingest: &IngestConfig) -> TimelineConfig {
    TimelineConfig {
        max_lateness_s: ingest.max_lateness_s,
        snapshot_interval_s: ingest.snapshot_interval_s,
    }
}

pub(crate) fn empty_tracks(site: &Site, seq: u64, stamp: f64) -> TrackSet {
    TrackSet {
        version: PROTOCOL_VERSION,
        site: site.clone(),
        seq,
        stamp,
        expected_count: 0.0,
        tracks: Vec::new(),
    }
}
