//! Ground truth: which targets exist where, as a pure function of (scenario, seed, time).

use protocol::{TruthObject, TruthSet};

use crate::scenario::Scenario;

/// The targets present at scenario time `t` (seconds since the start) and their
/// positions, in ascending id order.
pub fn truth_objects(scenario: &Scenario, seed: u64, t: f64) -> Vec<TruthObject> {
    let mut objects: Vec<TruthObject> = scenario
        .present_at(seed, t)
        .into_iter()
        .map(|(index, position)| TruthObject {
            id: scenario.targets[index].id,
            position,
        })
        .collect();
    objects.sort_by_key(|object| object.id);
    objects
}

/// Truth instant `k` (at scenario time `k / truth_rate_hz`) of a run that started at Unix
/// time `start`.
pub fn truth_set(scenario: &Scenario, seed: u64, start: f64, k: u64) -> TruthSet {
    let t = scenario.truth_time(k);
    TruthSet {
        version: protocol::PROTOCOL_VERSION,
        stamp: start + t,
        objects: truth_objects(scenario, seed, t),
    }
}
