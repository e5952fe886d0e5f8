//! The engine: admission of incoming sets, the reorder buffer, the filter, counters and the
//! current `TrackSet`/`Status`.
//!
//! Synchronous and driven by the clock its caller passes in, so the live service (wall clock)
//! and `replay` (the largest stamp seen) run exactly the same code.

use std::sync::Arc;

use protocol::{
    LatencyMs, MeasurementSet, Rejected, SensorDescriptor, SensorId, Site, Status, TrackSet,
    WireFormat, PROTOCOL_VERSION,
};
use thiserror::Error;

use crate::config::ServerConfig;
use crate::latency::LatencyWindow;
use crate::reorder::{Refused, ReorderBuffer};
use crate::sensors::{Learned, SensorRegistry};
use crate::tracker::{Tracker, TrackerState};

/// Why an incoming set or descriptor was not admitted. Each is counted in `Status`.
#[derive(Debug, Error)]
pub enum Rejection {
    /// The payload could not be decoded.
    #[error("undecodable payload: {0}")]
    Undecodable(String),
    /// The set or descriptor broke a validation rule.
    #[error("invalid {what} from {sensor}: {reason}")]
    Invalid {
        /// `set` or `descriptor`.
        what: &'static str,
        /// The sensor it named (or the key's sensor).
        sensor: String,
        /// The rule it broke.
        reason: String,
    },
    /// No descriptor is known for the sensor; `.1` counts its sets so far (ask for the
    /// descriptor on the first one).
    #[error("set from unknown sensor {0} (set {1} without a descriptor)")]
    UnknownSensor(SensorId, u64),
    /// Older than what was already processed.
    #[error("late set from {sensor}: stamp {stamp} < {released} already processed")]
    Late {
        /// The sensor.
        sensor: SensorId,
        /// Its stamp.
        stamp: f64,
        /// The newest processed stamp.
        released: f64,
    },
    /// The reorder buffer is full.
    #[error("reorder buffer full, set from {0} dropped")]
    Overflow(SensorId),
}

/// A set waiting in the reorder buffer.
#[derive(Debug)]
struct Pending {
    set: MeasurementSet,
    /// Arrival time on the caller's clock (for latency).
    arrived: f64,
}

/// Admission, ordering and filtering of measurement sets for one site.
pub struct Engine {
    config: ServerConfig,
    site: Site,
    /// True for the live service: sets stamped too far ahead of the clock are refused.
    live: bool,
    started: f64,
    sensors: SensorRegistry,
    buffer: ReorderBuffer<Pending>,
    tracker: Tracker,
    rejected: Rejected,
    latency: LatencyWindow,
    last_tracks: TrackSet,
    track_seq: u64,
}

impl Engine {
    /// An engine for `config`, starting at `now`; `live` enables the future-stamp check.
    pub fn new(config: ServerConfig, now: f64, live: bool) -> anyhow::Result<Self> {
        let site = Site::new(&config.site.name)?;
        let tracker = Tracker::new(&config)?;
        let buffer = ReorderBuffer::new(
            config.ingest.reorder_window_ms as f64 / 1000.0,
            config.ingest.queue_capacity,
        );
        let mut engine = Self {
            last_tracks: empty_tracks(&site, 0, 0.0),
            site,
            live,
            started: now,
            sensors: SensorRegistry::new(),
            buffer,
            tracker,
            rejected: Rejected::default(),
            latency: LatencyWindow::new(1024),
            track_seq: 0,
            config,
        };
        for (i, value) in engine.config.sensors.clone().into_iter().enumerate() {
            let descriptor: SensorDescriptor = serde_json::from_value(value)
                .map_err(|e| anyhow::anyhow!("configuration key `sensors[{i}]`: {e}"))?;
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

    /// Decodes, validates and queues one measurement set that arrived at `now`.
    ///
    /// `key_sensor` is the sensor named by the key it arrived on (the set must name the same one).
    /// Returns `UnknownSensor` when the caller should ask for the sensor's descriptor.
    pub fn admit_set(
        &mut self,
        key_sensor: Option<&SensorId>,
        payload: &[u8],
        format: WireFormat,
        now: f64,
    ) -> Result<(), Rejection> {
        let set: MeasurementSet = protocol::decode(payload, format)
            .map_err(|e| self.reject_undecodable(key_sensor, e.to_string()))?;
        self.admit_decoded(key_sensor, set, now)
    }

    /// Counts a payload that could not be decoded (or whose encoding is not supported); when it
    /// came on a known sensor's key, that sensor's `received` and `invalid` count it too.
    pub fn reject_undecodable(
        &mut self,
        key_sensor: Option<&SensorId>,
        reason: String,
    ) -> Rejection {
        self.rejected.undecodable += 1;
        if let Some(sensor) = key_sensor.and_then(|s| self.sensors.get_mut(s)) {
            sensor.counters.received += 1;
            sensor.counters.invalid += 1;
        }
        Rejection::Undecodable(reason)
    }

    /// True when a descriptor of `sensor` is known.
    pub fn is_known(&self, sensor: &SensorId) -> bool {
        self.sensors.get(sensor).is_some()
    }

    /// Validates and queues a decoded set (replay enters here).
    pub fn admit_decoded(
        &mut self,
        key_sensor: Option<&SensorId>,
        set: MeasurementSet,
        now: f64,
    ) -> Result<(), Rejection> {
        let name = set.sensor.clone();
        let invalid = |engine: &mut Self, reason: String| {
            engine.rejected.invalid += 1;
            if let Some(sensor) = engine.sensors.get_mut(&name) {
                sensor.counters.invalid += 1;
            }
            Rejection::Invalid {
                what: "set",
                sensor: name.to_string(),
                reason,
            }
        };
        if self.sensors.get(&name).is_none() {
            self.rejected.unknown_sensor += 1;
            let count = self.sensors.note_unknown(&name);
            return Err(Rejection::UnknownSensor(name, count));
        }
        if let Some(sensor) = self.sensors.get_mut(&name) {
            sensor.counters.received += 1;
        }
        if let Some(key_sensor) = key_sensor {
            if *key_sensor != name {
                return Err(invalid(
                    self,
                    format!("published on the key of sensor {key_sensor}"),
                ));
            }
        }
        if let Err(e) = set.validate() {
            return Err(invalid(self, e.to_string()));
        }
        let descriptor = self.sensors.get(&name).map(|s| s.descriptor.clone());
        if let Some(descriptor) = descriptor {
            if let Err(e) = set.validate_against(&descriptor) {
                return Err(invalid(self, e.to_string()));
            }
        }
        if self.live {
            if let Err(e) = set.validate_stamp(now, self.config.ingest.max_future_s) {
                return Err(invalid(self, e.to_string()));
            }
        }
        let max_rate = self.config.ingest.max_rate_hz;
        let within_rate = self
            .sensors
            .get_mut(&name)
            .is_some_and(|s| s.admit_rate(now, max_rate));
        if !within_rate {
            return Err(invalid(
                self,
                format!("more than {max_rate} sets per second (flood guard)"),
            ));
        }
        if let Some(sensor) = self.sensors.get_mut(&name) {
            sensor.check_seq(set.seq);
        }
        let stamp = set.stamp;
        match self.buffer.push(stamp, now, Pending { set, arrived: now }) {
            Ok(()) => Ok(()),
            Err(Refused::Late { stamp, released }) => {
                self.rejected.late += 1;
                if let Some(sensor) = self.sensors.get_mut(&name) {
                    sensor.counters.late += 1;
                }
                Err(Rejection::Late {
                    sensor: name,
                    stamp,
                    released,
                })
            }
            Err(Refused::Full) => {
                self.rejected.invalid += 1;
                if let Some(sensor) = self.sensors.get_mut(&name) {
                    sensor.counters.invalid += 1;
                }
                Err(Rejection::Overflow(name))
            }
        }
    }

    /// Processes every set whose reorder window has passed by `now`, in stamp order.
    /// Returns the track set after each processed set.
    pub fn step(&mut self, now: f64) -> Vec<TrackSet> {
        let ready = self.buffer.pop_ready(now);
        self.process(ready, now)
    }

    /// Processes everything still waiting (shutdown, end of a replay).
    pub fn drain(&mut self, now: f64) -> Vec<TrackSet> {
        let ready = self.buffer.drain();
        self.process(ready, now)
    }

    /// When the next waiting set becomes ready, on the caller's clock.
    pub fn next_ready_at(&self) -> Option<f64> {
        self.buffer.next_ready_at()
    }

    fn process(&mut self, ready: Vec<(f64, Pending)>, now: f64) -> Vec<TrackSet> {
        let mut out = Vec::with_capacity(ready.len());
        for (stamp, pending) in ready {
            let Some(sensor) = self.sensors.get(&pending.set.sensor) else {
                continue;
            };
            let model = sensor.model.clone();
            match self.tracker.process(stamp, model.as_ref(), &pending.set) {
                Ok(tracks) => {
                    if let Some(sensor) = self.sensors.get_mut(&pending.set.sensor) {
                        sensor.counters.processed += 1;
                        sensor.last_stamp = Some(stamp);
                    }
                    self.track_seq += 1;
                    let mut set = empty_tracks(&self.site, self.track_seq, stamp);
                    set.expected_count = self.tracker.expected_count();
                    set.tracks = tracks;
                    self.latency
                        .record((now - pending.arrived).max(0.0) * 1000.0);
                    self.last_tracks = set.clone();
                    out.push(set);
                }
                Err(e) => {
                    tracing::warn!(sensor = %pending.set.sensor, error = %e, "set not processed");
                    self.rejected.invalid += 1;
                    if let Some(sensor) = self.sensors.get_mut(&pending.set.sensor) {
                        sensor.counters.invalid += 1;
                    }
                }
            }
        }
        out
    }

    /// Records a latency sample measured outside the engine (publication after rate limiting).
    pub fn record_latency(&mut self, millis: f64) {
        self.latency.record(millis);
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
            latency_ms: LatencyMs {
                p50: (!self.latency.is_empty()).then(|| self.latency.percentile(0.5)),
                p99: (!self.latency.is_empty()).then(|| self.latency.percentile(0.99)),
            },
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
            self.buffer.set_released(stamp);
        }
        Ok(())
    }
}

fn empty_tracks(site: &Site, seq: u64, stamp: f64) -> TrackSet {
    TrackSet {
        version: PROTOCOL_VERSION,
        site: site.clone(),
        seq,
        stamp,
        expected_count: 0.0,
        tracks: Vec::new(),
    }
}
