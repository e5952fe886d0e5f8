//! `SensorDescriptor`: what a sensor is, published by its edge agent on `fusion/<site>/sensors/<sensor>/descriptor`.

use super::model::SensorModel;
use crate::ids::{SensorId, Site};
use serde::{Deserialize, Serialize};

/// Describes one sensor: its model, how often it detects an object and how much clutter it reports.
///
/// JSON: `{"version": 1, "site": "default", "sensor": "cam1", "model": {"kind": "camera", ...},
/// "detection_probability": 0.95, "clutter_rate": 2.0}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorDescriptor {
    /// Protocol version; must be [`crate::PROTOCOL_VERSION`].
    pub version: u32,
    /// The deployment the sensor belongs to.
    pub site: Site,
    /// The sensor's name within its site.
    pub sensor: SensorId,
    /// What one measurement is and how noisy it is.
    pub model: SensorModel,
    /// Probability in (0, 1] that an object inside the sensor's field of view is detected in a set.
    pub detection_probability: f64,
    /// Mean number (≥ 0) of false measurements per set, uniform over the sensor's measurement region.
    pub clutter_rate: f64,
}

impl SensorDescriptor {
    /// A descriptor of the current protocol version.
    pub fn new(
        site: Site,
        sensor: SensorId,
        model: SensorModel,
        detection_probability: f64,
        clutter_rate: f64,
    ) -> Self {
        Self {
            version: crate::PROTOCOL_VERSION,
            site,
            sensor,
            model,
            detection_probability,
            clutter_rate,
        }
    }
}
