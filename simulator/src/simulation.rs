//! A run: a scenario, a seed and a start time, with every sensor built.

use protocol::{MeasurementSet, SensorDescriptor, TruthSet};

use crate::error::ScenarioError;
use crate::replay::ReplayLines;
use crate::scenario::Scenario;
use crate::sensor_sim::SimulatedSensor;
use crate::truth::truth_set;
use crate::validate::validate;

/// A scenario bound to a seed and a start time. Everything it produces is a pure function
/// of `(scenario, seed, start)` and the instant asked for.
#[derive(Debug)]
pub struct Simulation {
    scenario: Scenario,
    seed: u64,
    start: f64,
    sensors: Vec<SimulatedSensor>,
}

impl Simulation {
    /// A run starting at the scenario's `start`, or at the shared clock's now if it has none.
    pub fn new(scenario: Scenario, seed: u64) -> Result<Self, ScenarioError> {
        let start = scenario.start_or_now();
        Self::with_start(scenario, seed, start)
    }

    /// A run whose scenario time 0 is Unix time `start` (overriding the scenario's).
    pub fn with_start(scenario: Scenario, seed: u64, start: f64) -> Result<Self, ScenarioError> {
        validate(&scenario)?;
        let sensors = (0..scenario.sensors.len())
            .map(|index| SimulatedSensor::new(&scenario, index))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            scenario,
            seed,
            start,
            sensors,
        })
    }

    /// The scenario being run.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The run's seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Unix time of scenario time 0.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The simulated sensors, in scenario order.
    pub fn sensors(&self) -> &[SimulatedSensor] {
        &self.sensors
    }

    /// Index of the sensor named `name`.
    pub fn sensor_index(&self, name: &str) -> Result<usize, ScenarioError> {
        self.scenario.sensor(name).map(|(index, _)| index)
    }

    /// Every sensor's descriptor, in scenario order.
    pub fn descriptors(&self) -> Vec<SensorDescriptor> {
        let site = &self.scenario.site;
        self.sensors
            .iter()
            .map(|s| s.spec().descriptor(site))
            .collect()
    }

    /// Truth instant `k` (stamp `start + k / truth_rate_hz`).
    pub fn truth_set(&self, k: u64) -> TruthSet {
        truth_set(&self.scenario, self.seed, self.start, k)
    }

    /// Frame `k` of sensor `index` (see [`SimulatedSensor::measurement_set`]).
    pub fn measurement_set(&self, index: usize, k: u64) -> Result<MeasurementSet, ScenarioError> {
        let sensor = self
            .sensors
            .get(index)
            .ok_or_else(|| ScenarioError::UnknownSensor {
                sensor: format!("#{index}"),
            })?;
        Ok(sensor.measurement_set(&self.scenario, self.seed, self.start, k))
    }

    /// The run's first `duration_s` seconds as replay lines (see [`ReplayLines`]).
    pub fn into_replay_lines(self, duration_s: f64) -> ReplayLines {
        ReplayLines::new(self, duration_s)
    }
}
