//! Rollback pacing: rollbacks may take at most a set share of the engine's time.
//!
//! A rollback re-processes every set after the late one, so a sensor that is always late makes
//! the filter re-process the other sensors' recent sets once per set of its own. Where that is
//! cheap (the room: a few people, 15 % of one core with two cameras late) every late set goes
//! back at once and its corrected tracks are out within milliseconds. Where it is not (fifty
//! targets, eight sensors) rolling back for each late set would saturate the engine and make the
//! on-time sets queue behind the rollbacks. So the engine keeps a budget of rollback time
//! (`ingest.max_rollback_share` of the clock, a token bucket): while the budget is spent, late
//! sets wait and then go back together in one rollback; sets newer than everything processed
//! never wait. A held set is released early when the history would otherwise move past it, so
//! pacing never makes a set late.

use crate::processing::{Pending, Tie};
use crate::timeline::{Incoming, Key};

/// Seconds of clock over which unused rollback budget accumulates (the largest burst of
/// rollback work allowed after a quiet spell is `share × BUDGET_WINDOW_S`).
const BUDGET_WINDOW_S: f64 = 1.0;

/// Holds late sets while the rollback budget is spent.
#[derive(Debug)]
pub struct RollbackPacing {
    budget: RollbackBudget,
    max_lateness_s: f64,
    held: Vec<Incoming<Tie, Pending>>,
}

impl RollbackPacing {
    /// Rollbacks may take `share` (0 < share ≤ 1) of the caller's clock, for a history of
    /// `max_lateness_s`; `now` is the caller's clock at start.
    pub fn new(share: f64, max_lateness_s: f64, now: f64) -> Self {
        Self {
            budget: RollbackBudget::new(share, now),
            max_lateness_s,
            held: Vec::new(),
        }
    }

    /// Number of late sets waiting for the next rollback.
    pub fn held(&self) -> usize {
        self.held.len()
    }

    /// Charges a rollback that took `seconds` of the engine's time to the budget.
    pub fn charge(&mut self, seconds: f64) {
        self.budget.charge(seconds);
    }

    /// What of `batch` (and of the sets held before) to process at `now`, given the newest
    /// processed key; with `force`, everything.
    pub fn select(
        &mut self,
        batch: Vec<Incoming<Tie, Pending>>,
        newest: Option<&Key<Tie>>,
        now: f64,
        force: bool,
    ) -> Vec<Incoming<Tie, Pending>> {
        let (late, mut on_time): (Vec<_>, Vec<_>) = batch
            .into_iter()
            .partition(|i| newest.is_some_and(|n| i.key < *n));
        self.held.extend(late);
        if self.held.is_empty() {
            return on_time;
        }
        let newest_after = on_time
            .iter()
            .map(|i| i.key.stamp())
            .chain(newest.map(Key::stamp))
            .fold(f64::NEG_INFINITY, f64::max);
        // Release a held set while it is still well inside the history the batch leaves behind.
        let horizon_after = newest_after - 0.75 * self.max_lateness_s;
        let due = force
            || self.budget.allows(now)
            || self.held.iter().any(|h| h.key.stamp() < horizon_after);
        if due {
            on_time.append(&mut self.held);
        }
        on_time
    }
}

/// A token bucket of rollback time: it fills at `share` seconds per second of clock, up to
/// `share × BUDGET_WINDOW_S`, and each rollback takes what it cost.
#[derive(Debug)]
struct RollbackBudget {
    share: f64,
    /// Seconds of rollback work allowed now; negative while paying off a costly rollback.
    credit_s: f64,
    updated: f64,
}

impl RollbackBudget {
    fn new(share: f64, now: f64) -> Self {
        Self {
            share,
            credit_s: share * BUDGET_WINDOW_S,
            updated: now,
        }
    }

    /// True when a rollback may start at `now`.
    fn allows(&mut self, now: f64) -> bool {
        let elapsed = (now - self.updated).max(0.0);
        self.credit_s = (self.credit_s + self.share * elapsed).min(self.share * BUDGET_WINDOW_S);
        self.updated = self.updated.max(now);
        self.credit_s >= 0.0
    }

    fn charge(&mut self, seconds: f64) {
        self.credit_s -= seconds;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{MeasurementSet, SensorId};

    fn incoming(stamp: f64, seq: u64) -> Incoming<Tie, Pending> {
        let sensor = SensorId::new("cam1").unwrap();
        let set = MeasurementSet::new(sensor.clone(), seq, stamp, vec![]);
        Incoming {
            key: Key::new(stamp, (sensor, seq)),
            item: Pending {
                set,
                model: std::sync::Arc::new(
                    gmphd::PositionSensor::new(
                        &[0.1, 0.1],
                        &[0.0, 0.0],
                        &[1.0, 1.0],
                        gmphd::Detection::new(0.9, 1.0).unwrap(),
                    )
                    .unwrap(),
                ),
                arrived: stamp,
            },
        }
    }

    #[test]
    fn cheap_rollbacks_go_at_once() {
        let mut pacing = RollbackPacing::new(0.25, 2.0, 0.0);
        let newest = Key::new(10.0, (SensorId::new("cam2").unwrap(), 0));
        for i in 0..100 {
            let now = 10.0 + i as f64 * 0.01;
            let out = pacing.select(vec![incoming(9.5, i)], Some(&newest), now, false);
            assert_eq!(out.len(), 1, "held at {now}");
            pacing.charge(0.001);
        }
    }

    #[test]
    fn costly_rollbacks_are_spaced_by_their_cost_over_the_share() {
        let mut pacing = RollbackPacing::new(0.25, 2.0, 10.0);
        let newest = Key::new(10.0, (SensorId::new("cam2").unwrap(), 0));
        // Spend the accumulated budget, then one rollback of 50 ms: the next may start only
        // after 200 ms of clock.
        pacing.charge(0.25 + 0.05);
        let mut released_at = None;
        for i in 0..30 {
            let now = 10.0 + i as f64 * 0.01;
            let out = pacing.select(vec![incoming(9.5, i)], Some(&newest), now, false);
            if !out.is_empty() {
                assert_eq!(out.len() as u64, i + 1, "every held set goes back together");
                released_at = Some(now);
                break;
            }
        }
        let released_at = released_at.expect("released within 0.3 s");
        // 10.2 up to rounding of the clock steps.
        assert!(
            (10.2 - 1e-9..=10.21 + 1e-9).contains(&released_at),
            "released at {released_at}"
        );
    }

    #[test]
    fn a_held_set_is_released_before_the_history_passes_it() {
        let mut pacing = RollbackPacing::new(0.25, 2.0, 0.0);
        pacing.charge(100.0);
        let old = Key::new(10.0, (SensorId::new("cam2").unwrap(), 0));
        assert!(pacing
            .select(vec![incoming(9.0, 0)], Some(&old), 10.0, false)
            .is_empty());
        let out = pacing.select(vec![incoming(10.6, 1)], Some(&old), 10.6, false);
        assert_eq!(
            out.len(),
            2,
            "the on-time set and the held one, 1.6 s behind"
        );
    }

    #[test]
    fn force_releases_everything() {
        let mut pacing = RollbackPacing::new(0.25, 2.0, 0.0);
        pacing.charge(100.0);
        let newest = Key::new(10.0, (SensorId::new("cam2").unwrap(), 0));
        assert!(pacing
            .select(vec![incoming(9.5, 0)], Some(&newest), 10.0, false)
            .is_empty());
        assert_eq!(pacing.select(vec![], Some(&newest), 10.0, true).len(), 1);
    }
}
