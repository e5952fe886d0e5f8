//! Validation of measurement sets, track sets, status reports, truth sets and replay lines.

use super::checks::{check_all_finite, check_finite, check_non_negative, check_version};
use super::matrix::check_covariance;
use crate::error::ProtocolError;
use crate::messages::{
    MeasurementSet, ReplayLine, SensorDescriptor, Status, Track, TrackSet, TruthSet,
};
use crate::MAX_MEASUREMENTS;

impl MeasurementSet {
    /// Checks what can be checked without the sensor's descriptor: version, at most 10 000 measurements,
    /// every number finite, and `covariances` (when present) one symmetric positive definite n×n matrix per
    /// measurement of n values.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        check_version(self.version)?;
        self.check_count()?;
        check_finite(self.stamp, || "stamp".to_owned())?;
        for (i, measurement) in self.measurements.iter().enumerate() {
            check_all_finite(measurement, |j| format!("measurements[{i}][{j}]"))?;
        }
        if let Some(covariances) = &self.covariances {
            if covariances.len() != self.measurements.len() {
                return Err(ProtocolError::CovarianceCount {
                    covariances: covariances.len(),
                    measurements: self.measurements.len(),
                });
            }
            for (i, (covariance, measurement)) in
                covariances.iter().zip(&self.measurements).enumerate()
            {
                check_covariance(covariance, measurement.len(), &format!("covariances[{i}]"))?;
            }
        }
        Ok(())
    }

    /// Checks the set as coming from the sensor `descriptor` describes: [`MeasurementSet::validate`], the same
    /// sensor name, and every measurement of the length the sensor's kind gives.
    pub fn validate_against(&self, descriptor: &SensorDescriptor) -> Result<(), ProtocolError> {
        if self.sensor != descriptor.sensor {
            return Err(ProtocolError::SensorMismatch {
                set: self.sensor.to_string(),
                descriptor: descriptor.sensor.to_string(),
            });
        }
        self.check_count()?;
        let kind = descriptor.model.kind();
        let expected = kind.measurement_dim();
        // Lengths first: a wrong length is the root cause of any covariance size mismatch that follows.
        if let Some((index, measurement)) = self
            .measurements
            .iter()
            .enumerate()
            .find(|(_, m)| m.len() != expected)
        {
            return Err(ProtocolError::MeasurementLength {
                index,
                len: measurement.len(),
                kind: kind.name(),
                expected,
            });
        }
        self.validate()
    }

    /// Rejects a set of more than [`MAX_MEASUREMENTS`] measurements.
    fn check_count(&self) -> Result<(), ProtocolError> {
        if self.measurements.len() > MAX_MEASUREMENTS {
            return Err(ProtocolError::TooManyMeasurements {
                count: self.measurements.len(),
                max: MAX_MEASUREMENTS,
            });
        }
        Ok(())
    }

    /// Rejects a live set stamped more than `max_future_s` seconds ahead of the server clock `now`
    /// (both in seconds since the Unix epoch). A non-finite stamp is left to [`MeasurementSet::validate`].
    pub fn validate_stamp(&self, now: f64, max_future_s: f64) -> Result<(), ProtocolError> {
        let ahead = self.stamp - now;
        if ahead > max_future_s {
            return Err(ProtocolError::StampInFuture {
                stamp: self.stamp,
                now,
                ahead,
                max_future_s,
            });
        }
        Ok(())
    }
}

impl Track {
    /// Checks every number finite, `position_covariance` symmetric positive definite and `weight` ≥ 0;
    /// `index` is the track's place in its set, for error messages.
    fn validate_at(&self, index: usize) -> Result<(), ProtocolError> {
        let field = |name: &str| format!("tracks[{index}].{name}");
        check_all_finite(&self.position, |i| format!("{}[{i}]", field("position")))?;
        if let Some(velocity) = &self.velocity {
            check_all_finite(velocity, |i| format!("{}[{i}]", field("velocity")))?;
        }
        check_covariance(&self.position_covariance, 3, &field("position_covariance"))?;
        check_non_negative(self.weight, &field("weight"))?;
        check_finite(self.first_seen, || field("first_seen"))
    }
}

impl TrackSet {
    /// Checks version, every number finite, `expected_count` ≥ 0, and each track (covariance SPD, weight ≥ 0).
    pub fn validate(&self) -> Result<(), ProtocolError> {
        check_version(self.version)?;
        check_finite(self.stamp, || "stamp".to_owned())?;
        check_non_negative(self.expected_count, "expected_count")?;
        for (index, track) in self.tracks.iter().enumerate() {
            track.validate_at(index)?;
        }
        Ok(())
    }
}

impl Status {
    /// Checks version, every number finite, and `uptime_s` and the latencies ≥ 0.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        check_version(self.version)?;
        check_non_negative(self.uptime_s, "uptime_s")?;
        check_finite(self.stamp, || "stamp".to_owned())?;
        for (i, sensor) in self.sensors.iter().enumerate() {
            if let Some(last_stamp) = sensor.last_stamp {
                check_finite(last_stamp, || format!("sensors[{i}].last_stamp"))?;
            }
        }
        if let Some(p50) = self.latency_ms.p50 {
            check_non_negative(p50, "latency_ms.p50")?;
        }
        if let Some(p99) = self.latency_ms.p99 {
            check_non_negative(p99, "latency_ms.p99")?;
        }
        Ok(())
    }
}

impl TruthSet {
    /// Checks version and every number finite.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        check_version(self.version)?;
        check_finite(self.stamp, || "stamp".to_owned())?;
        for (index, object) in self.objects.iter().enumerate() {
            check_all_finite(&object.position, |i| {
                format!("objects[{index}].position[{i}]")
            })?;
        }
        Ok(())
    }
}

impl ReplayLine {
    /// Validates the message the line holds (a measurement set without its descriptor: the replay reader
    /// checks it with [`MeasurementSet::validate_against`] once it knows the sensor).
    pub fn validate(&self) -> Result<(), ProtocolError> {
        match self {
            ReplayLine::Descriptor(descriptor) => descriptor.validate(),
            ReplayLine::Measurements(set) => set.validate(),
            ReplayLine::Truth(set) => set.validate(),
        }
    }
}
