//! Targets: an identity, a time span of presence and a motion.

use serde::{Deserialize, Serialize};

use crate::motion::Motion;

/// One simulated object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// Identity, reported as the `id` of the object in truth sets; unique in a scenario.
    pub id: u64,
    /// Scenario time (seconds since the start) at which the target appears.
    #[serde(default)]
    pub appear_s: f64,
    /// Scenario time at which it disappears; absent: it stays to the end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub disappear_s: Option<f64>,
    /// How it moves.
    pub motion: Motion,
}

impl Target {
    /// Whether the target exists at scenario time `t`: `appear_s ≤ t < disappear_s`.
    pub fn is_present(&self, t: f64) -> bool {
        t >= self.appear_s && self.disappear_s.is_none_or(|end| t < end)
    }

    /// The position at scenario time `t` in run `seed` (defined for any `t`, present or not).
    pub fn position_at(&self, seed: u64, t: f64) -> [f64; 3] {
        self.motion.position_at(seed, self.id, self.appear_s, t)
    }
}
