//! Interval stabbing along one coordinate: which items' intervals contain each query value.
//!
//! Gates in the filter — the χ² gate of a component–measurement pair, the merge gate of
//! the reducer, the ancestry gate of label recovery — all fail as soon as one coordinate's
//! difference exceeds √(γ σ²) along it. Sorting the queries along one coordinate and
//! stabbing each item's interval [centre − half, centre + half] into them (two binary
//! searches) finds every pair that can pass without testing the others: J log |Q| plus
//! the near pairs, instead of J × |Q|.
//!
//! The hits only pre-select: the caller still runs its full test on each. Every interval
//! is widened by a hair so that rounding in the search never drops a pair whose exact
//! difference lies on the boundary, and an item whose interval is not finite (a NaN or
//! infinite centre or width) hits every query, so pre-selection never changes a result.

/// Relative widening of every interval (see the module documentation).
const SLACK: f64 = 1e-9;

/// The run of `sorted` (ascending by value) inside [centre − half, centre + half], widened
/// by the slack; `None` when the interval is not finite.
pub(crate) fn run<T>(sorted: &[(f64, T)], centre: f64, half: f64) -> Option<(usize, usize)> {
    if !(centre.is_finite() && half.is_finite()) {
        return None;
    }
    let slack = SLACK * (half.abs() + centre.abs()) + f64::MIN_POSITIVE;
    let (low, high) = (centre - half - slack, centre + half + slack);
    let start = sorted.partition_point(|(v, _)| *v < low);
    let end = sorted.partition_point(|(v, _)| *v <= high);
    Some((start, end.max(start)))
}

/// [`run`] around each entry's own value, `runs_of_each(sorted, half)[k] ==
/// run(sorted, sorted[k].0, half)` (`None` where that is not finite), in one pass: the
/// runs of neighbouring centres start and end near each other, so each is found by walking
/// from the previous one instead of by two binary searches (the same comparisons decide
/// where a walk stops, so the runs are the same).
pub(crate) fn runs_of_each<T>(sorted: &[(f64, T)], half: f64) -> Vec<Option<(usize, usize)>> {
    let (mut start, mut end) = (0, 0);
    sorted
        .iter()
        .map(|&(centre, _)| {
            if !(centre.is_finite() && half.is_finite()) {
                return None;
            }
            let slack = SLACK * (half.abs() + centre.abs()) + f64::MIN_POSITIVE;
            let (low, high) = (centre - half - slack, centre + half + slack);
            // The partition points of `v < low` and `v <= high`, walked to from the last.
            while start > 0 && sorted[start - 1].0 >= low {
                start -= 1;
            }
            while start < sorted.len() && sorted[start].0 < low {
                start += 1;
            }
            while end > 0 && sorted[end - 1].0 > high {
                end -= 1;
            }
            while end < sorted.len() && sorted[end].0 <= high {
                end += 1;
            }
            Some((start, end.max(start)))
        })
        .collect()
}

/// For each query, the items whose interval contains it, ascending (compressed rows).
#[derive(Debug, Clone, Default)]
pub(crate) struct IntervalHits {
    /// Query q's items are `items[offsets[q]..offsets[q + 1]]` (half the bytes of `usize`
    /// indices to zero and fill: the update's list runs to thousands of pairs).
    offsets: Vec<usize>,
    items: Vec<u32>,
}

impl IntervalHits {
    /// Stabs the intervals `(centre, half_width)` of items 0, 1, … into the query values
    /// `queries` (a `None` query is hit by no item: the caller tests it another way).
    pub(crate) fn build(
        queries: &[Option<f64>],
        intervals: impl ExactSizeIterator<Item = (f64, f64)>,
    ) -> Self {
        // (value, query index), sorted by value.
        let mut sorted: Vec<(f64, usize)> = queries
            .iter()
            .enumerate()
            .filter_map(|(q, value)| value.map(|v| (v, q)))
            .collect();
        // (Distinct pairs: the unstable sort orders them as a stable one would.)
        sorted.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));

        // The run of `sorted` each item reaches.
        let runs: Vec<(usize, usize)> = intervals
            .map(|(centre, half)| run(&sorted, centre, half).unwrap_or((0, sorted.len())))
            .collect();

        // Counting pass, then a fill pass in item order, so that rows come out ascending.
        let mut offsets = vec![0usize; queries.len() + 1];
        for &(start, end) in &runs {
            for &(_, q) in &sorted[start..end] {
                offsets[q + 1] += 1;
            }
        }
        for q in 0..queries.len() {
            offsets[q + 1] += offsets[q];
        }
        let mut next = offsets.clone();
        let mut items = vec![0u32; offsets[queries.len()]];
        for (item, &(start, end)) in runs.iter().enumerate() {
            let item = u32::try_from(item).expect("fewer than 2^32 intervals");
            for &(_, q) in &sorted[start..end] {
                items[next[q]] = item;
                next[q] += 1;
            }
        }
        Self { offsets, items }
    }

    /// The items whose interval contains query `q`, ascending.
    pub(crate) fn hits(&self, q: usize) -> &[u32] {
        &self.items[self.offsets[q]..self.offsets[q + 1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_containing_intervals_in_item_order() {
        let queries = [Some(0.0), Some(5.0), None, Some(-3.0), Some(10.0)];
        let intervals = vec![
            (1.0, 1.0),
            (4.0, 2.0),
            (0.0, 100.0),
            (f64::NAN, 1.0),
            (10.0, 0.0),
        ];
        let hits = IntervalHits::build(&queries, intervals.into_iter());
        assert_eq!(hits.hits(0), &[0, 2, 3]);
        assert_eq!(hits.hits(1), &[1, 2, 3]);
        assert_eq!(hits.hits(2), &[] as &[u32]);
        assert_eq!(hits.hits(3), &[2, 3]);
        // A zero-width interval still contains its own centre.
        assert_eq!(hits.hits(4), &[2, 3, 4]);
    }

    #[test]
    fn runs_of_each_are_the_binary_searches_runs() {
        let values = [
            -3.0,
            -1.0,
            -1.0,
            -0.5,
            0.0,
            0.1,
            0.3,
            0.30000000000000004,
            1.0,
            1.0,
            2.5,
            7.0,
            1e9,
        ];
        for half in [0.0, 0.2, 0.5, 1.0, 4.0, 1e10, f64::INFINITY] {
            let sorted: Vec<(f64, usize)> = values.iter().copied().zip(0..).collect();
            let runs = runs_of_each(&sorted, half);
            for (k, &(centre, _)) in sorted.iter().enumerate() {
                assert_eq!(runs[k], run(&sorted, centre, half), "{centre} ± {half}");
            }
        }
    }

    #[test]
    fn boundaries_are_kept_despite_rounding() {
        // 0.1 + 0.2 rounds above 0.3: a difference computed as q − centre may equal the half
        // width although centre + half < q in floating point.
        let queries = [Some(0.1 + 0.2)];
        let hits = IntervalHits::build(&queries, [(0.1, 0.2)].into_iter());
        assert_eq!(hits.hits(0), &[0]);
    }
}
