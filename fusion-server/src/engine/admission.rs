//! Admission of measurement sets: decoding, the validation rules, the flood guard and the
//! queue for the next step, with the counters of what was refused.

use std::sync::Arc;

use gmphd::MeasurementModel;
use protocol::{MeasurementSet, SensorId, WireFormat};

use super::Engine;
use crate::processing::Pending;
use crate::rejection::Rejection;
use crate::timeline::{Incoming, Key};

impl Engine {
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

    /// Validates and queues a decoded set (replay enters here); the next [`Engine::step`]
    /// processes it.
    pub fn admit_decoded(
        &mut self,
        key_sensor: Option<&SensorId>,
        set: MeasurementSet,
        now: f64,
    ) -> Result<(), Rejection> {
        let name = set.sensor.clone();
        let Some(sensor) = self.sensors.get_mut(&name) else {
            self.rejected.unknown_sensor += 1;
            let count = self.sensors.note_unknown(&name);
            return Err(Rejection::UnknownSensor(name, count));
        };
        sensor.counters.received += 1;
        let model = Arc::clone(&sensor.model);
        if let Err(reason) = self.check_set(key_sensor, &set, now) {
            self.count_invalid(&name);
            return Err(Rejection::Invalid {
                what: "set",
                sensor: name.to_string(),
                reason,
            });
        }
        if let Some(sensor) = self.sensors.get_mut(&name) {
            sensor.check_seq(set.seq);
        }
        self.queue(set, model, now)
    }

    /// The validation rules a set must pass, in order; the first broken one is returned.
    fn check_set(
        &mut self,
        key_sensor: Option<&SensorId>,
        set: &MeasurementSet,
        now: f64,
    ) -> Result<(), String> {
        if let Some(key_sensor) = key_sensor.filter(|k| **k != set.sensor) {
            return Err(format!("published on the key of sensor {key_sensor}"));
        }
        set.validate().map_err(|e| e.to_string())?;
        if let Some(sensor) = self.sensors.get(&set.sensor) {
            set.validate_against(&sensor.descriptor)
                .map_err(|e| e.to_string())?;
        }
        if self.live {
            set.validate_stamp(now, self.ingest.max_future_s)
                .map_err(|e| e.to_string())?;
        }
        let max_rate = self.ingest.max_rate_hz;
        let within_rate = self
            .sensors
            .get_mut(&set.sensor)
            .is_some_and(|s| s.admit_rate(now, max_rate));
        if !within_rate {
            return Err(format!(
                "more than {max_rate} sets per second (flood guard)"
            ));
        }
        Ok(())
    }

    /// Queues a valid set, to be read with `model`, for the next step, unless it is older than the
    /// history kept.
    fn queue(
        &mut self,
        set: MeasurementSet,
        model: Arc<dyn MeasurementModel>,
        now: f64,
    ) -> Result<(), Rejection> {
        let name = set.sensor.clone();
        if let Some(horizon) = self.timeline.horizon().filter(|h| set.stamp < *h) {
            self.count_late(&name);
            return Err(Rejection::Late {
                sensor: name,
                stamp: set.stamp,
                horizon,
            });
        }
        if self.waiting.len() + self.pacing.held() >= self.ingest.queue_capacity {
            self.count_invalid(&name);
            return Err(Rejection::Overflow(name));
        }
        let key = Key::new(set.stamp, (name, set.seq));
        let item = Pending {
            set,
            model,
            arrived: now,
        };
        self.waiting.push(Incoming { key, item });
        Ok(())
    }

    pub(super) fn count_invalid(&mut self, name: &SensorId) {
        self.rejected.invalid += 1;
        if let Some(sensor) = self.sensors.get_mut(name) {
            sensor.counters.invalid += 1;
        }
    }

    pub(super) fn count_late(&mut self, name: &SensorId) {
        self.rejected.late += 1;
        if let Some(sensor) = self.sensors.get_mut(name) {
            sensor.counters.late += 1;
        }
    }
}
