//! How a target moves: constant velocity, reflected random walk or interpolated waypoints.

use serde::{Deserialize, Serialize};

use crate::random_walk::RandomWalk;

/// A target's motion, tagged by `kind` in a scenario file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Motion {
    /// `{kind = "constant_velocity", position, velocity}`.
    ConstantVelocity(ConstantVelocity),
    /// `{kind = "random_walk", position, std, bounds, knot_interval_s?}`.
    RandomWalk(RandomWalk),
    /// `{kind = "waypoints", points = [[t, [x, y, z]], …]}`.
    Waypoints(Waypoints),
}

/// Straight-line motion at a fixed velocity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstantVelocity {
    /// Position at the target's appear time (world metres).
    pub position: [f64; 3],
    /// Velocity in m/s.
    pub velocity: [f64; 3],
}

/// A path through timed points, linear between them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Waypoints {
    /// `(t, [x, y, z])` pairs, `t` in scenario seconds (since the scenario start), strictly
    /// increasing. Before the first time the target waits at the first point, after the
    /// last it waits at the last.
    pub points: Vec<(f64, [f64; 3])>,
}

impl Waypoints {
    /// The linearly interpolated position at scenario time `t`.
    ///
    /// An empty list (rejected by scenario validation) yields the origin.
    pub fn position_at(&self, t: f64) -> [f64; 3] {
        let Some(&(first_t, first_p)) = self.points.first() else {
            return [0.0; 3];
        };
        if t <= first_t {
            return first_p;
        }
        // Index of the first point strictly after `t`.
        let next = self.points.partition_point(|&(pt, _)| pt <= t);
        if next == self.points.len() {
            return self.points[next - 1].1;
        }
        let (t0, p0) = self.points[next - 1];
        let (t1, p1) = self.points[next];
        let f = (t - t0) / (t1 - t0);
        std::array::from_fn(|i| p0[i] + (p1[i] - p0[i]) * f)
    }
}

impl Motion {
    /// The position at scenario time `t` of target `target_id`, which appeared at scenario
    /// time `appear_s`, in run `seed`. A pure function of its arguments.
    pub fn position_at(&self, seed: u64, target_id: u64, appear_s: f64, t: f64) -> [f64; 3] {
        match self {
            Motion::ConstantVelocity(cv) => {
                let since = t - appear_s;
                std::array::from_fn(|i| cv.position[i] + cv.velocity[i] * since)
            }
            Motion::RandomWalk(walk) => walk.position_at(seed, target_id, t - appear_s),
            Motion::Waypoints(path) => path.position_at(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waypoints_interpolate_and_hold_at_the_ends() {
        let path = Waypoints {
            points: vec![(1.0, [0.0, 0.0, 1.7]), (3.0, [2.0, 4.0, 1.7])],
        };
        assert_eq!(path.position_at(0.0), [0.0, 0.0, 1.7]);
        assert_eq!(path.position_at(2.0), [1.0, 2.0, 1.7]);
        assert_eq!(path.position_at(3.0), [2.0, 4.0, 1.7]);
        assert_eq!(path.position_at(9.0), [2.0, 4.0, 1.7]);
    }

    #[test]
    fn constant_velocity_starts_at_its_position_when_it_appears() {
        let motion = Motion::ConstantVelocity(ConstantVelocity {
            position: [1.0, 2.0, 3.0],
            velocity: [0.5, 0.0, -1.0],
        });
        assert_eq!(motion.position_at(0, 1, 4.0, 4.0), [1.0, 2.0, 3.0]);
        assert_eq!(motion.position_at(0, 1, 4.0, 6.0), [2.0, 2.0, 1.0]);
    }
}
