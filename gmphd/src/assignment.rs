//! Minimum-total-cost bipartite matching over floating-point costs, with forbidden pairs.
//!
//! Both label continuity (Pham ch. 4.3) and the OSPA/GOSPA metrics need an optimal
//! assignment. `pathfinding::kuhn_munkres` works on integer weights, so costs are
//! scaled to `i64` here, once, with a documented resolution.
//!
//! # Resolution
//!
//! With `n = max(rows, cols)`, finite costs are mapped linearly onto the integers
//! `0..=F` where `F = ⌊10^15 / n²⌋` and the largest finite cost maps to `F`. A
//! forbidden pair costs `n·F + 1`, more than any complete assignment of allowed
//! pairs, so the solver first maximises the number of allowed pairs and only then
//! minimises their total cost (Pham's "maximum matching with minimum weight").
//! Every sum the solver forms stays below about `10^15`, far from `i64` overflow.
//! The chosen assignment is optimal up to rounding: its total cost is within
//! `n · max_cost / F` of the true minimum (relative `n³ · 10^-15`, i.e. 10^-6 for
//! 1000 × 1000 problems). Callers recompute totals from the float costs.

mod groups;

use groups::connected_groups;
use pathfinding::kuhn_munkres::kuhn_munkres_min;
use pathfinding::matrix::Matrix;
use thiserror::Error;

/// Integer budget the scaled costs of one whole assignment must stay below.
const INTEGER_BUDGET: f64 = 1e15;

/// Why a cost matrix was rejected.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AssignmentError {
    /// A cost was NaN, infinite or negative.
    #[error(
        "assignment cost at row {row}, column {col} is {value}; costs must be finite and >= 0"
    )]
    InvalidCost {
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
        /// The offending value.
        value: f64,
    },
    /// An allowed pair of [`SparseCosts`] names a row or column outside the problem.
    #[error("allowed pair ({row}, {col}) lies outside the {rows}x{cols} problem")]
    PairOutOfRange {
        /// Row of the offending pair.
        row: usize,
        /// Column of the offending pair.
        col: usize,
        /// Number of rows of the problem.
        rows: usize,
        /// Number of columns of the problem.
        cols: usize,
    },
    /// The entry vector does not have `rows × cols` entries.
    #[error("cost matrix declared {rows}x{cols} but holds {len} entries")]
    ShapeMismatch {
        /// Declared number of rows.
        rows: usize,
        /// Declared number of columns.
        cols: usize,
        /// Number of entries given.
        len: usize,
    },
}

/// A dense `rows × cols` cost matrix; `None` marks a forbidden pair.
#[derive(Debug, Clone, PartialEq)]
pub struct CostMatrix {
    rows: usize,
    cols: usize,
    entries: Vec<Option<f64>>,
}

impl CostMatrix {
    /// Builds the matrix from a function of `(row, col)`; `None` forbids the pair.
    pub fn from_fn(
        rows: usize,
        cols: usize,
        mut cost: impl FnMut(usize, usize) -> Option<f64>,
    ) -> Result<Self, AssignmentError> {
        let mut entries = Vec::with_capacity(rows * cols);
        for row in 0..rows {
            for col in 0..cols {
                entries.push(cost(row, col));
            }
        }
        Self::from_row_major(rows, cols, entries)
    }

    /// Builds the matrix from row-major entries; `None` forbids the pair.
    pub fn from_row_major(
        rows: usize,
        cols: usize,
        entries: Vec<Option<f64>>,
    ) -> Result<Self, AssignmentError> {
        if entries.len() != rows * cols {
            return Err(AssignmentError::ShapeMismatch {
                rows,
                cols,
                len: entries.len(),
            });
        }
        for (index, entry) in entries.iter().enumerate() {
            if let Some(value) = *entry {
                if !value.is_finite() || value < 0.0 {
                    return Err(AssignmentError::InvalidCost {
                        row: index / cols,
                        col: index % cols,
                        value,
                    });
                }
            }
        }
        Ok(Self {
            rows,
            cols,
            entries,
        })
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The cost of pairing `row` with `col`, `None` when forbidden or out of range.
    pub fn get(&self, row: usize, col: usize) -> Option<f64> {
        if row >= self.rows || col >= self.cols {
            return None;
        }
        self.entries[row * self.cols + col]
    }
}

/// One pair of an optimal matching.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchedPair {
    /// Row index.
    pub row: usize,
    /// Column index.
    pub col: usize,
    /// The (unscaled) cost of the pair.
    pub cost: f64,
}

/// The maximum-cardinality, minimum-total-cost matching of allowed pairs.
///
/// Every row or column appears at most once; forbidden pairs never appear. Pairs
/// are returned sorted by row.
///
/// Rows and columns that no chain of allowed pairs connects cannot affect each other's
/// assignment, and both objectives (count and total cost) add up over such groups: each
/// connected group is solved on its own, a lone allowed pair directly. Label continuity
/// mostly meets many small groups (each track near its own estimate), where this replaces
/// one O(n³) solution by a few tiny ones.
pub fn min_cost_matching(costs: &CostMatrix) -> Vec<MatchedPair> {
    let allowed: Vec<(usize, usize, f64)> = (0..costs.rows)
        .flat_map(|row| {
            (0..costs.cols).filter_map(move |col| Some((row, col, costs.get(row, col)?)))
        })
        .collect();
    matching(costs.rows, costs.cols, &allowed, Some(costs))
}

/// [`min_cost_matching`] of the matrix whose allowed pairs `costs` lists, without
/// building the matrix: for problems where each row allows a few columns (label
/// continuity), whose dense matrix would be mostly forbidden pairs.
pub fn min_cost_matching_sparse(costs: &SparseCosts) -> Vec<MatchedPair> {
    matching(costs.rows, costs.cols, &costs.allowed, None)
}

/// The allowed pairs of a `rows × cols` assignment problem, one by one; every pair not
/// listed is forbidden.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseCosts {
    rows: usize,
    cols: usize,
    allowed: Vec<(usize, usize, f64)>,
}

impl SparseCosts {
    /// The problem of `rows` × `cols` whose allowed pairs are `allowed` as (row, column,
    /// cost); a pair listed twice costs what its last entry says. Costs must be finite and
    /// ≥ 0, and rows and columns in range.
    pub fn new(
        rows: usize,
        cols: usize,
        allowed: Vec<(usize, usize, f64)>,
    ) -> Result<Self, AssignmentError> {
        for &(row, col, value) in &allowed {
            if row >= rows || col >= cols {
                return Err(AssignmentError::PairOutOfRange {
                    row,
                    col,
                    rows,
                    cols,
                });
            }
            if !value.is_finite() || value < 0.0 {
                return Err(AssignmentError::InvalidCost { row, col, value });
            }
        }
        Ok(Self {
            rows,
            cols,
            allowed,
        })
    }
}

/// [`min_cost_matching`] over the allowed pairs `allowed` of a `rows` × `cols` problem;
/// `whole` is its dense matrix when the caller has it.
fn matching(
    rows: usize,
    cols: usize,
    allowed: &[(usize, usize, f64)],
    whole: Option<&CostMatrix>,
) -> Vec<MatchedPair> {
    let groups = connected_groups(rows, cols, allowed);
    if groups.len() == 1 && groups.rows(0).len() == rows && groups.cols(0).len() == cols {
        return match whole {
            Some(costs) => solve_group(costs),
            None => solve_group(&group_matrix(groups.get(0), allowed.iter())),
        };
    }
    // The allowed pairs by group, each group's in their listed order (a counting sort):
    // group g's are `by_group[ends[g]..ends[g + 1]]`, as indices into `allowed`.
    let mut ends = vec![0usize; groups.len() + 1];
    for pair in allowed {
        ends[groups.of_row(pair.0) + 1] += 1;
    }
    for g in 0..groups.len() {
        ends[g + 1] += ends[g];
    }
    let mut next = ends.clone();
    let mut by_group = vec![0usize; allowed.len()];
    for (i, pair) in allowed.iter().enumerate() {
        let g = groups.of_row(pair.0);
        by_group[next[g]] = i;
        next[g] += 1;
    }
    let mut pairs = Vec::with_capacity(rows.min(cols));
    for g in 0..groups.len() {
        let mut group_allowed = by_group[ends[g]..ends[g + 1]].iter().map(|&i| &allowed[i]);
        let (group_rows, group_cols) = groups.get(g);
        if let ([row], [col]) = (group_rows, group_cols) {
            // A lone allowed pair (its last listed cost).
            let &(_, _, cost) = group_allowed
                .next_back()
                .expect("a group has an allowed pair");
            pairs.push(MatchedPair {
                row: *row,
                col: *col,
                cost,
            });
            continue;
        }
        let costs = group_matrix((group_rows, group_cols), group_allowed);
        pairs.extend(solve_group(&costs).into_iter().map(|p| MatchedPair {
            row: group_rows[p.row],
            col: group_cols[p.col],
            cost: p.cost,
        }));
    }
    pairs.sort_by_key(|p| p.row);
    pairs
}

/// The dense matrix of one group (its rows and columns ascending) from its allowed pairs
/// (a later entry of a pair overwrites an earlier one).
fn group_matrix<'a>(
    (group_rows, group_cols): (&[usize], &[usize]),
    allowed: impl Iterator<Item = &'a (usize, usize, f64)>,
) -> CostMatrix {
    let position = |sorted: &[usize], node: usize| {
        sorted
            .binary_search(&node)
            .expect("an allowed pair's nodes are in its group")
    };
    let cols = group_cols.len();
    let mut entries = vec![None; group_rows.len() * cols];
    for &(row, col, cost) in allowed {
        entries[position(group_rows, row) * cols + position(group_cols, col)] = Some(cost);
    }
    CostMatrix {
        rows: group_rows.len(),
        cols,
        entries,
    }
}

/// [`min_cost_matching`] of one whole matrix by Kuhn–Munkres.
fn solve_group(costs: &CostMatrix) -> Vec<MatchedPair> {
    if costs.rows == 0 || costs.cols == 0 {
        return Vec::new();
    }
    // kuhn_munkres needs rows <= columns; solve the transpose otherwise.
    let transposed = costs.rows > costs.cols;
    let (short, long) = if transposed {
        (costs.cols, costs.rows)
    } else {
        (costs.rows, costs.cols)
    };
    let entry = |i: usize, j: usize| {
        if transposed {
            costs.get(j, i)
        } else {
            costs.get(i, j)
        }
    };

    let n = long as f64;
    let steps = (INTEGER_BUDGET / (n * n)).floor().max(1.0);
    let max_cost = costs
        .entries
        .iter()
        .flatten()
        .fold(0.0_f64, |acc, &c| acc.max(c));
    // All-zero costs: any scale works, use 1 to avoid dividing by zero.
    let scale = if max_cost > 0.0 {
        steps / max_cost
    } else {
        1.0
    };
    let forbidden = (n * steps) as i64 + 1;
    let weights = Matrix::from_fn(short, long, |(i, j)| match entry(i, j) {
        Some(c) => (c * scale).round() as i64,
        None => forbidden,
    });
    let (_, columns) = kuhn_munkres_min(&weights);

    let mut pairs: Vec<MatchedPair> = columns
        .into_iter()
        .enumerate()
        .filter_map(|(i, j)| {
            let cost = entry(i, j)?;
            let (row, col) = if transposed { (j, i) } else { (i, j) };
            Some(MatchedPair { row, col, cost })
        })
        .collect();
    pairs.sort_by_key(|p| p.row);
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Total cost and count of a matching.
    fn score(pairs: &[MatchedPair]) -> (usize, f64) {
        (pairs.len(), pairs.iter().map(|p| p.cost).sum())
    }

    #[test]
    fn solving_groups_apart_is_as_good_as_solving_the_whole() {
        let mut rng = ChaCha8Rng::seed_from_u64(99);
        let mut uniform = move || rng.gen::<f64>();
        for trial in 0..200 {
            let (rows, cols) = (1 + trial % 13, 1 + (trial * 7) % 11);
            // Sparse: points on a line, pairs allowed only when close.
            let xs: Vec<f64> = (0..rows).map(|_| 10.0 * uniform()).collect();
            let ys: Vec<f64> = (0..cols).map(|_| 10.0 * uniform()).collect();
            let costs = CostMatrix::from_fn(rows, cols, |r, c| {
                let d = (xs[r] - ys[c]).abs();
                (d < 1.5).then_some(d)
            })
            .unwrap();
            let grouped = min_cost_matching(&costs);
            let allowed = (0..rows)
                .flat_map(|r| (0..cols).map(move |c| (r, c)))
                .filter_map(|(r, c)| Some((r, c, costs.get(r, c)?)))
                .rev()
                .collect();
            let sparse = SparseCosts::new(rows, cols, allowed).unwrap();
            assert_eq!(min_cost_matching_sparse(&sparse), grouped, "trial {trial}");
            let whole = solve_group(&costs);
            let (count, total) = score(&grouped);
            let (whole_count, whole_total) = score(&whole);
            assert_eq!(count, whole_count, "trial {trial}");
            assert!((total - whole_total).abs() < 1e-9, "trial {trial}");
            assert!(grouped.windows(2).all(|w| w[0].row < w[1].row));
            let mut cols_used: Vec<usize> = grouped.iter().map(|p| p.col).collect();
            cols_used.sort_unstable();
            cols_used.dedup();
            assert_eq!(cols_used.len(), grouped.len());
            assert!(grouped
                .iter()
                .all(|p| costs.get(p.row, p.col) == Some(p.cost)));
        }
    }
}
