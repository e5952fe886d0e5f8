//! Vo & Ma's nonlinear (unscented) GM-PHD demo: its targets, sensor, filter and scans,
//! shared by the `scans` benchmark (`vo_nonlinear`) and the `vo_nonlinear_export` example
//! (which writes the very sets the benchmark runs on, so that another implementation can
//! be scored on the same data).
//!
//! 10 targets on coordinated turns (initial states and birth/death times of the demo's
//! nonlinear `gen_truth.m`, reordered to [x, y, vx, vy, ω]), σ_v = 5 m/s²,
//! σ_ω = π/180 rad/s; p_S 0.99; four birth components (weights 0.02, 0.02, 0.03, 0.03,
//! P = diag(50, 50, 50, 50, 6π/180)²); a bearing–range sensor at the origin
//! (σ = 2π/180 rad and 10 m, range 2000 m, p_D 0.98, 20 clutter returns per scan);
//! pruning T = 1e-5, merging U = 4, J_max = 100. Our bearing is measured from the x axis
//! and the clutter spans [−π, π) × [0, 2000] m instead of the demo's half plane (a clutter
//! density half the demo's).

use std::f64::consts::PI;

use gmphd::{
    BearingRange, BirthTiming, CoordinatedTurn, Detection, FilterConfig, GmPhdFilter, Measurement,
    MixtureBirth, PruneMergeCap, Survival, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Scans per run.
pub const STEPS: usize = 100;
/// Seed of the benchmark's run (run `r` of the export uses `SEED + r`).
pub const SEED: u64 = 7100;

/// The demo's turn-rate unit, 2°/s.
pub const W_TURN: f64 = 2.0 * PI / 180.0;

/// Nonlinear demo targets: ([x, y, vx, vy, ω], first scan, last scan).
pub const TARGETS: [([f64; 5], usize, usize); 10] = [
    ([1003.8676, 1488.2543, -10.0, -10.0, W_TURN / 8.0], 1, STEPS),
    ([-255.8857, 1011.4102, 20.0, 3.0, -W_TURN / 3.0], 10, STEPS),
    ([-1507.3806, 256.7993, 11.0, 10.0, -W_TURN / 2.0], 10, STEPS),
    ([-1500.0, 250.0, 43.0, 0.0, 0.0], 10, 66),
    ([246.1324, 738.9253, 11.0, 5.0, W_TURN / 4.0], 20, 80),
    ([-242.6194, 993.2007, -12.0, -12.0, W_TURN / 2.0], 40, STEPS),
    ([1000.0, 1500.0, 0.0, -10.0, W_TURN / 4.0], 40, STEPS),
    ([250.0, 750.0, -50.0, 0.0, -W_TURN / 4.0], 40, 80),
    ([1000.0, 1500.0, -50.0, 0.0, -W_TURN / 4.0], 60, STEPS),
    ([250.0, 750.0, -40.0, 25.0, W_TURN / 4.0], 60, STEPS),
];

/// Acceleration noise σ_w (m/s²) and turn-rate noise σ_u (rad/s) of the motion model.
pub const ACCEL_NOISE_STD: f64 = 5.0;
pub const TURN_RATE_NOISE_STD: f64 = PI / 180.0;
pub const SURVIVAL_PROBABILITY: f64 = 0.99;
pub const DETECTION_PROBABILITY: f64 = 0.98;
/// Mean clutter returns per scan.
pub const CLUTTER_RATE: f64 = 20.0;
/// Measurement noise [σ_bearing (rad), σ_range (m)].
pub const NOISE_STD: [f64; 2] = [2.0 * PI / 180.0, 10.0];
/// The sensor's maximum range (m); clutter spans [−π, π) × [0, MAX_RANGE].
pub const MAX_RANGE: f64 = 2000.0;
/// Birth components: (weight, [x, y]) with zero velocity and turn rate.
pub const BIRTHS: [(f64, [f64; 2]); 4] = [
    (0.02, [-1500.0, 250.0]),
    (0.02, [-250.0, 1000.0]),
    (0.03, [250.0, 750.0]),
    (0.03, [1000.0, 1500.0]),
];
/// Standard deviations of the birth covariance's diagonal, [x, y, vx, vy, ω].
pub const BIRTH_STD: [f64; 5] = [50.0, 50.0, 50.0, 50.0, 6.0 * PI / 180.0];
/// Pruning threshold T, merging threshold U (squared Mahalanobis distance), J_max.
pub const PRUNE_THRESHOLD: f64 = 1e-5;
pub const MERGE_THRESHOLD: f64 = 4.0;
pub const MAX_COMPONENTS: usize = 100;

/// True states [x, y, vx, vy, ω] per scan (index 0 is scan 1; noiseless coordinated
/// turns, the state at a target's first scan is its initial state).
pub fn truth_states() -> Vec<Vec<DVector<f64>>> {
    let mut per_scan = vec![Vec::new(); STEPS];
    for (start, first, last) in TARGETS {
        let mut state = DVector::from_row_slice(&start);
        for k in first..=last {
            if k > first {
                state = CoordinatedTurn::transition(&state, 1.0);
            }
            per_scan[k - 1].push(state.clone());
        }
    }
    per_scan
}

/// World positions per scan (the plane z = 0), as the simulation takes them.
pub fn truth() -> Vec<Vec<Vector3<f64>>> {
    truth_states()
        .iter()
        .map(|scan| scan.iter().map(|s| Vector3::new(s[0], s[1], 0.0)).collect())
        .collect()
}

/// The demo's bearing–range sensor at the origin.
pub fn sensor() -> BearingRange {
    BearingRange::new(
        [0.0, 0.0, 0.0],
        NOISE_STD,
        MAX_RANGE,
        Detection::new(DETECTION_PROBABILITY, CLUTTER_RATE).unwrap(),
    )
    .unwrap()
}

/// The demo's filter: unscented coordinated-turn prediction, per-step births.
pub fn filter() -> GmPhdFilter {
    let spread = DVector::from_row_slice(&BIRTH_STD);
    let cov = DMatrix::from_diagonal(&spread.component_mul(&spread));
    let births = BIRTHS
        .iter()
        .map(|(w, [x, y])| {
            (
                *w,
                DVector::from_vec(vec![*x, *y, 0.0, 0.0, 0.0]),
                cov.clone(),
            )
        })
        .collect();
    let motion = CoordinatedTurn::new(
        ACCEL_NOISE_STD,
        TURN_RATE_NOISE_STD,
        0.0,
        UnscentedParams::default(),
    )
    .unwrap();
    GmPhdFilter::new(
        Box::new(motion),
        Box::new(MixtureBirth::new(5, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(PRUNE_THRESHOLD, MERGE_THRESHOLD, MAX_COMPONENTS).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(SURVIVAL_PROBABILITY),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

/// The scans of one run: one generator seeded `seed`, one [`super::simulate_set`] per
/// scan (each target detected with p_D, then Poisson clutter).
pub fn scans(
    sensor: &BearingRange,
    truth: &[Vec<Vector3<f64>>],
    seed: u64,
) -> Vec<Vec<Measurement>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    truth
        .iter()
        .map(|objects| super::simulate_set(sensor, objects, &mut rng))
        .collect()
}
