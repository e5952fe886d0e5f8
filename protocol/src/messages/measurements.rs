//! `MeasurementSet`: one scan, frame or audio frame of one sensor, on `fusion/<site>/sensors/<sensor>/measurements`.

use crate::ids::SensorId;
use serde::{Deserialize, Serialize};

/// The measurements of one sensor at one capture time. An empty set is information: nothing was detected.
///
/// JSON: `{"version": 1, "sensor": "cam1", "seq": 42, "stamp": 1763700000.040,
/// "measurements": [[320.5, 240.1], [101.0, 57.5]], "covariances": null}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasurementSet {
    /// Protocol version; must be [`crate::PROTOCOL_VERSION`].
    pub version: u32,
    /// The sensor that produced the set.
    pub sensor: SensorId,
    /// Increases by one per set from each agent; a gap tells the server that sets were lost.
    pub seq: u64,
    /// Capture time, seconds since the Unix epoch on the shared clock.
    pub stamp: f64,
    /// One vector per measurement, of the length the sensor's kind gives.
    pub measurements: Vec<Vec<f64>>,
    /// `null`, or one covariance matrix (arrays of rows) per measurement replacing the model's `noise_std`.
    pub covariances: Option<Vec<Vec<Vec<f64>>>>,
}

impl MeasurementSet {
    /// A set of the current protocol version without per-measurement covariances.
    pub fn new(sensor: SensorId, seq: u64, stamp: f64, measurements: Vec<Vec<f64>>) -> Self {
        Self {
            version: crate::PROTOCOL_VERSION,
            sensor,
            seq,
            stamp,
            measurements,
            covariances: None,
        }
    }
}
