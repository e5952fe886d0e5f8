//! What the other people already explain: the union of their regions, row by row.
//!
//! The separable likelihood of Hoseinnezhad, Vo & Vu (eq. 20) scores each person's region on its own,
//! which holds while regions do not overlap. When one person stands in front of another the pixels they
//! share are foreground once, not twice: a person is scored only on the pixels the others' estimated
//! regions leave free. So a head hidden inside a nearer person's outline is neither evidence for nor
//! against the hidden person (it is not a miss), and a second hypothesis on a person already explained
//! finds nothing to gain there.

use super::foreground::ForegroundMap;
use super::region::{Region, RowSpan};

/// Disjoint column intervals per row: the union of some regions.
#[derive(Debug, Clone, Default)]
pub struct Cover {
    /// Row-sorted `(row, left, right)`, merged so that intervals of one row do not overlap.
    intervals: Vec<(i32, f32, f32)>,
    /// For each row from `first_row`, the index of its first interval (one more entry at the end).
    starts: Vec<usize>,
    first_row: i32,
}

impl Cover {
    /// The union of `regions`.
    pub fn from_regions<'a>(regions: impl IntoIterator<Item = &'a Region>) -> Self {
        let mut raw: Vec<(i32, f32, f32)> = regions
            .into_iter()
            .flat_map(|r| r.spans.iter())
            .filter(|s| s.right > s.left)
            .map(|s| (s.row, s.left, s.right))
            .collect();
        if raw.is_empty() {
            return Self::default();
        }
        raw.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut intervals: Vec<(i32, f32, f32)> = Vec::with_capacity(raw.len());
        for (row, left, right) in raw {
            match intervals.last_mut() {
                Some(last) if last.0 == row && left <= last.2 => last.2 = last.2.max(right),
                _ => intervals.push((row, left, right)),
            }
        }
        let first_row = intervals[0].0;
        let last_row = intervals[intervals.len() - 1].0;
        let mut starts = Vec::with_capacity((last_row - first_row + 2) as usize);
        let mut k = 0;
        for row in first_row..=last_row + 1 {
            while k < intervals.len() && intervals[k].0 < row {
                k += 1;
            }
            starts.push(k);
        }
        Self {
            intervals,
            starts,
            first_row,
        }
    }

    /// The intervals of `row`.
    fn row(&self, row: i32) -> &[(i32, f32, f32)] {
        let index = row - self.first_row;
        if self.starts.is_empty() || index < 0 || index as usize + 1 >= self.starts.len() {
            return &[];
        }
        let i = index as usize;
        &self.intervals[self.starts[i]..self.starts[i + 1]]
    }

    /// Length of `span` (columns) that the union covers.
    pub fn covered_length(&self, span: &RowSpan) -> f32 {
        self.row(span.row)
            .iter()
            .map(|&(_, a, b)| (b.min(span.right) - a.max(span.left)).max(0.0))
            .sum()
    }

    /// The score of `span` over the pixels the union leaves free (see [`ForegroundMap::row_sum`]).
    pub fn free_sum(&self, map: &ForegroundMap, span: &RowSpan) -> f32 {
        if self.intervals.is_empty() {
            return map.span_sum(span);
        }
        let mut sum = map.row_sum(span.row, span.left, span.right);
        for &(_, a, b) in self.row(span.row) {
            let (left, right) = (a.max(span.left), b.min(span.right));
            if right > left {
                sum -= map.row_sum(span.row, left, right);
            }
        }
        span.weight * sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn region(spans: &[(i32, f32, f32)]) -> Region {
        Region {
            spans: spans
                .iter()
                .map(|&(row, left, right)| RowSpan {
                    row,
                    left,
                    right,
                    weight: 1.0,
                })
                .collect(),
            head_spans: 0,
            shoulder_row: 0.0,
        }
    }

    #[test]
    fn the_union_leaves_only_the_free_part_of_a_span() {
        let others = [
            region(&[(0, 2.0, 4.0), (1, 0.0, 1.0)]),
            region(&[(0, 3.0, 6.0)]),
        ];
        let cover = Cover::from_regions(&others);
        let mut map = ForegroundMap::default();
        map.fill(8, 2, &[1.0; 16], 0.0);
        let span = RowSpan {
            row: 0,
            left: 0.0,
            right: 8.0,
            weight: 1.0,
        };
        assert!((cover.covered_length(&span) - 4.0).abs() < 1e-6);
        assert!((cover.free_sum(&map, &span) - 4.0).abs() < 1e-6);
        let below = RowSpan { row: 1, ..span };
        assert!((cover.free_sum(&map, &below) - 7.0).abs() < 1e-6);
        let outside = RowSpan { row: 5, ..span };
        assert_eq!(cover.covered_length(&outside), 0.0);
        assert_eq!(Cover::default().covered_length(&span), 0.0);
    }
}
