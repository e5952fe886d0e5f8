//! A reflected random walk whose position at any time is a pure function of
//! `(seed, target id, time)`.
//!
//! # Construction
//!
//! Time since the target appeared is cut into knots `dt = knot_interval_s` apart. Per axis,
//! the walk's unreflected offset at knot `i` is `σ·√dt·S(i)`, where `S` is a standard
//! random walk (unit-variance Gaussian steps, `S(0) = 0`) built so that `S(i)` can be
//! computed directly, without stepping through knots `0..i`:
//!
//! * knots are grouped in blocks of `B = 1024`; block `c` ends `E_c = √B·N(c)` above where
//!   it starts, so `S(b·B) = Σ_{c<b} E_c` (a handful of terms even for hours of walk);
//! * inside a block, `S` is filled in by Lévy's Brownian-bridge construction: the value at
//!   the midpoint `m` of a dyadic interval `[l, h]` is `(S(l) + S(h))/2 + √((h−l)/4)·N(b, m)`,
//!   which is exactly the conditional law of a random walk's midpoint, so the result is a
//!   random walk in distribution; reaching knot `j` takes at most `log₂ B = 10` steps.
//!
//! Every `N(…)` above is a standard normal drawn from the hash of
//! `(seed, "random_walk", target id, axis, block or node)` (see `seeding`), so any process
//! evaluating any time gets the same value. Between knots the path is linear; the linear
//! path is then folded into the bounds box by mirror reflection ([`BoundsBox::reflect`]).
//! The result is continuous, stays in the box, and starts at `position`.

use serde::{Deserialize, Serialize};

use crate::bounds::BoundsBox;
use crate::seeding::StreamKey;

/// Knots per block of the construction (a power of two, so the bisection is exact).
const KNOTS_PER_BLOCK: u64 = 1024;
/// Key tag of a block's end-to-end increment.
const BLOCK_END_TAG: u64 = 1;
/// Key tag of a bridge midpoint inside a block.
const BRIDGE_TAG: u64 = 2;

/// The knot spacing used when a scenario does not give one, in seconds.
pub const DEFAULT_KNOT_INTERVAL_S: f64 = 1.0;

/// A random walk `{position, std, bounds, knot_interval_s}` reflected in a box.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomWalk {
    /// Where the walk starts, at the target's appear time (world metres, inside `bounds`).
    pub position: [f64; 3],
    /// Per-axis diffusion in m/√s: the displacement over `Δt` seconds (before reflection)
    /// has standard deviation `std·√Δt` on each axis. Zero pins an axis.
    pub std: [f64; 3],
    /// The box the walk is reflected in.
    pub bounds: BoundsBox,
    /// Seconds between the walk's knots (default [`DEFAULT_KNOT_INTERVAL_S`]); the path is
    /// linear between knots, so this sets how often the walker turns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knot_interval_s: Option<f64>,
}

impl RandomWalk {
    /// The knot spacing in seconds.
    pub fn knot_interval(&self) -> f64 {
        self.knot_interval_s.unwrap_or(DEFAULT_KNOT_INTERVAL_S)
    }

    /// The position `since_appear` seconds after the target appeared (negative times are
    /// treated as zero), for the run `seed` and target `target_id`.
    pub fn position_at(&self, seed: u64, target_id: u64, since_appear: f64) -> [f64; 3] {
        let dt = self.knot_interval();
        let knots = since_appear.max(0.0) / dt;
        // Knot indices beyond 2^53 s/dt are far outside any scenario; the cast saturates.
        let knot = knots.floor() as u64;
        let fraction = knots - knot as f64;
        let walk_key = StreamKey::new(seed, "random_walk").with(target_id);
        let mut position = [0.0; 3];
        for (axis, out) in position.iter_mut().enumerate() {
            let axis_key = walk_key.with(axis as u64);
            let before = standard_walk_at_knot(axis_key, knot);
            let after = standard_walk_at_knot(axis_key, knot + 1);
            let offset = before + (after - before) * fraction;
            let raw = self.position[axis] + self.std[axis] * dt.sqrt() * offset;
            *out = self.bounds.reflect(axis, raw);
        }
        position
    }
}

/// `S(knot)` of a standard random walk (unit-variance steps, `S(0) = 0`) on one axis.
fn standard_walk_at_knot(axis_key: StreamKey, knot: u64) -> f64 {
    let block = knot / KNOTS_PER_BLOCK;
    let within = knot % KNOTS_PER_BLOCK;
    let block_scale = (KNOTS_PER_BLOCK as f64).sqrt();
    let block_end = |c: u64| block_scale * axis_key.with(BLOCK_END_TAG).with(c).standard_normal();
    let block_start: f64 = (0..block).map(block_end).sum();
    if within == 0 {
        return block_start;
    }
    // Bisect [0, B] down to `within`, drawing each midpoint from its bridge law.
    let (mut low, mut high) = (0u64, KNOTS_PER_BLOCK);
    let (mut low_value, mut high_value) = (0.0, block_end(block));
    loop {
        let mid = (low + high) / 2;
        let spread = ((high - low) as f64 / 4.0).sqrt();
        let noise = axis_key
            .with(BRIDGE_TAG)
            .with(block)
            .with(mid)
            .standard_normal();
        let mid_value = 0.5 * (low_value + high_value) + spread * noise;
        match within.cmp(&mid) {
            std::cmp::Ordering::Equal => return block_start + mid_value,
            std::cmp::Ordering::Less => (high, high_value) = (mid, mid_value),
            std::cmp::Ordering::Greater => (low, low_value) = (mid, mid_value),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn open_walk(std: f64) -> RandomWalk {
        RandomWalk {
            position: [0.0; 3],
            std: [std; 3],
            bounds: BoundsBox {
                min: [-1e9; 3],
                max: [1e9; 3],
            },
            knot_interval_s: Some(0.5),
        }
    }

    #[test]
    fn steps_are_independent_unit_gaussians_across_blocks() {
        let key = StreamKey::new(11, "walk-test");
        // Cover two block boundaries so both parts of the construction are exercised.
        let n = 3 * KNOTS_PER_BLOCK;
        let steps: Vec<f64> = (0..n)
            .map(|i| standard_walk_at_knot(key, i + 1) - standard_walk_at_knot(key, i))
            .collect();
        let mean = steps.iter().sum::<f64>() / n as f64;
        let var = steps.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / n as f64;
        let lag1 = steps.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / (n - 1) as f64;
        assert!(mean.abs() < 0.1, "mean step {mean}");
        assert!((var - 1.0).abs() < 0.1, "step variance {var}");
        assert!(lag1.abs() < 0.1, "lag-1 covariance {lag1}");
    }

    #[test]
    fn starts_at_position_and_is_continuous() {
        let walk = open_walk(0.3);
        assert_eq!(walk.position_at(5, 1, 0.0), [0.0; 3]);
        let a = walk.position_at(5, 1, 2.0 - 1e-9);
        let b = walk.position_at(5, 1, 2.0);
        assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-6));
    }

    #[test]
    fn different_targets_and_seeds_walk_differently() {
        let walk = open_walk(0.3);
        assert_ne!(walk.position_at(5, 1, 10.0), walk.position_at(5, 2, 10.0));
        assert_ne!(walk.position_at(5, 1, 10.0), walk.position_at(6, 1, 10.0));
    }

    #[test]
    fn reflected_walk_stays_in_its_box() {
        let walk = RandomWalk {
            position: [1.0, 1.0, 1.7],
            std: [1.0, 1.0, 0.0],
            bounds: BoundsBox {
                min: [0.0, 0.0, 1.7],
                max: [3.0, 2.0, 1.7],
            },
            knot_interval_s: None,
        };
        for i in 0..2000 {
            let p = walk.position_at(3, 9, i as f64 * 0.37);
            assert!(walk.bounds.contains(&p), "{p:?} left the box");
        }
    }
}
