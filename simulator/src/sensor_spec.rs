//! A simulated sensor: a descriptor body plus its frame timing.

use protocol::{SensorDescriptor, SensorId, SensorModel, Site};
use serde::{Deserialize, Serialize};

/// One `[[sensors]]` entry: the body of a protocol `SensorDescriptor` (`sensor`, `model`,
/// `detection_probability`, `clutter_rate`; `version` and `site` come from the scenario)
/// plus when its frames are taken.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// The sensor's name within the site (a key chunk of `[A-Za-z0-9_-]`, 1 to 64 long).
    pub sensor: SensorId,
    /// Probability in (0, 1] of detecting a target inside the field of view.
    pub detection_probability: f64,
    /// Mean number of clutter measurements per set (≥ 0).
    pub clutter_rate: f64,
    /// Frames per second (> 0).
    pub rate_hz: f64,
    /// Scenario time of frame 0 in seconds (≥ 0): frame `k` is taken at
    /// `phase_s + k / rate_hz`, so sensors with different phases never share instants.
    #[serde(default)]
    pub phase_s: f64,
    /// The measurement model: a table tagged by `kind`, with the fields of PROTOCOL.md.
    pub model: SensorModel,
}

impl SensorSpec {
    /// The descriptor an agent for this sensor publishes on `site`.
    pub fn descriptor(&self, site: &Site) -> SensorDescriptor {
        SensorDescriptor::new(
            site.clone(),
            self.sensor.clone(),
            self.model.clone(),
            self.detection_probability,
            self.clutter_rate,
        )
    }

    /// Scenario time (seconds since the start) of frame `k`.
    pub fn frame_time(&self, k: u64) -> f64 {
        self.phase_s + k as f64 / self.rate_hz
    }

    /// Number of frames taken in the first `duration_s` seconds (those with
    /// `frame_time(k) < duration_s`).
    pub fn frame_count(&self, duration_s: f64) -> u64 {
        count_instants(self.phase_s, self.rate_hz, duration_s)
    }
}

/// Number of `k ≥ 0` with `offset + k / rate < duration`, computed with the same
/// arithmetic as the instants themselves so that rounding cannot add or drop one.
pub(crate) fn count_instants(offset: f64, rate: f64, duration: f64) -> u64 {
    // Written positively so that NaN inputs also give no instants.
    let has_instants = duration > offset && rate > 0.0;
    if !has_instants {
        return 0;
    }
    // A first guess from the closed form, then step until the boundary is exact.
    let mut count = ((duration - offset) * rate).floor().max(0.0) as u64;
    while count > 0 && offset + (count - 1) as f64 / rate >= duration {
        count -= 1;
    }
    while offset + count as f64 / rate < duration {
        count += 1;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::count_instants;

    #[test]
    fn counts_instants_strictly_before_the_end() {
        assert_eq!(count_instants(0.0, 10.0, 1.0), 10);
        assert_eq!(count_instants(0.05, 10.0, 1.0), 10);
        assert_eq!(count_instants(0.0, 3.0, 1.0), 3);
        assert_eq!(count_instants(0.0, 25.0, 0.0), 0);
        assert_eq!(count_instants(2.0, 25.0, 1.0), 0);
    }
}
