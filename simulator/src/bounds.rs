//! Axis-aligned boxes: the region a random walk is reflected in.

use serde::{Deserialize, Serialize};

/// An axis-aligned box `{min: [x, y, z], max: [x, y, z]}` in world metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundsBox {
    /// The corner with the smallest coordinates.
    pub min: [f64; 3],
    /// The corner with the largest coordinates.
    pub max: [f64; 3],
}

impl BoundsBox {
    /// Whether `p` lies inside the box (faces included).
    pub fn contains(&self, p: &[f64; 3]) -> bool {
        (0..3).all(|i| self.min[i] <= p[i] && p[i] <= self.max[i])
    }

    /// Folds an unbounded coordinate into `[min, max]` along `axis` as a ball bouncing
    /// between two walls would: the path is mirrored at each face, so a continuous path
    /// stays continuous and a piecewise-linear one stays piecewise linear.
    pub fn reflect(&self, axis: usize, x: f64) -> f64 {
        let (lo, hi) = (self.min[axis], self.max[axis]);
        let width = hi - lo;
        if width <= 0.0 {
            return lo;
        }
        let folded = (x - lo).rem_euclid(2.0 * width);
        lo + if folded > width {
            2.0 * width - folded
        } else {
            folded
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_mirrors_at_both_faces() {
        let b = BoundsBox {
            min: [0.0, -1.0, 2.0],
            max: [3.0, 1.0, 2.0],
        };
        assert_eq!(b.reflect(0, 1.0), 1.0);
        assert_eq!(b.reflect(0, 3.5), 2.5);
        assert_eq!(b.reflect(0, -0.5), 0.5);
        assert_eq!(b.reflect(0, 6.5), 0.5);
        assert_eq!(b.reflect(1, 1.25), 0.75);
        // A flat axis pins the coordinate.
        assert_eq!(b.reflect(2, 7.0), 2.0);
        assert!(b.contains(&[0.0, 1.0, 2.0]));
        assert!(!b.contains(&[0.0, 1.1, 2.0]));
    }
}
