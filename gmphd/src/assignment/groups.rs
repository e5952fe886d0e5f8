//! The groups of an assignment problem that no chain of allowed pairs connects to each
//! other: each is solved on its own (see [`super::min_cost_matching`]).

use petgraph::unionfind::UnionFind;

/// The groups of [`connected_groups`], their rows and columns each in one list (most
/// groups are a single pair, which would otherwise take two allocations each).
pub(super) struct Groups {
    /// Every group's rows, ascending within a group; group g's end at `row_ends[g]`.
    rows: Vec<usize>,
    row_ends: Vec<usize>,
    /// Likewise their columns.
    cols: Vec<usize>,
    col_ends: Vec<usize>,
    /// The group of each row (`usize::MAX` for rows without an allowed pair).
    group_of_row: Vec<usize>,
}

impl Groups {
    pub(super) fn len(&self) -> usize {
        self.row_ends.len()
    }

    pub(super) fn rows(&self, g: usize) -> &[usize] {
        let start = g
            .checked_sub(1)
            .map_or(0, |previous| self.row_ends[previous]);
        &self.rows[start..self.row_ends[g]]
    }

    pub(super) fn cols(&self, g: usize) -> &[usize] {
        let start = g
            .checked_sub(1)
            .map_or(0, |previous| self.col_ends[previous]);
        &self.cols[start..self.col_ends[g]]
    }

    /// Group g's rows and columns.
    pub(super) fn get(&self, g: usize) -> (&[usize], &[usize]) {
        (self.rows(g), self.cols(g))
    }

    /// The group of a row that has an allowed pair.
    pub(super) fn of_row(&self, row: usize) -> usize {
        self.group_of_row[row]
    }
}

/// The rows and columns (ascending) of each group that allowed pairs connect, ordered by
/// their first row; rows and columns without any allowed pair are left out.
pub(super) fn connected_groups(
    rows: usize,
    cols: usize,
    allowed: &[(usize, usize, f64)],
) -> Groups {
    // Rows are nodes 0..R, columns R..R+C; each allowed pair links its two.
    let mut sets = UnionFind::<usize>::new(rows + cols);
    let mut linked = vec![false; rows + cols];
    for &(row, col, _) in allowed {
        sets.union(row, rows + col);
        linked[row] = true;
        linked[rows + col] = true;
    }
    // Each linked node's group, numbered in order of first appearance (a group's first
    // node is its first row: rows come before columns, and every group has a row).
    let mut group_of_set = vec![usize::MAX; rows + cols];
    let mut group_of_node = vec![usize::MAX; rows + cols];
    let mut count = 0;
    for node in (0..rows + cols).filter(|&n| linked[n]) {
        let set = sets.find_mut(node);
        if group_of_set[set] == usize::MAX {
            group_of_set[set] = count;
            count += 1;
        }
        group_of_node[node] = group_of_set[set];
    }
    // Rows, then columns, placed by group (a counting sort keeps them ascending).
    let place = |nodes: std::ops::Range<usize>, offset: usize| {
        let mut ends = vec![0usize; count];
        for node in nodes.clone().filter(|&n| linked[n]) {
            ends[group_of_node[node]] += 1;
        }
        for g in 1..count {
            ends[g] += ends[g - 1];
        }
        let mut next: Vec<usize> = (0..count)
            .map(|g| g.checked_sub(1).map_or(0, |previous| ends[previous]))
            .collect();
        let mut placed = vec![0usize; ends.last().copied().unwrap_or(0)];
        for node in nodes.filter(|&n| linked[n]) {
            let g = group_of_node[node];
            placed[next[g]] = node - offset;
            next[g] += 1;
        }
        (placed, ends)
    };
    let (row_list, row_ends) = place(0..rows, 0);
    let (col_list, col_ends) = place(rows..rows + cols, rows);
    group_of_node.truncate(rows);
    Groups {
        rows: row_list,
        row_ends,
        cols: col_list,
        col_ends,
        group_of_row: group_of_node,
    }
}
