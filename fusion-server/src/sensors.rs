//! The sensors the server knows: their descriptors, measurement models, liveliness and counters.
//!
//! A sensor becomes known from its published descriptor, from a reply to the server's `get`, or
//! from a static descriptor in the configuration (which then wins over what the agent publishes).

use std::collections::BTreeMap;
use std::sync::Arc;

use gmphd::measurement::MeasurementModel;
use protocol::{SensorDescriptor, SensorId, SensorStatus};

/// Per-sensor counters, as reported in `Status`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Decodable sets that named this sensor.
    pub received: u64,
    /// Sets that updated the filter.
    pub processed: u64,
    /// Sets older than the history the server keeps (`ingest.max_lateness_s`; dropped).
    pub late: u64,
    /// Sets rejected by validation, the future-stamp check or the flood guard.
    pub invalid: u64,
    /// Sets missing from `seq` gaps.
    pub lost: u64,
    /// Rollbacks this sensor's late sets caused.
    pub rollbacks: u64,
    /// This sensor's sets processed again after a rollback.
    pub reprocessed: u64,
}

/// One known sensor.
#[derive(Debug, Clone)]
pub struct Sensor {
    /// Its descriptor (validated).
    pub descriptor: SensorDescriptor,
    /// The measurement model built from the descriptor.
    pub model: Arc<dyn MeasurementModel>,
    /// True when the descriptor came from the server's configuration.
    pub from_config: bool,
    /// True while the agent's liveliness token is seen.
    pub alive: bool,
    /// Counters for `Status`.
    pub counters: Counters,
    /// Stamp of the last processed set.
    pub last_stamp: Option<f64>,
    /// `seq` of the last admitted set.
    pub last_seq: Option<u64>,
    flood: FloodGuard,
}

/// The outcome of accounting for a set's `seq`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeqCheck {
    /// The next set, or the first one seen.
    InOrder,
    /// `n` sets were skipped (counted as lost).
    Gap(u64),
    /// A `seq` at or below the last one: the agent restarted (seq 0) or repeats itself.
    Restarted,
}

impl Sensor {
    fn new(
        descriptor: SensorDescriptor,
        model: Arc<dyn MeasurementModel>,
        from_config: bool,
    ) -> Self {
        Self {
            descriptor,
            model,
            from_config,
            alive: false,
            counters: Counters::default(),
            last_stamp: None,
            last_seq: None,
            flood: FloodGuard::default(),
        }
    }

    /// Accounts for an admitted set's `seq`, counting gaps as lost.
    pub fn check_seq(&mut self, seq: u64) -> SeqCheck {
        let check = match self.last_seq {
            None => SeqCheck::InOrder,
            Some(last) if seq == last + 1 => SeqCheck::InOrder,
            Some(last) if seq > last + 1 => SeqCheck::Gap(seq - last - 1),
            Some(_) => SeqCheck::Restarted,
        };
        if let SeqCheck::Gap(n) = check {
            self.counters.lost += n;
        }
        self.last_seq = Some(seq);
        check
    }

    /// True when one more set at time `now` stays within `max_rate_hz` (token bucket of one
    /// second's worth of sets).
    pub fn admit_rate(&mut self, now: f64, max_rate_hz: f64) -> bool {
        self.flood.admit(now, max_rate_hz)
    }

    /// This sensor's line of `Status`.
    pub fn status(&self) -> SensorStatus {
        SensorStatus {
            sensor: self.descriptor.sensor.clone(),
            kind: self.descriptor.model.kind(),
            alive: self.alive,
            last_stamp: self.last_stamp,
            received: self.counters.received,
            processed: self.counters.processed,
            late: self.counters.late,
            invalid: self.counters.invalid,
            lost: self.counters.lost,
            rollbacks: self.counters.rollbacks,
            reprocessed: self.counters.reprocessed,
        }
    }
}

/// Token bucket: `rate` tokens per second, at most one second's worth saved up.
#[derive(Debug, Clone, Copy, Default)]
struct FloodGuard {
    tokens: f64,
    last: Option<f64>,
}

impl FloodGuard {
    fn admit(&mut self, now: f64, rate: f64) -> bool {
        let elapsed = self.last.map_or(1.0, |last| (now - last).max(0.0));
        self.last = Some(now);
        self.tokens = (self.tokens + elapsed * rate).min(rate.max(1.0));
        if self.tokens >= 1.0 {
            self.tokens -= 1.0;
            true
        } else {
            false
        }
    }
}

/// What happened when a descriptor was offered to the registry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Learned {
    /// A sensor not known before.
    New,
    /// A known sensor's descriptor changed.
    Changed,
    /// Nothing new.
    Unchanged,
    /// The configuration's static descriptor stands; the published one is ignored.
    OverriddenByConfig,
}

/// All known sensors, by name (ordered, so that `Status` lists them deterministically).
#[derive(Debug, Default)]
pub struct SensorRegistry {
    sensors: BTreeMap<SensorId, Sensor>,
    /// Sensors that sent data before any descriptor was known, and how often.
    unknown: BTreeMap<SensorId, u64>,
    /// Liveliness of sensors whose descriptor is not known yet (tokens often arrive first).
    pending_alive: BTreeMap<SensorId, bool>,
}

impl SensorRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds or updates a sensor from a validated descriptor and the model built from it.
    pub fn learn(
        &mut self,
        descriptor: SensorDescriptor,
        model: Arc<dyn MeasurementModel>,
        from_config: bool,
    ) -> Learned {
        self.unknown.remove(&descriptor.sensor);
        match self.sensors.get_mut(&descriptor.sensor) {
            None => {
                let name = descriptor.sensor.clone();
                let mut sensor = Sensor::new(descriptor, model, from_config);
                sensor.alive = self.pending_alive.remove(&name).unwrap_or(false);
                self.sensors.insert(name, sensor);
                Learned::New
            }
            Some(known) if known.from_config && !from_config => Learned::OverriddenByConfig,
            Some(known) if known.descriptor == descriptor => Learned::Unchanged,
            Some(known) => {
                known.descriptor = descriptor;
                known.model = model;
                known.from_config |= from_config;
                Learned::Changed
            }
        }
    }

    /// The sensor called `name`, if known.
    pub fn get(&self, name: &SensorId) -> Option<&Sensor> {
        self.sensors.get(name)
    }

    /// The sensor called `name`, if known, for updating its counters.
    pub fn get_mut(&mut self, name: &SensorId) -> Option<&mut Sensor> {
        self.sensors.get_mut(name)
    }

    /// Records data from a sensor with no descriptor; returns how often it happened so far
    /// (the caller asks for the descriptor the first time).
    pub fn note_unknown(&mut self, name: &SensorId) -> u64 {
        let count = self.unknown.entry(name.clone()).or_insert(0);
        *count += 1;
        *count
    }

    /// Marks a sensor's liveliness token as present or gone. For a sensor not known yet the
    /// state is remembered and applied when its descriptor arrives. Returns false then.
    pub fn set_alive(&mut self, name: &SensorId, alive: bool) -> bool {
        match self.sensors.get_mut(name) {
            Some(sensor) => {
                sensor.alive = alive;
                true
            }
            None => {
                self.pending_alive.insert(name.clone(), alive);
                false
            }
        }
    }

    /// Every known sensor, ordered by name.
    pub fn iter(&self) -> impl Iterator<Item = &Sensor> {
        self.sensors.values()
    }

    /// Number of known sensors.
    pub fn len(&self) -> usize {
        self.sensors.len()
    }

    /// True when no sensor is known.
    pub fn is_empty(&self) -> bool {
        self.sensors.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flood_guard_allows_the_rate_and_refuses_a_burst_beyond_it() {
        let mut guard = FloodGuard::default();
        let admitted = (0..100).filter(|_| guard.admit(10.0, 20.0)).count();
        assert_eq!(admitted, 20, "one second's worth of tokens in a burst");
        assert!(!guard.admit(10.01, 20.0));
        assert!(guard.admit(10.06, 20.0), "tokens come back at the rate");
    }
}
