//! People who keep their distance: the targets' positions when nobody may come closer to anyone else
//! than a scenario's `personal_space_m` (horizontally, head to head).
//!
//! Each target's [`Motion`](crate::Motion) alone is its *intended* path, a pure function of time. Alone, two
//! intended paths cross through one another; people step aside instead. The crowd is stepped jointly
//! every [`STEP_S`] from scenario time 0, as position-based crowd dynamics do (Müller et al. 2007,
//! "Position based dynamics"; Weiss et al. 2017 for crowds):
//!
//! 1. each present target wants the velocity of its intended path plus a pull back onto it (the
//!    distance to it over [`CATCH_UP_S`]), at most [`MAX_SPEED`]; its velocity turns towards that at
//!    most at [`MAX_ACCEL`], as a walker's does, and it moves; a target appears at its intended position
//!    with its intended velocity, stepping aside if it would stand too close to someone;
//! 2. each pair closer than the personal space is pushed apart along the line joining them, half the
//!    shortfall each, turned by [`PASSING_TURN_RAD`] so that two people meeting head on pass each other on
//!    one side instead of stalling; a few passes settle chains of three;
//! 3. a target's velocity is what it moved in the step, pushes included, but no faster than before.
//!
//! On its path a target follows it exactly; after a detour it rejoins it smoothly, without the sudden
//! turns and bursts of speed no walker makes (a filter's motion model would rightly lose them). Heights
//! follow the intended paths. Between steps positions are interpolated linearly. Steps are computed once
//! per (scenario, seed) and remembered ([`CrowdCache`]); the result stays a pure function of the
//! scenario, the seed and the time, the same in every process.

use std::sync::{Arc, Mutex};

use crate::target::Target;

/// Seconds between two steps of the joint walk.
pub const STEP_S: f64 = 0.02;
/// Fastest a target moves while catching up with its intended path, m/s: a brisk walk.
pub const MAX_SPEED: f64 = 1.8;
/// Largest change of a target's velocity, m/s²: people start, stop and turn at 1–2 m/s².
pub const MAX_ACCEL: f64 = 2.0;
/// Seconds over which a target pulls back onto its intended path after a detour.
pub const CATCH_UP_S: f64 = 1.0;
/// How far a push is turned from the line between two people, rad: both sidestep to the same hand.
pub const PASSING_TURN_RAD: f64 = 0.5;
/// How far ahead a walker looks for people it is heading for, s.
pub const AVOID_AHEAD_S: f64 = 3.0;
/// Fastest a walker sidesteps to pass someone, m/s.
pub const MAX_SIDESTEP: f64 = 0.8;
/// A walker aims to pass others this many times the personal space apart.
pub const COMFORT: f64 = 1.3;
/// Passes over all pairs per step.
const RESOLVE_PASSES: usize = 4;
/// Seconds of walk computed beyond the time asked for, so that a run going forward rarely recomputes.
const LOOKAHEAD_S: f64 = 60.0;

/// The joint walk of one (scenario, seed): every target's position at each step.
struct Crowd {
    targets: Vec<Target>,
    seed: u64,
    personal_space_m: f64,
    /// `steps[k][i]`: target `i` at scenario time `k · STEP_S`.
    steps: Vec<Vec<[f64; 3]>>,
}

impl Crowd {
    /// The walk of `targets` in run `seed` up to scenario time `until_s` at least.
    fn walk(targets: &[Target], seed: u64, personal_space_m: f64, until_s: f64) -> Self {
        let count = (until_s.max(0.0) / STEP_S).ceil() as usize + 2;
        let mut steps = Vec::with_capacity(count);
        let mut walkers: Vec<Walker> = targets
            .iter()
            .map(|t| Walker::on_path(t, seed, 0.0))
            .collect();
        let mut now: Vec<[f64; 3]> = walkers.iter().map(|w| w.position).collect();
        let mut present: Vec<bool> = targets.iter().map(|t| t.is_present(0.0)).collect();
        resolve(&mut now, &present, personal_space_m);
        for (walker, &position) in walkers.iter_mut().zip(&now) {
            walker.position = position;
        }
        steps.push(now.clone());
        for k in 1..count {
            let t = k as f64 * STEP_S;
            let avoid: Vec<[f64; 2]> = (0..targets.len())
                .map(|i| avoidance(&walkers, &present, i, personal_space_m))
                .collect();
            for (i, target) in targets.iter().enumerate() {
                walkers[i] = if present[i] {
                    walkers[i].step(target, seed, t, avoid[i])
                } else {
                    Walker::on_path(target, seed, t)
                };
                now[i] = walkers[i].position;
                let arrived = !present[i] && target.is_present(t);
                present[i] = target.is_present(t);
                if arrived {
                    make_room(&mut now, &present, i, personal_space_m);
                    walkers[i].position = now[i];
                }
            }
            resolve(&mut now, &present, personal_space_m);
            for (walker, &position) in walkers.iter_mut().zip(&now) {
                walker.moved_to(position);
            }
            steps.push(now.clone());
        }
        Self {
            targets: targets.to_vec(),
            seed,
            personal_space_m,
            steps,
        }
    }

    /// Whether this walk is of `targets` in run `seed` and reaches scenario time `t`.
    fn covers(&self, targets: &[Target], seed: u64, personal_space_m: f64, t: f64) -> bool {
        self.seed == seed
            && self.personal_space_m == personal_space_m
            && self.targets == targets
            && t <= (self.steps.len() - 2) as f64 * STEP_S
    }

    /// Target `index` at scenario time `t ≥ 0`, interpolated between steps.
    fn position(&self, index: usize, t: f64) -> [f64; 3] {
        let at = t.max(0.0) / STEP_S;
        let k = (at.floor() as usize).min(self.steps.len() - 2);
        let f = at - k as f64;
        let (a, b) = (self.steps[k][index], self.steps[k + 1][index]);
        std::array::from_fn(|axis| a[axis] + (b[axis] - a[axis]) * f)
    }
}

/// One target of the joint walk: where it is and how fast it goes (horizontally; the height is the
/// intended one).
#[derive(Debug, Clone, Copy)]
struct Walker {
    position: [f64; 3],
    velocity: [f64; 2],
    /// Where it was at the start of the step, for [`Walker::moved_to`].
    previous: [f64; 2],
}

impl Walker {
    /// `target` on its intended path at time `t`, with the path's velocity.
    fn on_path(target: &Target, seed: u64, t: f64) -> Self {
        let position = target.position_at(seed, t);
        let next = target.position_at(seed, t + STEP_S);
        let velocity = [0, 1].map(|a| (next[a] - position[a]) / STEP_S);
        Self {
            position,
            velocity,
            // As if it had come along its path: unpushed, it keeps the path's velocity.
            previous: [0, 1].map(|a| position[a] - velocity[a] * STEP_S),
        }
    }

    /// The walker one step later, at time `t`, before anyone is pushed (step 1 of the module
    /// documentation).
    fn step(&self, target: &Target, seed: u64, t: f64, avoid: [f64; 2]) -> Self {
        let (here, next) = (
            target.position_at(seed, t - STEP_S),
            target.position_at(seed, t),
        );
        let wanted = clamp_length(
            [0, 1].map(|a| {
                (next[a] - here[a]) / STEP_S + (here[a] - self.position[a]) / CATCH_UP_S + avoid[a]
            }),
            MAX_SPEED,
        );
        let change = clamp_length(
            [0, 1].map(|a| wanted[a] - self.velocity[a]),
            MAX_ACCEL * STEP_S,
        );
        let velocity = [0, 1].map(|a| self.velocity[a] + change[a]);
        Self {
            position: [
                self.position[0] + velocity[0] * STEP_S,
                self.position[1] + velocity[1] * STEP_S,
                next[2],
            ],
            velocity,
            previous: [self.position[0], self.position[1]],
        }
    }

    /// Takes the position after the pushes; the velocity is what it moved over the step, but a push
    /// never makes anyone faster than they were going (a walker stopped by another does not bounce
    /// off, nor does one who appeared too close run away).
    fn moved_to(&mut self, position: [f64; 3]) {
        let speed = self.velocity[0].hypot(self.velocity[1]);
        let moved = [0, 1].map(|a| (position[a] - self.previous[a]) / STEP_S);
        self.velocity = clamp_length(moved, speed);
        self.position = position;
    }
}

/// The change of velocity walker `i` wants so as to pass the others it is heading for at
/// [`COMFORT`] times the personal space `space` (its half of the sidestep; step 1 of the module
/// documentation). With the current velocities, another walker that will come closest within
/// [`AVOID_AHEAD_S`] and then closer than that is steered away from along the vector between them at that
/// moment (people heading straight at each other both step to their left); one already closer than
/// that is drifted away from over [`CATCH_UP_S`].
fn avoidance(walkers: &[Walker], present: &[bool], i: usize, space: f64) -> [f64; 2] {
    let mut sum = [0.0; 2];
    if !present[i] {
        return sum;
    }
    let me = &walkers[i];
    for (j, other) in walkers.iter().enumerate() {
        if j == i || !present[j] {
            continue;
        }
        let r = [0, 1].map(|a| me.position[a] - other.position[a]);
        let w = [0, 1].map(|a| me.velocity[a] - other.velocity[a]);
        let distance = r[0].hypot(r[1]);
        if distance == 0.0 {
            // Coincident heads are parted by the pushes (`resolve`), not steered.
            continue;
        }
        let comfortable = COMFORT * space;
        if distance < comfortable {
            // Too close for comfort: drift apart, whether or not either is moving.
            let drift = (comfortable - distance) / CATCH_UP_S;
            for a in 0..2 {
                sum[a] += r[a] / distance * drift;
            }
        }
        let closing = -(r[0] * w[0] + r[1] * w[1]);
        let w2 = w[0] * w[0] + w[1] * w[1];
        if closing <= 0.0 || w2 == 0.0 {
            continue;
        }
        let when = closing / w2;
        let miss = [0, 1].map(|a| r[a] + w[a] * when);
        let miss_length = miss[0].hypot(miss[1]);
        if when > AVOID_AHEAD_S || miss_length >= comfortable {
            continue;
        }
        let away = if miss_length > 1e-9 {
            miss.map(|x| x / miss_length)
        } else {
            [-r[1] / distance, r[0] / distance]
        };
        let speed = (0.5 * (comfortable - miss_length) / when.max(STEP_S)).min(MAX_SIDESTEP);
        for a in 0..2 {
            sum[a] += away[a] * speed;
        }
    }
    sum
}

/// `v` shortened to at most `limit` long.
fn clamp_length(v: [f64; 2], limit: f64) -> [f64; 2] {
    let length = v[0].hypot(v[1]);
    if length > limit {
        v.map(|x| x * limit / length)
    } else {
        v
    }
}

/// Moves target `i`, just arrived, out of the personal space of those already present: the newcomer
/// steps aside, they do not jump.
fn make_room(positions: &mut [[f64; 3]], present: &[bool], i: usize, space: f64) {
    for _ in 0..RESOLVE_PASSES {
        for j in 0..positions.len() {
            if j == i || !present[j] {
                continue;
            }
            let (distance, (ux, uy)) = separation(positions[i], positions[j]);
            if distance < space {
                positions[i][0] = positions[j][0] + ux * space;
                positions[i][1] = positions[j][1] + uy * space;
            }
        }
    }
}

/// The horizontal distance from `b` to `a` and the unit vector from `b` towards `a`; coincident
/// heads (only if placed so on purpose) are parted along x.
fn separation(a: [f64; 3], b: [f64; 3]) -> (f64, (f64, f64)) {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    let distance = dx.hypot(dy);
    if distance > 0.0 {
        (distance, (dx / distance, dy / distance))
    } else {
        (0.0, (1.0, 0.0))
    }
}

/// Pushes apart the present targets of `positions` that stand closer than `space` to one another.
fn resolve(positions: &mut [[f64; 3]], present: &[bool], space: f64) {
    let (sin, cos) = PASSING_TURN_RAD.sin_cos();
    for _ in 0..RESOLVE_PASSES {
        for i in 0..positions.len() {
            for j in i + 1..positions.len() {
                if !(present[i] && present[j]) {
                    continue;
                }
                let (distance, (ux, uy)) = separation(positions[i], positions[j]);
                if distance >= space {
                    continue;
                }
                let (px, py) = (ux * cos - uy * sin, ux * sin + uy * cos);
                let half = 0.5 * (space - distance) / (ux * px + uy * py);
                positions[i][0] += px * half;
                positions[i][1] += py * half;
                positions[j][0] -= px * half;
                positions[j][1] -= py * half;
            }
        }
    }
}

/// The remembered joint walk of a scenario (see the module documentation); empty until first asked.
/// Clones start empty, and every cache compares equal: it is a memo, not part of the scenario.
#[derive(Default)]
pub(crate) struct CrowdCache(Mutex<Option<Arc<Crowd>>>);

impl CrowdCache {
    /// Target `index` of `targets` at scenario time `t` of run `seed`, keeping `personal_space_m` from the
    /// others; before 0 the intended position.
    pub(crate) fn position(
        &self,
        targets: &[Target],
        index: usize,
        seed: u64,
        personal_space_m: f64,
        t: f64,
    ) -> [f64; 3] {
        if t < 0.0 {
            return targets[index].position_at(seed, t);
        }
        let crowd = {
            let mut slot = self
                .0
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            match slot.as_ref() {
                Some(crowd) if crowd.covers(targets, seed, personal_space_m, t) => crowd.clone(),
                _ => {
                    let crowd = Arc::new(Crowd::walk(
                        targets,
                        seed,
                        personal_space_m,
                        t + LOOKAHEAD_S,
                    ));
                    *slot = Some(crowd.clone());
                    crowd
                }
            }
        };
        crowd.position(index, t)
    }
}

impl std::fmt::Debug for CrowdCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("CrowdCache")
    }
}

impl Clone for CrowdCache {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl PartialEq for CrowdCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{ConstantVelocity, Motion};

    fn walker(id: u64, position: [f64; 3], velocity: [f64; 3]) -> Target {
        Target {
            id,
            appear_s: 0.0,
            disappear_s: None,
            motion: Motion::ConstantVelocity(ConstantVelocity { position, velocity }),
        }
    }

    #[test]
    fn people_meeting_head_on_pass_each_other_smoothly_and_return_to_their_paths() {
        let targets = [
            walker(1, [0.0, 0.0, 1.7], [1.0, 0.0, 0.0]),
            walker(2, [4.0, 0.0, 1.6], [-1.0, 0.0, 0.0]),
        ];
        let cache = CrowdCache::default();
        let at = |k: usize| [0, 1].map(|i| cache.position(&targets, i, 1, 0.5, k as f64 * STEP_S));
        let (mut closest, mut fastest, mut hardest) = (f64::INFINITY, 0.0_f64, 0.0_f64);
        for k in 2..=400 {
            let [a, b, c] = [at(k - 2), at(k - 1), at(k)];
            closest = closest.min((c[0][0] - c[1][0]).hypot(c[0][1] - c[1][1]));
            for i in 0..2 {
                let v = [0, 1].map(|x| (c[i][x] - b[i][x]) / STEP_S);
                let dv = [0, 1].map(|x| v[x] - (b[i][x] - a[i][x]) / STEP_S);
                fastest = fastest.max(v[0].hypot(v[1]));
                hardest = hardest.max(dv[0].hypot(dv[1]) / STEP_S);
            }
        }
        println!("closest approach {closest:.3} m, fastest {fastest:.2} m/s, largest acceleration {hardest:.2} m/s²");
        assert!(closest >= 0.45, "they came within {closest} m");
        assert!(fastest <= MAX_SPEED + 0.1, "{fastest} m/s");
        // Pushes add to the walkers' own acceleration, but stay within what people do.
        assert!(hardest <= 2.0 * MAX_ACCEL, "{hardest} m/s²");
        // By 8 s both are past each other and back on their paths.
        let end = at(400);
        let off = |p: [f64; 3], x: f64| (p[0] - x).hypot(p[1]);
        assert!(
            off(end[0], 8.0) < 0.02 && off(end[1], -4.0) < 0.02,
            "{end:?}"
        );
        assert_eq!(end[1][2], 1.6, "heights follow the intended paths");
    }

    #[test]
    fn people_far_apart_walk_their_intended_paths() {
        let targets = [
            walker(1, [0.0, 0.0, 1.7], [0.5, 0.0, 0.0]),
            walker(2, [0.0, 3.0, 1.7], [0.5, 0.0, 0.0]),
        ];
        let cache = CrowdCache::default();
        for t in [0.0, 0.33, 7.1, 75.0] {
            for (i, target) in targets.iter().enumerate() {
                let joint = cache.position(&targets, i, 9, 0.5, t);
                let alone = target.position_at(9, t);
                assert!(
                    (0..3).all(|a| (joint[a] - alone[a]).abs() < 1e-9),
                    "{t}: {joint:?}"
                );
            }
        }
    }

    #[test]
    fn a_changed_scenario_is_walked_again() {
        let mut targets = vec![walker(1, [0.0, 0.0, 1.7], [0.0; 3])];
        let cache = CrowdCache::default();
        assert_eq!(cache.position(&targets, 0, 1, 0.5, 1.0), [0.0, 0.0, 1.7]);
        targets[0] = walker(1, [2.0, 0.0, 1.7], [0.0; 3]);
        assert_eq!(cache.position(&targets, 0, 1, 0.5, 1.0), [2.0, 0.0, 1.7]);
    }
}
