//! The bounded in-memory history of published track sets, which answers `_time` queries on
//! `fusion/<site>/tracks` (PROTOCOL.md, "History").
//!
//! Sets are kept in stamp order. A set whose stamp is not newer than the newest one kept is a
//! corrected answer (the engine re-processed data after a late arrival): it replaces every kept
//! set stamped at or after it, so that a query returns the newest answer for each stamp. The
//! history spans at most `span_s` seconds of stamps and holds at most `max_sets` sets, which
//! bounds its memory (`heap_bytes`; `tests/history_memory.rs` measures it for the default room).

use std::collections::VecDeque;
use std::ops::Bound;
use std::time::{SystemTime, UNIX_EPOCH};

use protocol::{Track, TrackSet};
use zenoh_util::time_range::{TimeBound, TimeRange};

/// The name of Zenoh's time-range selector parameter.
pub const TIME_PARAMETER: &str = "_time";

/// Track sets in stamp order over a bounded span of stamps.
#[derive(Debug, Clone)]
pub struct TrackHistory {
    span_s: f64,
    max_sets: usize,
    sets: VecDeque<TrackSet>,
}

impl TrackHistory {
    /// A history spanning `span_s` seconds of stamps and at most `max_sets` sets; a span of 0
    /// (or `max_sets` 0) keeps nothing.
    pub fn new(span_s: f64, max_sets: usize) -> Self {
        Self {
            span_s,
            max_sets,
            sets: VecDeque::new(),
        }
    }

    /// The history of `span_s` seconds of a publisher that puts at most `max_rate_hz` sets per
    /// second: every published set is kept, and the count is capped at what that rate can put
    /// in the span (a guard; the span is what bounds it at a deployment's real rate).
    pub fn for_publisher(span_s: f64, max_rate_hz: f64) -> Self {
        let max_sets = (span_s * max_rate_hz).ceil();
        let max_sets = if max_sets.is_finite() && max_sets > 0.0 {
            max_sets as usize + 1
        } else {
            0
        };
        Self::new(span_s, max_sets)
    }

    /// Records a published set; a set not newer than the newest kept replaces every kept set
    /// stamped at or after it. Sets with a non-finite stamp are not kept.
    pub fn record(&mut self, set: TrackSet) {
        if self.max_sets == 0 || self.span_s <= 0.0 || !set.stamp.is_finite() {
            return;
        }
        while self.sets.back().is_some_and(|kept| kept.stamp >= set.stamp) {
            self.sets.pop_back();
        }
        let oldest_kept = set.stamp - self.span_s;
        self.sets.push_back(set);
        while self
            .sets
            .front()
            .is_some_and(|kept| kept.stamp < oldest_kept)
            || self.sets.len() > self.max_sets
        {
            self.sets.pop_front();
        }
    }

    /// The kept sets whose stamp lies in `range`, in stamp order.
    pub fn in_range(&self, range: &StampRange) -> impl Iterator<Item = &TrackSet> + '_ {
        let first = match range.start {
            Bound::Included(t) => self.sets.partition_point(|s| s.stamp < t),
            Bound::Excluded(t) => self.sets.partition_point(|s| s.stamp <= t),
            Bound::Unbounded => 0,
        };
        let end = match range.end {
            Bound::Included(t) => self.sets.partition_point(|s| s.stamp <= t),
            Bound::Excluded(t) => self.sets.partition_point(|s| s.stamp < t),
            Bound::Unbounded => self.sets.len(),
        };
        self.sets.range(first..end.max(first))
    }

    /// Number of sets kept.
    pub fn len(&self) -> usize {
        self.sets.len()
    }

    /// True when nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.sets.is_empty()
    }

    /// Heap memory the kept sets hold, in bytes (the sets, their track vectors and site names;
    /// the allocator's own overhead aside).
    pub fn heap_bytes(&self) -> usize {
        let slots = self.sets.capacity() * std::mem::size_of::<TrackSet>();
        let tracks: usize = self
            .sets
            .iter()
            .map(|s| s.tracks.capacity() * std::mem::size_of::<Track>() + s.site.as_str().len())
            .sum();
        slots + tracks
    }
}

/// A range of stamps (seconds since the Unix epoch), each end included, excluded or open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StampRange {
    /// Lower end.
    pub start: Bound<f64>,
    /// Upper end.
    pub end: Bound<f64>,
}

impl StampRange {
    /// True when `stamp` lies in the range.
    pub fn contains(&self, stamp: f64) -> bool {
        let above = match self.start {
            Bound::Included(t) => stamp >= t,
            Bound::Excluded(t) => stamp > t,
            Bound::Unbounded => true,
        };
        let below = match self.end {
            Bound::Included(t) => stamp <= t,
            Bound::Excluded(t) => stamp < t,
            Bound::Unbounded => true,
        };
        above && below
    }

    /// Parses a Zenoh time range (`[now(-30s)..now()]`, `[2026-12-02T00:00:00Z..now()[`, …),
    /// resolving `now()` at `now`.
    pub fn parse(text: &str, now: SystemTime) -> Result<Self, String> {
        // Zenoh's parser panics on some malformed durations (`now(s)`, or an overflowing one):
        // a bad selector must get an error reply, never take the queryable down.
        let parsed = std::panic::catch_unwind(|| text.parse::<TimeRange>())
            .map_err(|_| format!("{TIME_PARAMETER}={text}: not a usable time range"))?;
        let range =
            parsed.map_err(|e| format!("{TIME_PARAMETER}={text}: not a Zenoh time range: {e}"))?;
        let resolved = range.resolve_at(now);
        Ok(Self {
            start: seconds(resolved.start),
            end: seconds(resolved.end),
        })
    }
}

fn seconds(bound: TimeBound<SystemTime>) -> Bound<f64> {
    let since_epoch = |t: SystemTime| match t.duration_since(UNIX_EPOCH) {
        Ok(d) => d.as_secs_f64(),
        Err(before) => -before.duration().as_secs_f64(),
    };
    match bound {
        TimeBound::Inclusive(t) => Bound::Included(since_epoch(t)),
        TimeBound::Exclusive(t) => Bound::Excluded(since_epoch(t)),
        TimeBound::Unbounded => Bound::Unbounded,
    }
}

/// The `_time` range a query's parameters ask for: `Ok(None)` without one, an error for a
/// malformed one (or one given twice). Parameters are `;`- or `&`-separated `name=value` pairs.
pub fn requested_range(parameters: &str, now: SystemTime) -> Result<Option<StampRange>, String> {
    let mut found = None;
    for pair in parameters.split([';', '&']) {
        let (name, value) = pair.split_once('=').unwrap_or((pair, ""));
        if name.trim() != TIME_PARAMETER {
            continue;
        }
        if found.is_some() {
            return Err(format!("{TIME_PARAMETER} given twice"));
        }
        found = Some(StampRange::parse(value.trim(), now)?);
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::Site;
    use std::time::Duration;

    fn set(seq: u64, stamp: f64) -> TrackSet {
        TrackSet {
            version: 1,
            site: Site::default(),
            seq,
            stamp,
            expected_count: 0.0,
            tracks: Vec::new(),
        }
    }

    fn stamps<'a>(sets: impl Iterator<Item = &'a TrackSet>) -> Vec<(u64, f64)> {
        sets.map(|s| (s.seq, s.stamp)).collect()
    }

    const ALL: StampRange = StampRange {
        start: Bound::Unbounded,
        end: Bound::Unbounded,
    };

    #[test]
    fn a_range_returns_the_sets_stamped_in_it_in_stamp_order() {
        let mut history = TrackHistory::new(100.0, 1000);
        for i in 0..10 {
            history.record(set(i, 10.0 + i as f64));
        }
        let range = StampRange {
            start: Bound::Included(12.0),
            end: Bound::Excluded(15.0),
        };
        assert_eq!(
            stamps(history.in_range(&range)),
            vec![(2, 12.0), (3, 13.0), (4, 14.0)]
        );
        let range = StampRange {
            start: Bound::Excluded(17.0),
            end: Bound::Included(100.0),
        };
        assert_eq!(stamps(history.in_range(&range)), vec![(8, 18.0), (9, 19.0)]);
        let empty = StampRange {
            start: Bound::Included(15.0),
            end: Bound::Included(11.0),
        };
        assert_eq!(history.in_range(&empty).count(), 0);
    }

    #[test]
    fn a_republished_set_replaces_every_set_stamped_at_or_after_it() {
        let mut history = TrackHistory::new(100.0, 1000);
        for (seq, stamp) in [(0, 1.0), (1, 2.0), (2, 3.0), (3, 4.0)] {
            history.record(set(seq, stamp));
        }
        // A correction for stamp 2.5 after a late set: the answers for 3 and 4 are superseded.
        history.record(set(4, 2.5));
        history.record(set(5, 3.5));
        assert_eq!(
            stamps(history.in_range(&ALL)),
            vec![(0, 1.0), (1, 2.0), (4, 2.5), (5, 3.5)]
        );
        // The same stamp again: the newest answer wins.
        history.record(set(6, 3.5));
        assert_eq!(history.in_range(&ALL).last().map(|s| s.seq), Some(6));
        assert_eq!(history.len(), 4);
    }

    #[test]
    fn the_history_is_bounded_by_its_span_and_its_count() {
        let mut history = TrackHistory::new(2.0, 1000);
        for i in 0..100 {
            history.record(set(i, i as f64 * 0.1));
        }
        let kept = stamps(history.in_range(&ALL));
        assert_eq!(kept.first().map(|k| k.0), Some(79), "2 s of stamps kept");
        assert_eq!(kept.len(), 21);

        let mut history = TrackHistory::for_publisher(10.0, 1.0);
        for i in 0..100 {
            history.record(set(i, i as f64 * 0.01));
        }
        assert_eq!(history.len(), 11, "at most span × rate + 1 sets");
        assert_eq!(history.in_range(&ALL).last().map(|s| s.seq), Some(99));

        let mut off = TrackHistory::for_publisher(0.0, 30.0);
        off.record(set(0, 1.0));
        assert!(off.is_empty(), "a span of 0 keeps nothing");
        let mut history = TrackHistory::new(10.0, 10);
        history.record(set(0, f64::NAN));
        assert!(history.is_empty(), "a non-finite stamp is not kept");
    }

    #[test]
    fn time_ranges_are_read_in_zenoh_syntax_and_bad_ones_refused() {
        let now = UNIX_EPOCH + Duration::from_secs(1_000);
        let range = requested_range("_time=[now(-30s)..now()];format=json", now)
            .expect("valid")
            .expect("present");
        assert_eq!(range.start, Bound::Included(970.0));
        assert_eq!(range.end, Bound::Included(1000.0));
        assert!(range.contains(985.0) && !range.contains(1000.5) && !range.contains(969.0));
        let open = requested_range("_time=]now(-1m)..]", now).expect("valid");
        assert_eq!(
            open,
            Some(StampRange {
                start: Bound::Excluded(940.0),
                end: Bound::Unbounded
            })
        );
        let fixed = requested_range("_time=[1970-01-01T00:10:00Z..now()[", now)
            .expect("valid")
            .expect("present");
        assert_eq!(fixed.start, Bound::Included(600.0));
        assert_eq!(fixed.end, Bound::Excluded(1000.0));
        assert_eq!(requested_range("format=json", now), Ok(None));
        for bad in [
            "_time=yesterday",
            "_time=[now(-30s)..",
            "_time=",
            "_time=[now()..now()];_time=[now()..now()]",
            "_time=[2020-01-01T00:00:00Z;1e300]",
            "_time=[now(s)..now()]",
        ] {
            assert!(requested_range(bad, now).is_err(), "{bad} accepted");
        }
    }
}
