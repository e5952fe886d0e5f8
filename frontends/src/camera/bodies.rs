//! Pieces of one body joined: background subtraction splits a person wherever the clothes match
//! what is behind them (trousers the colour of the floor), and each piece above the size limit
//! would otherwise report a head of its own. Pieces stacked one over the other within a body's
//! width, or side by side at the same height, are taken as one body; the heads of a body then
//! come from its whole outline (`top_profile.rs`), so joining the pieces of two people who touch
//! loses neither head.

use petgraph::unionfind::UnionFind;

/// The bounding box of a connected piece of foreground, `[left, top, right, bottom)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PieceBox {
    /// Leftmost column.
    pub left: u32,
    /// Topmost row.
    pub top: u32,
    /// One past the rightmost column.
    pub right: u32,
    /// One past the bottom row.
    pub bottom: u32,
}

impl PieceBox {
    fn width(&self) -> u32 {
        self.right - self.left
    }

    fn height(&self) -> u32 {
        self.bottom - self.top
    }
}

/// How far apart pieces of one body may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JoinRule {
    /// Pieces that share at least half the narrower one's columns join when the rows between
    /// them are at most this many.
    pub stacked_gap_rows: u32,
    /// Pieces that share at least half the shorter one's rows join when the columns between
    /// them are at most this many.
    pub beside_gap_cols: u32,
}

impl JoinRule {
    /// Whether two pieces belong to one body.
    pub fn joins(&self, a: &PieceBox, b: &PieceBox) -> bool {
        let overlap = |lo_a: u32, hi_a: u32, lo_b: u32, hi_b: u32| {
            i64::from(hi_a.min(hi_b)) - i64::from(lo_a.max(lo_b))
        };
        let columns = overlap(a.left, a.right, b.left, b.right);
        let rows = overlap(a.top, a.bottom, b.top, b.bottom);
        let stacked = 2 * columns >= i64::from(a.width().min(b.width()))
            && -rows <= i64::from(self.stacked_gap_rows);
        let beside = 2 * rows >= i64::from(a.height().min(b.height()))
            && -columns <= i64::from(self.beside_gap_cols);
        stacked || beside
    }
}

/// The body each piece belongs to, numbered 0.. in order of each body's first piece.
pub fn group_pieces(pieces: &[PieceBox], rule: JoinRule) -> Vec<usize> {
    let mut sets = UnionFind::<usize>::new(pieces.len());
    for i in 0..pieces.len() {
        for j in i + 1..pieces.len() {
            if rule.joins(&pieces[i], &pieces[j]) {
                sets.union(i, j);
            }
        }
    }
    let mut numbers = vec![usize::MAX; pieces.len()];
    let mut next = 0;
    (0..pieces.len())
        .map(|i| {
            let root = sets.find(i);
            if numbers[root] == usize::MAX {
                numbers[root] = next;
                next += 1;
            }
            numbers[root]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn piece(left: u32, top: u32, right: u32, bottom: u32) -> PieceBox {
        PieceBox {
            left,
            top,
            right,
            bottom,
        }
    }

    const RULE: JoinRule = JoinRule {
        stacked_gap_rows: 20,
        beside_gap_cols: 3,
    };

    #[test]
    fn a_split_body_is_one_and_two_people_apart_are_two() {
        let torso = piece(100, 50, 140, 150);
        let legs = piece(105, 165, 135, 260);
        let far_legs = piece(105, 190, 135, 260);
        let right_half = piece(141, 60, 160, 150);
        let other_person = piece(200, 50, 240, 260);
        assert!(RULE.joins(&torso, &legs), "15 rows apart under the torso");
        assert!(!RULE.joins(&torso, &far_legs), "40 rows apart");
        assert!(
            RULE.joins(&torso, &right_half),
            "one column apart at the same height"
        );
        assert!(!RULE.joins(&torso, &other_person));
        let groups = group_pieces(&[torso, other_person, legs, right_half], RULE);
        println!("{groups:?}");
        assert_eq!(groups, vec![0, 1, 0, 0]);
    }
}
