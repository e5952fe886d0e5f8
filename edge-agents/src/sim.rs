//! `edge-agent sim` (and `--simulate` on the sensor subcommands): frames of simulated sensors, and truth,
//! merged in stamp order.
//!
//! Everything comes from `simulator::Simulation`, a pure function of (scenario, seed, start): a process that
//! simulates one sensor produces exactly the sets that sensor has in a process simulating all of them.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use protocol::{SensorId, SensorKind, Site};
use simulator::{Scenario, Simulation};

use crate::cli::{ScenarioArgs, SimCommand, SimulateArgs, TimingArgs};
use crate::emit::Frame;
use crate::error::AgentError;
use crate::launch::Prepared;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};

/// Prepares `edge-agent sim`.
pub fn prepare_sim(command: &SimCommand) -> Result<Prepared, AgentError> {
    let scenario = load_scenario(&command.scenario, command.common.site.as_ref())?;
    let mut selected = Vec::with_capacity(command.sensor.len());
    for name in &command.sensor {
        selected.push(scenario.sensor(name.as_str())?.0);
    }
    if command.sensor.is_empty() {
        selected = (0..scenario.sensors.len()).collect();
    }
    if selected.is_empty() && !command.truth {
        return Err(AgentError::Usage(
            "the scenario has no sensors and --truth is not set: nothing to simulate".into(),
        ));
    }
    prepare(
        scenario,
        &command.scenario,
        &command.timing,
        selected,
        command.truth,
    )
}

/// Prepares `--simulate` on a sensor subcommand: one sensor of `kind` from the scenario, without truth.
pub fn prepare_simulated_sensor(
    args: &SimulateArgs,
    site: Option<&Site>,
    timing: &TimingArgs,
    kind: SensorKind,
) -> Result<Prepared, AgentError> {
    let scenario = load_scenario(&args.scenario, site)?;
    let index = pick_sensor(&scenario, args.sensor.as_ref(), kind)?;
    prepare(scenario, &args.scenario, timing, vec![index], false)
}

/// The scenario file, or the built-in room; `--site` replaces the scenario's site.
fn load_scenario(args: &ScenarioArgs, site: Option<&Site>) -> Result<Scenario, AgentError> {
    let mut scenario = match &args.scenario {
        Some(path) => Scenario::from_file(path)?,
        None => simulator::default_room(),
    };
    if let Some(site) = site {
        scenario.site = site.clone();
    }
    Ok(scenario)
}

/// The scenario index of the sensor `name` (which must be of `kind`), or of the first sensor of `kind`.
fn pick_sensor(
    scenario: &Scenario,
    name: Option<&SensorId>,
    kind: SensorKind,
) -> Result<usize, AgentError> {
    let (index, spec) = match name {
        Some(name) => scenario.sensor(name.as_str())?,
        None => scenario
            .sensors
            .iter()
            .enumerate()
            .find(|(_, spec)| spec.model.kind() == kind)
            .ok_or_else(|| {
                AgentError::Usage(format!("the scenario has no `{kind}` sensor to simulate"))
            })?,
    };
    if spec.model.kind() != kind {
        return Err(AgentError::Usage(format!(
            "scenario sensor `{}` is a `{}`, not a `{kind}`",
            spec.sensor,
            spec.model.kind()
        )));
    }
    Ok(index)
}

/// Binds the scenario to seed and start and builds the merged source of the `selected` sensors.
fn prepare(
    scenario: Scenario,
    args: &ScenarioArgs,
    timing: &TimingArgs,
    mut selected: Vec<usize>,
    truth: bool,
) -> Result<Prepared, AgentError> {
    let duration = match args.duration {
        Some(d) if d.is_finite() && d >= 0.0 => d,
        Some(d) => {
            return Err(AgentError::invalid(
                "--duration",
                format!("{d} is not a number of seconds ≥ 0"),
            ))
        }
        None => scenario.duration_s,
    };
    if let Some(start) = timing.start.filter(|s| !s.is_finite()) {
        return Err(AgentError::invalid(
            "--start",
            format!("{start} is not a Unix time"),
        ));
    }
    let start = timing.start.or(scenario.start).unwrap_or_else(wall_clock);
    // Scenario order, once each: the order of the merge's tie-break, whatever order the flags came in.
    selected.sort_unstable();
    selected.dedup();
    let truth_site = truth.then(|| scenario.site.clone());
    let simulation = Simulation::with_start(scenario, args.seed, start)?;
    let descriptors = {
        let all = simulation.descriptors();
        selected.iter().map(|&i| all[i].clone()).collect()
    };
    Ok(Prepared {
        calibrate: false,
        announce_calibration: false,
        source: Box::new(SimSource::new(simulation, selected, truth, duration)),
        descriptors,
        truth_site,
        origin_stamp: start,
        origin_wall: start,
    })
}

/// The frames of the selected sensors and the truth instants, merged by stamp. At equal stamps truth comes
/// first, then the sensors in scenario order (the simulator's replay order).
struct SimSource {
    simulation: Simulation,
    /// Scenario index of each stream's sensor (stream i of the emitter is `sensors[i]`).
    sensors: Vec<usize>,
    /// Instants of each queue: 0 is truth, 1 + i is stream i.
    counts: Vec<u64>,
    pending: BinaryHeap<Reverse<PendingInstant>>,
}

impl SimSource {
    fn new(simulation: Simulation, sensors: Vec<usize>, truth: bool, duration: f64) -> Self {
        let scenario = simulation.scenario();
        let truth_count = if truth {
            scenario.truth_count(duration)
        } else {
            0
        };
        let counts: Vec<u64> = std::iter::once(truth_count)
            .chain(
                sensors
                    .iter()
                    .map(|&i| scenario.sensors[i].frame_count(duration)),
            )
            .collect();
        let mut source = Self {
            simulation,
            sensors,
            counts,
            pending: BinaryHeap::new(),
        };
        for queue in 0..source.counts.len() {
            source.schedule(queue, 0);
        }
        source
    }

    /// Queues instant `k` of `queue` if the queue has it.
    fn schedule(&mut self, queue: usize, k: u64) {
        if k >= self.counts[queue] {
            return;
        }
        let scenario = self.simulation.scenario();
        let t = match queue {
            0 => scenario.truth_time(k),
            q => scenario.sensors[self.sensors[q - 1]].frame_time(k),
        };
        self.pending.push(Reverse(PendingInstant { t, queue, k }));
    }
}

impl EventSource for SimSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        let Some(Reverse(instant)) = self.pending.pop() else {
            return Ok(None);
        };
        self.schedule(instant.queue, instant.k + 1);
        let event = match instant.queue {
            0 => Event::Truth(self.simulation.truth_set(instant.k)),
            q => {
                let set = self
                    .simulation
                    .measurement_set(self.sensors[q - 1], instant.k)?;
                Event::Set {
                    stream: q - 1,
                    frame: Frame {
                        stamp: set.stamp,
                        measurements: set.measurements,
                        covariances: set.covariances,
                    },
                }
            }
        };
        Ok(Some(event))
    }
}

/// One pending instant of the merge.
#[derive(Debug, Clone, Copy)]
struct PendingInstant {
    /// Scenario time; stamps are `start + t`, so ordering by `t` orders by stamp.
    t: f64,
    /// 0 for truth, 1 + stream index: the tie-break at equal times.
    queue: usize,
    k: u64,
}

impl PartialEq for PendingInstant {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for PendingInstant {}

impl PartialOrd for PendingInstant {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for PendingInstant {
    fn cmp(&self, other: &Self) -> Ordering {
        self.t
            .total_cmp(&other.t)
            .then(self.queue.cmp(&other.queue))
            .then(self.k.cmp(&other.k))
    }
}
