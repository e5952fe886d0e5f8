//! Replay files: a run as JSON-Lines input for offline fusion.

use std::cmp::{Ordering, Reverse};
use std::collections::{BinaryHeap, VecDeque};

use protocol::{MeasurementSet, ReplayLine, SensorDescriptor};

use crate::error::ScenarioError;
use crate::scenario::Scenario;
use crate::simulation::Simulation;

/// The first `duration_s` seconds of a run of `scenario` with `seed` as replay lines (see
/// [`ReplayLines`]). Stamps start at the scenario's `start`, or at the shared clock's now
/// when it has none: set `start` for a reproducible file.
///
/// Fails when the scenario does not validate (so the iterator itself never has to).
pub fn replay_lines(
    scenario: &Scenario,
    seed: u64,
    duration_s: f64,
) -> Result<ReplayLines, ScenarioError> {
    Ok(Simulation::new(scenario.clone(), seed)?.into_replay_lines(duration_s))
}

/// The sensors' descriptors and the measurement sets (in stamp order) of the first
/// `duration_s` seconds of a run, as [`replay_lines`] gives them, without the truth.
pub fn descriptors_and_sets(
    scenario: &Scenario,
    seed: u64,
    duration_s: f64,
) -> Result<(Vec<SensorDescriptor>, Vec<MeasurementSet>), ScenarioError> {
    let (mut descriptors, mut sets) = (Vec::new(), Vec::new());
    for line in replay_lines(scenario, seed, duration_s)? {
        match line {
            ReplayLine::Descriptor(d) => descriptors.push(d),
            ReplayLine::Measurements(s) => sets.push(s),
            ReplayLine::Truth(_) => {}
        }
    }
    Ok((descriptors, sets))
}

/// The lines of a run, generated lazily: every sensor's descriptor first (scenario
/// order), then all measurement sets and truth sets merged by stamp. At equal stamps the
/// truth set comes first, then the sensors in scenario order.
#[derive(Debug)]
pub struct ReplayLines {
    simulation: Simulation,
    descriptors: VecDeque<SensorDescriptor>,
    /// Number of instants of each stream (0: truth, 1 + i: sensor i) within the duration.
    counts: Vec<u64>,
    /// The next instant of every stream that has one left, earliest on top.
    pending: BinaryHeap<Reverse<Event>>,
}

impl ReplayLines {
    /// The lines of the first `duration_s` seconds of `simulation`.
    pub(crate) fn new(simulation: Simulation, duration_s: f64) -> Self {
        let scenario = simulation.scenario();
        let counts: Vec<u64> = std::iter::once(scenario.truth_count(duration_s))
            .chain(scenario.sensors.iter().map(|s| s.frame_count(duration_s)))
            .collect();
        let mut lines = Self {
            descriptors: simulation.descriptors().into(),
            counts,
            pending: BinaryHeap::new(),
            simulation,
        };
        for stream in 0..lines.counts.len() {
            lines.schedule(stream, 0);
        }
        lines
    }

    /// Queues instant `k` of `stream` if the stream has it.
    fn schedule(&mut self, stream: usize, k: u64) {
        if k >= self.counts[stream] {
            return;
        }
        let scenario = self.simulation.scenario();
        let t = match stream {
            0 => scenario.truth_time(k),
            s => scenario.sensors[s - 1].frame_time(k),
        };
        self.pending.push(Reverse(Event { t, stream, k }));
    }

    /// Produces the line of one instant.
    fn render(&self, event: Event) -> ReplayLine {
        let simulation = &self.simulation;
        match event.stream {
            0 => ReplayLine::Truth(simulation.truth_set(event.k)),
            s => ReplayLine::Measurements(simulation.sensors()[s - 1].measurement_set(
                simulation.scenario(),
                simulation.seed(),
                simulation.start(),
                event.k,
            )),
        }
    }
}

impl Iterator for ReplayLines {
    type Item = ReplayLine;

    fn next(&mut self) -> Option<ReplayLine> {
        if let Some(descriptor) = self.descriptors.pop_front() {
            return Some(ReplayLine::Descriptor(descriptor));
        }
        let Reverse(event) = self.pending.pop()?;
        self.schedule(event.stream, event.k + 1);
        Some(self.render(event))
    }
}

/// One pending line of the merge: which stream, which instant, and when.
#[derive(Debug, Clone, Copy)]
struct Event {
    /// Scenario time of the instant; stamps are `start + t`, so ordering by `t` is
    /// ordering by stamp.
    t: f64,
    /// 0 for truth, 1 + sensor index for a sensor: the tie-break at equal times.
    stream: usize,
    k: u64,
}

impl PartialEq for Event {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Event {}

impl PartialOrd for Event {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Event {
    fn cmp(&self, other: &Self) -> Ordering {
        self.t
            .total_cmp(&other.t)
            .then(self.stream.cmp(&other.stream))
            .then(self.k.cmp(&other.k))
    }
}
