//! Heads from a body's top outline: per column the top-most foreground row of the body, read as
//! a skyline whose peaks stand for heads. A peak counts when its prominence — how far it rises
//! above the lowest point one must cross to reach a higher peak, or the body's bottom when there
//! is none — is at least a threshold, so two heads in one blob (people touching, or joined by a
//! shadow) give two points at their own columns, while the bumps of a noisy outline and the
//! shoulders beside a head give none.

/// A column of the profile with no pixel of the body.
pub const NO_PIXEL: u32 = u32::MAX;

/// The head points `[x, y]` of a body whose outline is `tops` (the top row of each column from
/// `left` on, [`NO_PIXEL`] where the body has no pixel) and whose bottom edge is at row `bottom`.
///
/// A head's y is its peak's top row; its x is the mean centre of the columns around the peak
/// whose top lies within `band_rows` rows of it (pixel `(col, row)` covers `[col, col + 1)`).
/// Heads are returned highest first.
pub fn head_points(
    tops: &[u32],
    left: u32,
    bottom: u32,
    min_prominence: u32,
    band_rows: u32,
) -> Vec<[f64; 2]> {
    let elevation: Vec<i64> = tops
        .iter()
        .map(|&top| {
            if top == NO_PIXEL {
                0
            } else {
                i64::from(bottom) - i64::from(top)
            }
        })
        .collect();
    let mut heads: Vec<(u32, [f64; 2])> = plateaus(&elevation)
        .into_iter()
        .filter(|&(start, end)| prominence(&elevation, start, end) >= i64::from(min_prominence))
        .map(|(start, _)| {
            let top = tops[start];
            (
                top,
                [
                    band_centre(tops, start, top.saturating_add(band_rows)) + f64::from(left),
                    f64::from(top),
                ],
            )
        })
        .collect();
    heads.sort_by(|a, b| a.0.cmp(&b.0).then(a.1[0].total_cmp(&b.1[0])));
    heads.into_iter().map(|(_, point)| point).collect()
}

/// The runs `[start, end]` of equal elevation that are higher than both neighbours (the profile's
/// ends count as ground, elevation 0).
fn plateaus(elevation: &[i64]) -> Vec<(usize, usize)> {
    let at = |i: isize| -> i64 {
        if i < 0 || i as usize >= elevation.len() {
            0
        } else {
            elevation[i as usize]
        }
    };
    let mut out = Vec::new();
    let mut start = 0;
    while start < elevation.len() {
        let mut end = start;
        while end + 1 < elevation.len() && elevation[end + 1] == elevation[start] {
            end += 1;
        }
        let e = elevation[start];
        if e > 0 && at(start as isize - 1) < e && at(end as isize + 1) < e {
            out.push((start, end));
        }
        start = end + 1;
    }
    out
}

/// The prominence of the plateau `[start, end]`. Going left a point as high as the plateau ends
/// the search, going right only a higher one does, so of two equal peaks exactly one keeps its
/// full height.
fn prominence(elevation: &[i64], start: usize, end: usize) -> i64 {
    let peak = elevation[start];
    let lowest_until = |columns: &mut dyn Iterator<Item = usize>, stop_at_equal: bool| -> i64 {
        let mut lowest = peak;
        for i in columns {
            let e = elevation[i];
            if e > peak || (stop_at_equal && e == peak) {
                return lowest;
            }
            lowest = lowest.min(e);
        }
        // No higher peak that side: the descent goes down to the ground.
        0
    };
    let left = lowest_until(&mut (0..start).rev(), true);
    let right = lowest_until(&mut (end + 1..elevation.len()), false);
    peak - left.max(right)
}

/// The mean centre of the contiguous columns around `column` whose top row is at most `limit`.
fn band_centre(tops: &[u32], column: usize, limit: u32) -> f64 {
    let inside = |i: usize| tops[i] <= limit;
    let mut first = column;
    while first > 0 && inside(first - 1) {
        first -= 1;
    }
    let mut last = column;
    while last + 1 < tops.len() && inside(last + 1) {
        last += 1;
    }
    (first + last) as f64 / 2.0 + 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A skyline of flat steps: `(columns, top row)` pairs from left to right.
    fn skyline(steps: &[(usize, u32)]) -> Vec<u32> {
        steps
            .iter()
            .flat_map(|&(n, top)| std::iter::repeat_n(top, n))
            .collect()
    }

    #[test]
    fn two_heads_on_shoulders_give_two_points_at_their_own_columns() {
        // Shoulders at row 60, heads 10 columns wide up to rows 20 and 23, a neck between.
        let tops = skyline(&[(10, 60), (10, 20), (15, 60), (10, 23), (10, 60)]);
        let heads = head_points(&tops, 100, 200, 12, 4);
        println!("{heads:?}");
        assert_eq!(heads, vec![[115.0, 20.0], [140.0, 23.0]]);
    }

    #[test]
    fn bumps_below_the_prominence_are_not_heads() {
        // One head, and a 5-row bump on the shoulder.
        let tops = skyline(&[(10, 60), (10, 20), (5, 60), (4, 55), (10, 60)]);
        let heads = head_points(&tops, 0, 200, 12, 4);
        assert_eq!(heads, vec![[15.0, 20.0]]);
        // Two equal heads: both count, once each.
        let tops = skyline(&[(5, 20), (5, 60), (5, 20)]);
        assert_eq!(
            head_points(&tops, 0, 100, 12, 4),
            vec![[2.5, 20.0], [12.5, 20.0]]
        );
    }

    #[test]
    fn gaps_in_the_outline_are_ground() {
        let tops = skyline(&[(4, 30), (3, NO_PIXEL), (4, 30)]);
        assert_eq!(
            head_points(&tops, 0, 100, 12, 4),
            vec![[2.0, 30.0], [9.0, 30.0]]
        );
        assert!(head_points(&[], 0, 100, 12, 4).is_empty());
    }
}
