//! Rollback pacing: sets older than what was processed wait a little and go back together.
//!
//! A rollback re-processes every set after the late one, so a sensor that is always 0.4 s late
//! would otherwise make the filter re-process 0.4 s of every other sensor's sets for each of its
//! own. With `ingest.rollback_interval_s` > 0, late sets are held until that long has passed since
//! the last rollback, then all go back in one rollback; sets newer than everything processed never
//! wait. With 0 (the default) every late set goes back at once.
//! A held set is released early when the history would otherwise move past it, so pacing never
//! makes a set late.

use crate::processing::{Pending, Tie};
use crate::timeline::{Incoming, Key};

/// Holds late sets between rollbacks.
#[derive(Debug)]
pub struct RollbackPacing {
    interval_s: f64,
    max_lateness_s: f64,
    held: Vec<Incoming<Tie, Pending>>,
    last_rollback: f64,
}

impl RollbackPacing {
    /// At most one rollback per `interval_s` (caller's clock), for a history of `max_lateness_s`.
    pub fn new(interval_s: f64, max_lateness_s: f64) -> Self {
        Self {
            interval_s,
            max_lateness_s,
            held: Vec::new(),
            last_rollback: f64::NEG_INFINITY,
        }
    }

    /// Number of late sets waiting for the next rollback.
    pub fn held(&self) -> usize {
        self.held.len()
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
        // Keep a held set well inside the history the batch leaves behind.
        let horizon_after = newest_after - self.max_lateness_s + self.interval_s;
        let due = force
            || now - self.last_rollback >= self.interval_s
            || self.held.iter().any(|h| h.key.stamp() < horizon_after);
        if due {
            on_time.append(&mut self.held);
            self.last_rollback = now;
        }
        on_time
    }
}
