//! The scenario: what is simulated, read from and written to TOML.

use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use protocol::Site;
use serde::{Deserialize, Serialize};

use crate::crowd::CrowdCache;
use crate::error::ScenarioError;
use crate::sensor_spec::{count_instants, SensorSpec};
use crate::target::Target;
use crate::validate::validate;

/// A complete simulation scenario (see the crate documentation and SCENARIOS.md for the
/// file format).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The deployment the simulated sensors belong to (default `default`).
    #[serde(default)]
    pub site: Site,
    /// Unix time (s) of scenario time 0; absent: the shared clock when the run starts
    /// (see [`Scenario::start_or_now`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
    /// Length of the scenario in seconds.
    pub duration_s: f64,
    /// Truth sets per second.
    pub truth_rate_hz: f64,
    /// The simulated objects.
    #[serde(default)]
    pub targets: Vec<Target>,
    /// The simulated sensors.
    #[serde(default)]
    pub sensors: Vec<SensorSpec>,
    /// The smallest horizontal distance, in metres, between two present targets (heads): people step
    /// aside rather than walk through one another (see [`Scenario::position_of`]). Absent: every target
    /// follows its own motion, through the others.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub personal_space_m: Option<f64>,
    /// The remembered joint walk when `personal_space_m` is set.
    #[serde(skip)]
    pub(crate) crowd: CrowdCache,
}

impl Scenario {
    /// Parses and validates a scenario from TOML text.
    pub fn from_toml_str(text: &str) -> Result<Self, ScenarioError> {
        let scenario: Scenario = toml::from_str(text).map_err(|e| ScenarioError::Syntax {
            message: e.to_string(),
        })?;
        validate(&scenario)?;
        Ok(scenario)
    }

    /// Reads, parses and validates a scenario file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, ScenarioError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_toml_str(&text)
    }

    /// The scenario as TOML text (without comments) that [`Scenario::from_toml_str`]
    /// reads back to an equal scenario.
    pub fn to_toml_string(&self) -> Result<String, ScenarioError> {
        toml::to_string(self).map_err(|e| ScenarioError::Syntax {
            message: e.to_string(),
        })
    }

    /// Checks every value (also done by the parsers): times, rates, motions, unique ids
    /// and sensor names, and that each sensor's descriptor makes a measurement model.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        validate(self)
    }

    /// The Unix time of scenario time 0: `start` if the scenario fixes it, else the shared
    /// (system) clock now. Processes that must agree on stamps need the same start, so a
    /// launcher resolves it once and hands it to every process (e.g. by setting `start`).
    pub fn start_or_now(&self) -> f64 {
        self.start.unwrap_or_else(|| {
            SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map(|d| d.as_secs_f64())
                .unwrap_or(0.0)
        })
    }

    /// The sensor named `name`, with its index in `sensors`.
    pub fn sensor(&self, name: &str) -> Result<(usize, &SensorSpec), ScenarioError> {
        self.sensors
            .iter()
            .enumerate()
            .find(|(_, s)| s.sensor.as_str() == name)
            .ok_or_else(|| ScenarioError::UnknownSensor {
                sensor: name.to_owned(),
            })
    }

    /// Scenario time (seconds since the start) of truth instant `k`.
    pub fn truth_time(&self, k: u64) -> f64 {
        k as f64 / self.truth_rate_hz
    }

    /// Number of truth instants in the first `duration_s` seconds.
    pub fn truth_count(&self, duration_s: f64) -> u64 {
        count_instants(0.0, self.truth_rate_hz, duration_s)
    }

    /// The position of `targets[index]` at scenario time `t` (any `t`, present or not) in run `seed`:
    /// its own motion's, or with `personal_space_m` set that of the joint walk in which everyone keeps that
    /// distance from the others (module `crowd`: the motions are where each intends to go).
    ///
    /// # Panics
    /// If `index` is not a target's index.
    pub fn position_of(&self, index: usize, seed: u64, t: f64) -> [f64; 3] {
        match self.personal_space_m {
            Some(space) => self.crowd.position(&self.targets, index, seed, space, t),
            None => self.targets[index].position_at(seed, t),
        }
    }

    /// The positions of the targets present at scenario time `t` of run `seed`, with their indices in
    /// `targets`.
    pub fn present_at(&self, seed: u64, t: f64) -> Vec<(usize, [f64; 3])> {
        (0..self.targets.len())
            .filter(|&i| self.targets[i].is_present(t))
            .map(|i| (i, self.position_of(i, seed, t)))
            .collect()
    }

    /// The smallest horizontal distance between two targets present at scenario time `t` of run
    /// `seed`, `None` with fewer than two: how close the people come.
    pub fn closest_pair_m(&self, seed: u64, t: f64) -> Option<f64> {
        let heads: Vec<[f64; 3]> = self
            .present_at(seed, t)
            .into_iter()
            .map(|(_, head)| head)
            .collect();
        let pairs = heads.iter().enumerate().flat_map(|(i, a)| {
            heads[i + 1..]
                .iter()
                .map(move |b| (a[0] - b[0]).hypot(a[1] - b[1]))
        });
        pairs.reduce(f64::min)
    }
}
