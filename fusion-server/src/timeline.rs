//! The timeline: every set is processed as soon as it is admitted, in stamp order, and a set
//! older than what has been processed rolls the filter back and re-processes.
//!
//! The filter can only move forward in time, but sensors deliver their sets with different
//! delays. Instead of holding every set for a window (adding that window to every track's
//! latency), the timeline processes a set at once when it is the newest, and keeps what it needs
//! to go back: the processed sets of the last `max_lateness_s` and snapshots of the filter state
//! taken every `snapshot_interval_s` of stamp time. A set older than the newest processed one
//! restores the last snapshot taken before its stamp and re-processes that snapshot's later sets
//! together with the new one, in stamp order. Because every step is deterministic and a
//! snapshot restores the state exactly, the result is bit for bit the result of processing the
//! same sets in stamp order, whatever order they arrived in.
//!
//! A batch of sets handed over together (what arrived while the filter was busy) causes at most
//! one rollback. A set older than the newest stamp minus `max_lateness_s` is refused, so no set
//! can make the filter re-process more than that much history.

use std::collections::VecDeque;

/// The order sets are processed in: stamp, then a tie-breaker that does not depend on arrival
/// (the server uses the sensor's name and the set's `seq`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Key<T> {
    /// The stamp's IEEE bits: stamps are finite and non-negative, so the bits order like the
    /// numbers and the key can be `Ord`.
    stamp_bits: u64,
    /// Orders sets with the same stamp.
    pub tie: T,
}

impl<T> Key<T> {
    /// The key of a set stamped `stamp` (finite, ≥ 0).
    pub fn new(stamp: f64, tie: T) -> Self {
        debug_assert!(stamp.is_finite() && stamp >= 0.0);
        Self {
            stamp_bits: stamp.to_bits(),
            tie,
        }
    }

    /// The stamp.
    pub fn stamp(&self) -> f64 {
        f64::from_bits(self.stamp_bits)
    }
}

/// What the timeline drives: a deterministic processor whose state can be copied and restored.
pub trait Processor<I> {
    /// A copy of the whole state (restoring it must give back exactly this state).
    type State: Clone;
    /// What processing one item produces.
    type Output: Clone;

    /// A copy of the current state.
    fn snapshot(&self) -> Self::State;
    /// Puts the state back to `state`.
    fn restore(&mut self, state: &Self::State);
    /// Processes one item; `None` when the item could not be used (it stays in the timeline, so
    /// that re-processing repeats exactly what happened).
    fn process(&mut self, item: &I) -> Option<Self::Output>;
}

/// How much history the timeline keeps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimelineConfig {
    /// Sets older than the newest processed stamp minus this are refused (seconds).
    pub max_lateness_s: f64,
    /// A snapshot is taken before a set stamped at least this long after the previous snapshot
    /// (seconds of stamp time; smaller = less re-processing per rollback, more memory).
    pub snapshot_interval_s: f64,
}

/// One item handed to the timeline.
#[derive(Debug)]
pub struct Incoming<T, I> {
    /// Where it goes in the processing order.
    pub key: Key<T>,
    /// The item.
    pub item: I,
}

/// One item (re)processed by a batch, in key order.
#[derive(Debug)]
pub struct Processed<'a, T, O> {
    /// Its key.
    pub key: &'a Key<T>,
    /// What processing it produced, `None` when it could not be used.
    pub output: Option<&'a O>,
    /// True for an item of this batch, false for an earlier item re-processed by a rollback.
    pub fresh: bool,
}

/// What one batch did.
#[derive(Debug)]
pub struct BatchReport<T> {
    /// The key of the set that caused a rollback (the batch's oldest), if one was needed.
    pub rollback_cause: Option<Key<T>>,
    /// Keys of the earlier sets that were processed again.
    pub reprocessed: Vec<Key<T>>,
    /// Items refused because they are older than the history kept.
    pub too_late: Vec<Key<T>>,
    /// Items refused because an item with the same key was already processed.
    pub duplicates: Vec<Key<T>>,
}

impl<T> Default for BatchReport<T> {
    fn default() -> Self {
        Self {
            rollback_cause: None,
            reprocessed: Vec::new(),
            too_late: Vec::new(),
            duplicates: Vec::new(),
        }
    }
}

#[derive(Debug)]
struct Entry<T, I, O> {
    key: Key<T>,
    item: I,
    output: Option<O>,
}

/// A snapshot of the state after exactly the entries whose keys are below `before`.
#[derive(Debug)]
struct Snapshot<T, S> {
    /// `None`: before everything.
    before: Option<Key<T>>,
    /// The stamp of the first item processed after it.
    stamp: f64,
    state: S,
}

impl<T: Ord, S> Snapshot<T, S> {
    /// True when restoring this snapshot leaves an item with `key` still to be processed.
    fn precedes(&self, key: &Key<T>) -> bool {
        self.before.as_ref().is_none_or(|before| before <= key)
    }

    /// The stamp of the item it precedes, for a snapshot that can be evicted (not the first).
    fn evictable_stamp(&self) -> Option<f64> {
        self.before.as_ref().map(Key::stamp)
    }
}

/// The processed sets of the recent past and the snapshots needed to go back to any of them.
#[derive(Debug)]
pub struct Timeline<T, I, O, S> {
    config: TimelineConfig,
    /// Processed items, in key order.
    entries: VecDeque<Entry<T, I, O>>,
    /// Snapshots, in key order; the first one precedes every entry.
    snapshots: VecDeque<Snapshot<T, S>>,
    /// The newest processed stamp.
    newest: Option<f64>,
    /// Nothing older than this is admitted (the stamp of a restored checkpoint).
    floor: Option<f64>,
    /// Outputs of entries that fell out of the history, in key order (no rollback reaches them).
    settled: Vec<O>,
    keep_settled: bool,
}

impl<T, I, O, S> Timeline<T, I, O, S>
where
    T: Ord + Clone,
    O: Clone,
    S: Clone,
{
    /// An empty timeline; `keep_settled` keeps the final outputs for [`Timeline::take_settled`]
    /// (offline replay), the live service does not need them.
    pub fn new(config: TimelineConfig, keep_settled: bool) -> Self {
        Self {
            config,
            entries: VecDeque::new(),
            snapshots: VecDeque::new(),
            newest: None,
            floor: None,
            settled: Vec::new(),
            keep_settled,
        }
    }

    /// Sets stamped before this are refused: the newest processed stamp minus `max_lateness_s`
    /// (or the restored checkpoint's stamp, if later).
    pub fn horizon(&self) -> Option<f64> {
        let by_lateness = self.newest.map(|n| n - self.config.max_lateness_s);
        match (by_lateness, self.floor) {
            (Some(h), Some(f)) => Some(h.max(f)),
            (h, f) => h.or(f),
        }
    }

    /// The newest processed stamp.
    pub fn newest(&self) -> Option<f64> {
        self.newest
    }

    /// The key of the newest processed item.
    pub fn newest_key(&self) -> Option<&Key<T>> {
        self.entries.back().map(|e| &e.key)
    }

    /// True when a set stamped `stamp` would be refused as too late.
    pub fn is_too_late(&self, stamp: f64) -> bool {
        self.horizon().is_some_and(|h| stamp < h)
    }

    /// Number of processed items kept.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Number of snapshots kept.
    pub fn snapshot_count(&self) -> usize {
        self.snapshots.len()
    }

    /// The output of the newest processed item.
    pub fn latest_output(&self) -> Option<&O> {
        self.entries.back().and_then(|e| e.output.as_ref())
    }

    /// Processes a batch of items in key order, rolling `processor` back once if the oldest of
    /// them is older than what has been processed; `on_processed` sees every item processed
    /// (fresh and re-processed), in key order.
    pub fn process_batch<P>(
        &mut self,
        batch: Vec<Incoming<T, I>>,
        processor: &mut P,
        mut on_processed: impl FnMut(Processed<'_, T, O>),
    ) -> BatchReport<T>
    where
        P: Processor<I, State = S, Output = O>,
    {
        let mut report = BatchReport::default();
        let fresh = self.admissible(batch, &mut report);
        let Some(oldest) = fresh.first().map(|i| i.key.clone()) else {
            return report;
        };
        let redo = self.roll_back_for(&oldest, processor, &mut report);
        let mut fresh = fresh.into_iter().peekable();
        let mut redo = redo.into_iter().peekable();
        loop {
            let take_fresh = match (fresh.peek(), redo.peek()) {
                (Some(f), Some(r)) => f.key < r.key,
                (Some(_), None) => true,
                (None, Some(_)) => false,
                (None, None) => break,
            };
            let (key, item) = if take_fresh {
                let next = fresh.next().expect("peeked");
                (next.key, next.item)
            } else {
                let next = redo.next().expect("peeked");
                report.reprocessed.push(next.key.clone());
                (next.key, next.item)
            };
            let entry = self.run(key, item, processor);
            on_processed(Processed {
                key: &entry.key,
                output: entry.output.as_ref(),
                fresh: take_fresh,
            });
        }
        self.evict();
        report
    }

    /// The batch's items sorted by key, without those too late or already processed.
    fn admissible(
        &self,
        mut batch: Vec<Incoming<T, I>>,
        report: &mut BatchReport<T>,
    ) -> Vec<Incoming<T, I>> {
        batch.sort_by(|a, b| a.key.cmp(&b.key));
        let mut kept: Vec<Incoming<T, I>> = Vec::with_capacity(batch.len());
        for incoming in batch {
            if self.is_too_late(incoming.key.stamp()) {
                report.too_late.push(incoming.key);
            } else if self.contains(&incoming.key)
                || kept.last().is_some_and(|k| k.key == incoming.key)
            {
                report.duplicates.push(incoming.key);
            } else {
                kept.push(incoming);
            }
        }
        kept
    }

    fn contains(&self, key: &Key<T>) -> bool {
        let newest = self.entries.back().map(|e| &e.key);
        newest.is_some_and(|newest| key <= newest)
            && self.entries.binary_search_by(|e| e.key.cmp(key)).is_ok()
    }

    /// When `oldest` goes before processed entries: restores the last snapshot that precedes it
    /// and returns the entries after that snapshot, to be processed again.
    fn roll_back_for<P>(
        &mut self,
        oldest: &Key<T>,
        processor: &mut P,
        report: &mut BatchReport<T>,
    ) -> Vec<Entry<T, I, O>>
    where
        P: Processor<I, State = S, Output = O>,
    {
        let needs_rollback = self.entries.back().is_some_and(|e| e.key > *oldest);
        if !needs_rollback {
            return Vec::new();
        }
        report.rollback_cause = Some(oldest.clone());
        // The first snapshot precedes every entry, and `admissible` refused anything older.
        let keep = self
            .snapshots
            .iter()
            .rposition(|s| s.precedes(oldest))
            .unwrap_or(0);
        self.snapshots.truncate(keep + 1);
        let snapshot = &self.snapshots[keep];
        processor.restore(&snapshot.state);
        let from = match &snapshot.before {
            None => 0,
            Some(before) => self.entries.partition_point(|e| e.key < *before),
        };
        self.entries.drain(from..).collect()
    }

    /// Processes one item at the end of the timeline, taking a snapshot before it when due.
    fn run<P>(&mut self, key: Key<T>, item: I, processor: &mut P) -> &Entry<T, I, O>
    where
        P: Processor<I, State = S, Output = O>,
    {
        let stamp = key.stamp();
        let last_snapshot = self.snapshots.back();
        let due = last_snapshot.is_none_or(|s| stamp - s.stamp >= self.config.snapshot_interval_s);
        if due {
            let first = self.snapshots.is_empty() && self.entries.is_empty();
            self.snapshots.push_back(Snapshot {
                before: (!first).then(|| key.clone()),
                stamp,
                state: processor.snapshot(),
            });
        }
        let output = processor.process(&item);
        self.newest = Some(self.newest.map_or(stamp, |n| n.max(stamp)));
        self.entries.push_back(Entry { key, item, output });
        self.entries.back().expect("just pushed")
    }

    /// Drops the history no admissible set can reach: everything before the last snapshot that
    /// is older than the horizon.
    fn evict(&mut self) {
        let Some(horizon) = self.horizon() else {
            return;
        };
        // Snapshots after the first that are strictly older than the horizon: keep the last one.
        let reachable_from = self
            .snapshots
            .iter()
            .rposition(|s| s.evictable_stamp().is_some_and(|at| at < horizon));
        let Some(keep) = reachable_from else {
            return;
        };
        self.snapshots.drain(..keep);
        let before = self.snapshots[0]
            .before
            .clone()
            .expect("a snapshot with a stamp has a key");
        let settled = self.entries.partition_point(|e| e.key < before);
        for entry in self.entries.drain(..settled) {
            if self.keep_settled {
                self.settled.extend(entry.output);
            }
        }
    }

    /// Takes the outputs that can no longer change, in key order (requires `keep_settled`).
    pub fn take_settled(&mut self) -> Vec<O> {
        std::mem::take(&mut self.settled)
    }

    /// Settles everything: the outputs of every kept entry follow those already settled.
    pub fn settle_all(&mut self) -> Vec<O> {
        let mut settled = std::mem::take(&mut self.settled);
        settled.extend(self.entries.drain(..).filter_map(|e| e.output));
        self.snapshots.clear();
        settled
    }

    /// Forgets the history and starts at `stamp` (after restoring a checkpoint whose last set
    /// was stamped `stamp`: its state is the new beginning, and older sets are refused).
    pub fn reset_at(&mut self, stamp: f64) {
        self.entries.clear();
        self.snapshots.clear();
        self.settled.clear();
        self.newest = None;
        self.floor = Some(stamp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Order-sensitive toy processing: the state is a running hash of what was processed, so
    /// any difference in order or content shows.
    #[derive(Default)]
    struct Hasher {
        state: u64,
        restores: usize,
    }

    impl Processor<u64> for Hasher {
        type State = u64;
        type Output = u64;
        fn snapshot(&self) -> u64 {
            self.state
        }
        fn restore(&mut self, state: &u64) {
            self.state = *state;
            self.restores += 1;
        }
        fn process(&mut self, item: &u64) -> Option<u64> {
            self.state = self.state.wrapping_mul(1_000_003).wrapping_add(*item);
            Some(self.state)
        }
    }

    fn config() -> TimelineConfig {
        TimelineConfig {
            max_lateness_s: 2.0,
            snapshot_interval_s: 0.25,
        }
    }

    /// Items every 0.1 s from three sensors, as (stamp, sensor): the item's value encodes both.
    fn items(n: usize) -> Vec<(f64, u8)> {
        (0..n)
            .map(|i| (0.1 * (i / 3) as f64, (i % 3) as u8))
            .collect()
    }

    fn incoming(&(stamp, sensor): &(f64, u8)) -> Incoming<u8, u64> {
        Incoming {
            key: Key::new(stamp, sensor),
            item: (stamp * 10.0).round() as u64 * 10 + sensor as u64,
        }
    }

    /// Feeds `order` in batches of `batch` and returns (final state, settled outputs).
    fn run(order: &[(f64, u8)], batch: usize) -> (u64, Vec<u64>, Hasher) {
        let mut timeline = Timeline::new(config(), true);
        let mut hasher = Hasher::default();
        for chunk in order.chunks(batch.max(1)) {
            let report =
                timeline.process_batch(chunk.iter().map(incoming).collect(), &mut hasher, |_| {});
            assert!(report.too_late.is_empty() && report.duplicates.is_empty());
        }
        (hasher.state, timeline.settle_all(), hasher)
    }

    #[test]
    fn in_order_items_never_roll_back() {
        let order = items(60);
        let (_, outputs, hasher) = run(&order, 1);
        assert_eq!(outputs.len(), 60);
        assert_eq!(hasher.restores, 0);
    }

    #[test]
    fn a_late_item_gives_the_in_order_result() {
        let order = items(30);
        let (expected_state, expected, _) = run(&order, 1);
        let mut late = order.clone();
        let item = late.remove(4);
        late.insert(20, item);
        let (state, outputs, hasher) = run(&late, 1);
        assert_eq!((state, outputs), (expected_state, expected));
        assert_eq!(hasher.restores, 1);
    }

    #[test]
    fn a_batch_of_late_items_rolls_back_once() {
        let order = items(30);
        let (expected_state, _, _) = run(&order, 1);
        let mut timeline = Timeline::new(config(), false);
        let mut hasher = Hasher::default();
        let (late, on_time): (Vec<_>, Vec<_>) = order.iter().partition(|(_, s)| *s == 2);
        for item in &on_time {
            timeline.process_batch(vec![incoming(item)], &mut hasher, |_| {});
        }
        let mut reprocessed = 0;
        let report =
            timeline.process_batch(late.iter().map(incoming).collect(), &mut hasher, |p| {
                reprocessed += usize::from(!p.fresh);
            });
        assert_eq!(hasher.restores, 1);
        assert_eq!(report.reprocessed.len(), reprocessed);
        assert_eq!(reprocessed, on_time.len());
        assert_eq!(hasher.state, expected_state);
    }

    #[test]
    fn too_late_and_duplicate_items_are_refused() {
        let mut timeline = Timeline::new(config(), false);
        let mut hasher = Hasher::default();
        timeline.process_batch(vec![incoming(&(5.0, 0))], &mut hasher, |_| {});
        let report = timeline.process_batch(
            vec![
                incoming(&(2.9, 1)),
                incoming(&(5.0, 0)),
                incoming(&(3.5, 1)),
            ],
            &mut hasher,
            |_| {},
        );
        assert_eq!(report.too_late, vec![Key::new(2.9, 1)]);
        assert_eq!(report.duplicates, vec![Key::new(5.0, 0)]);
        assert_eq!(timeline.len(), 2);
        assert_eq!(timeline.horizon(), Some(3.0));
    }

    #[test]
    fn history_stays_bounded() {
        let mut timeline = Timeline::new(config(), false);
        let mut hasher = Hasher::default();
        for item in items(3000) {
            timeline.process_batch(vec![incoming(&item)], &mut hasher, |_| {});
        }
        // 2 s of history at 30 items per second, plus one snapshot interval.
        assert!(timeline.len() <= 3 * 23 + 3, "{}", timeline.len());
        assert!(
            timeline.snapshot_count() <= 10,
            "{}",
            timeline.snapshot_count()
        );
    }

    #[test]
    fn nothing_older_than_a_restored_checkpoint_is_admitted() {
        let mut timeline = Timeline::new(config(), false);
        let mut hasher = Hasher::default();
        timeline.reset_at(10.0);
        let report = timeline.process_batch(
            vec![incoming(&(9.5, 0)), incoming(&(10.5, 0))],
            &mut hasher,
            |_| {},
        );
        assert_eq!(report.too_late, vec![Key::new(9.5, 0)]);
        assert_eq!(timeline.len(), 1);
    }

    proptest! {
        /// Any arrival order within the history, in any batch sizes, gives the in-order result.
        #[test]
        fn arrival_order_does_not_matter(
            delays in prop::collection::vec(0.0..1.9_f64, 90),
            batch in 1usize..6,
        ) {
            let order = items(90);
            let (expected_state, expected, _) = run(&order, 1);
            let mut arrival: Vec<(f64, (f64, u8))> = order
                .iter()
                .zip(&delays)
                .map(|(item, delay)| (item.0 + delay, *item))
                .collect();
            arrival.sort_by(|a, b| a.0.total_cmp(&b.0));
            let arrival: Vec<(f64, u8)> = arrival.into_iter().map(|(_, item)| item).collect();
            let (state, outputs, _) = run(&arrival, batch);
            prop_assert_eq!(state, expected_state);
            prop_assert_eq!(outputs, expected);
        }
    }
}
