//! Vo & Ma's linear GM-PHD demo: its targets, sensor, filter and scans, shared by
//! `vo_demo.rs`, `exp_vo_demo.rs` and the `vo_demo_export` example (which writes the
//! very sets `exp_vo_demo.rs` runs on, so that another implementation can be scored on
//! the same data).
//!
//! The 12 targets of the demo's `gen_truth.m` (its [x; vx; y; vy] reordered to our
//! [x, y, vx, vy]); 2-D constant velocity, T = 1 s, σ_v = 5 m/s²; p_S 0.99; four birth
//! components of weight 0.03, P = diag(10²); σ = 10 m; p_D 0.98; 60 clutter returns per
//! scan over [−1000, 1000]²; pruning T = 1e-5, merging U = 4, J_max = 100.

use gmphd::{
    BirthTiming, ConstantVelocity, Detection, FilterConfig, GmPhdFilter, Measurement, MixtureBirth,
    PositionSensor, PruneMergeCap, Survival, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand_chacha::ChaCha8Rng;

/// Scans per run.
pub const STEPS: usize = 100;
/// Merging threshold U (squared Mahalanobis distance).
pub const MERGE_THRESHOLD: f64 = 4.0;
pub const DETECTION_PROBABILITY: f64 = 0.98;
/// Mean clutter returns per scan.
pub const CLUTTER_RATE: f64 = 60.0;
/// Measurement noise σ per axis, in metres.
pub const NOISE_STD: f64 = 10.0;
/// Where the four birth components sit (x, y), zero velocity.
pub const BIRTH_POSITIONS: [[f64; 2]; 4] = [
    [0.0, 0.0],
    [400.0, -600.0],
    [-800.0, -200.0],
    [-200.0, 800.0],
];

/// (initial state [x, y, vx, vy], first step, last step) of the demo's targets.
pub const TARGETS: [([f64; 4], usize, usize); 12] = [
    ([0.0, 0.0, 0.0, -10.0], 1, 70),
    ([400.0, -600.0, -10.0, 5.0], 1, STEPS),
    ([-800.0, -200.0, 20.0, -5.0], 1, 70),
    ([400.0, -600.0, -7.0, -4.0], 20, STEPS),
    ([400.0, -600.0, -2.5, 10.0], 20, STEPS),
    ([0.0, 0.0, 7.5, -5.0], 20, STEPS),
    ([-800.0, -200.0, 12.0, 7.0], 40, STEPS),
    ([-200.0, 800.0, 15.0, -10.0], 40, STEPS),
    ([-800.0, -200.0, 3.0, 15.0], 60, STEPS),
    ([-200.0, 800.0, -3.0, -15.0], 60, STEPS),
    ([0.0, 0.0, -20.0, -15.0], 80, STEPS),
    ([-200.0, 800.0, 15.0, -5.0], 80, STEPS),
];

/// True positions at steps 1..=STEPS (index 0 is step 1); as in the demo, the state
/// recorded at a target's first step has already been propagated once.
pub fn truth() -> Vec<Vec<DVector<f64>>> {
    let mut per_step = vec![Vec::new(); STEPS];
    for ([x, y, vx, vy], first, last) in TARGETS {
        for k in first..=last {
            let age = (k - first + 1) as f64;
            per_step[k - 1].push(DVector::from_vec(vec![x + vx * age, y + vy * age]));
        }
    }
    per_step
}

/// The demo's position sensor over [−1000, 1000]².
pub fn sensor() -> PositionSensor {
    PositionSensor::new(
        &[NOISE_STD, NOISE_STD],
        &[-1000.0, -1000.0],
        &[1000.0, 1000.0],
        Detection::new(DETECTION_PROBABILITY, CLUTTER_RATE).unwrap(),
    )
    .unwrap()
}

/// The demo's filter, except that the process noise is our continuous white-noise
/// acceleration (see `vo_demo.rs`).
pub fn filter() -> GmPhdFilter {
    let birth_cov = DMatrix::from_diagonal_element(4, 4, 100.0);
    let births = BIRTH_POSITIONS
        .iter()
        .map(|[x, y]| {
            (
                0.03,
                DVector::from_vec(vec![*x, *y, 0.0, 0.0]),
                birth_cov.clone(),
            )
        })
        .collect();
    GmPhdFilter::new(
        Box::new(ConstantVelocity::new(2, 5.0).unwrap()),
        Box::new(MixtureBirth::new(4, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, MERGE_THRESHOLD, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

/// One scan through [`super::simulate_set`]: each target detected with p_D, then
/// Poisson clutter (the demo's order).
pub fn scan(
    truth: &[DVector<f64>],
    sensor: &PositionSensor,
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let world: Vec<Vector3<f64>> = truth
        .iter()
        .map(|p| Vector3::new(p[0], p[1], 0.0))
        .collect();
    super::simulate_set(sensor, &world, rng)
}
