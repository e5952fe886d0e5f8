//! Per-scan cost of Vo & Ma's two GM-PHD demos (the goals of issue 7 name both).
//!
//! * `vo_linear`: the linear demo as in `tests/exp_vo_demo.rs` — 12 targets (the demo's
//!   `gen_truth.m`), 2-D constant velocity (T = 1 s, σ_v = 5 m/s²), p_S 0.99, four birth
//!   components of weight 0.03, σ = 10 m position sensor with p_D 0.98 and 60 clutter
//!   returns per scan over [−1000, 1000]², pruning T = 1e-5, merging U = 4, J_max = 100.
//! * `vo_nonlinear`: the unscented demo — 10 targets on coordinated turns (initial states
//!   and birth/death times of the demo's nonlinear `gen_truth.m`, reordered to
//!   [x, y, vx, vy, ω]), σ_v = 5 m/s², σ_ω = π/180 rad/s, four birth components
//!   (weights 0.02, 0.02, 0.03, 0.03, P = diag(50, 50, 50, 50, 6π/180)²), a bearing–range
//!   sensor at the origin (σ = 2π/180 rad and 10 m, range 2000 m, p_D 0.98, 20 clutter
//!   returns per scan), same reduction. Our bearing is measured from the x axis and the
//!   clutter spans [−π, π) × [0, 2000] m instead of the demo's half plane (a clutter
//!   density half the demo's); the cost per scan does not depend on that.
//!
//! Each benchmark runs all 100 scans of one seeded run from an empty intensity (the
//! measurement sets are simulated beforehand) and reports the time per scan: the mean
//! over the run, births and deaths included. `filter` is the bare recursion (predict,
//! update, reduce), `tracker` the `LabelledTracker` step (plus label continuity and the
//! track manager) that the server runs.

mod support;

use std::f64::consts::PI;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use gmphd::{
    BearingRange, BirthTiming, CoordinatedTurn, Detection, FilterConfig, GmPhdFilter,
    LabelledTracker, Measurement, MeasurementModel, MixtureBirth, MotionModel, PruneMergeCap,
    Survival, TrackerConfig, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use support::clock::BenchClock;
use support::common::vo_demo;

const SCANS: usize = 100;

/// The demo's turn-rate unit, 2°/s.
const W_TURN: f64 = 2.0 * PI / 180.0;

/// Nonlinear demo targets: ([x, y, vx, vy, ω], first scan, last scan).
const TURNING_TARGETS: [([f64; 5], usize, usize); 10] = [
    ([1003.8676, 1488.2543, -10.0, -10.0, W_TURN / 8.0], 1, SCANS),
    ([-255.8857, 1011.4102, 20.0, 3.0, -W_TURN / 3.0], 10, SCANS),
    ([-1507.3806, 256.7993, 11.0, 10.0, -W_TURN / 2.0], 10, SCANS),
    ([-1500.0, 250.0, 43.0, 0.0, 0.0], 10, 66),
    ([246.1324, 738.9253, 11.0, 5.0, W_TURN / 4.0], 20, 80),
    ([-242.6194, 993.2007, -12.0, -12.0, W_TURN / 2.0], 40, SCANS),
    ([1000.0, 1500.0, 0.0, -10.0, W_TURN / 4.0], 40, SCANS),
    ([250.0, 750.0, -50.0, 0.0, -W_TURN / 4.0], 40, 80),
    ([1000.0, 1500.0, -50.0, 0.0, -W_TURN / 4.0], 60, SCANS),
    ([250.0, 750.0, -40.0, 25.0, W_TURN / 4.0], 60, SCANS),
];

/// World positions per scan (index 0 is scan 1) of the linear demo (the tests' scenario).
fn linear_truth() -> Vec<Vec<Vector3<f64>>> {
    vo_demo::truth()
        .iter()
        .map(|scan| scan.iter().map(|p| Vector3::new(p[0], p[1], 0.0)).collect())
        .collect()
}

/// World positions per scan of the nonlinear demo (noiseless coordinated turns).
fn turning_truth() -> Vec<Vec<Vector3<f64>>> {
    let mut per_scan = vec![Vec::new(); SCANS];
    for (start, first, last) in TURNING_TARGETS {
        let mut state = DVector::from_row_slice(&start);
        for k in first..=last {
            if k > first {
                state = CoordinatedTurn::transition(&state, 1.0);
            }
            per_scan[k - 1].push(Vector3::new(state[0], state[1], 0.0));
        }
    }
    per_scan
}

fn filter(
    motion: Box<dyn MotionModel>,
    births: Vec<(f64, DVector<f64>, DMatrix<f64>)>,
) -> GmPhdFilter {
    let state_dim = motion.state_dim();
    GmPhdFilter::new(
        motion,
        Box::new(MixtureBirth::new(state_dim, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

fn turning_filter() -> GmPhdFilter {
    let spread = DVector::from_vec(vec![50.0, 50.0, 50.0, 50.0, 6.0 * PI / 180.0]);
    let cov = DMatrix::from_diagonal(&spread.component_mul(&spread));
    let births = [
        (0.02, [-1500.0, 250.0]),
        (0.02, [-250.0, 1000.0]),
        (0.03, [250.0, 750.0]),
        (0.03, [1000.0, 1500.0]),
    ]
    .iter()
    .map(|(w, [x, y])| {
        (
            *w,
            DVector::from_vec(vec![*x, *y, 0.0, 0.0, 0.0]),
            cov.clone(),
        )
    })
    .collect();
    let motion = CoordinatedTurn::new(5.0, PI / 180.0, 0.0, UnscentedParams::default()).unwrap();
    filter(Box::new(motion), births)
}

/// One scenario: its sensor, its simulated scans and how to build a fresh filter.
struct Demo {
    name: &'static str,
    sensor: Box<dyn MeasurementModel>,
    scans: Vec<Vec<Measurement>>,
    fresh_filter: fn() -> GmPhdFilter,
}

fn demos() -> Vec<Demo> {
    let position = vo_demo::sensor();
    let radar = BearingRange::new(
        [0.0, 0.0, 0.0],
        [2.0 * PI / 180.0, 10.0],
        2000.0,
        Detection::new(0.98, 20.0).unwrap(),
    )
    .unwrap();
    let simulate = |sensor: &dyn MeasurementModel, truth: Vec<Vec<Vector3<f64>>>, seed| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        truth
            .iter()
            .map(|objects| support::common::simulate_set(sensor, objects, &mut rng))
            .collect()
    };
    vec![
        Demo {
            name: "vo_linear",
            scans: simulate(&position, linear_truth(), 7000),
            sensor: Box::new(position),
            fresh_filter: vo_demo::filter,
        },
        Demo {
            name: "vo_nonlinear",
            scans: simulate(&radar, turning_truth(), 7100),
            sensor: Box::new(radar),
            fresh_filter: turning_filter,
        },
    ]
}

/// Time of `iters` whole runs divided by the number of scans per run, so that criterion
/// reports the mean time of one scan.
fn per_scan(iters: u64, mut run: impl FnMut() -> Duration) -> Duration {
    (0..iters).map(|_| run()).sum::<Duration>() / SCANS as u32
}

fn bench_scans(c: &mut Criterion<BenchClock>) {
    let clock = BenchClock::from_env();
    let mut group = c.benchmark_group("scan");
    for demo in demos() {
        let sensor = demo.sensor.as_ref();
        group.bench_function(format!("{}/filter", demo.name), |b| {
            b.iter_custom(|iters| {
                per_scan(iters, || {
                    let mut filter = (demo.fresh_filter)();
                    let start = clock.now();
                    for (index, set) in demo.scans.iter().enumerate() {
                        filter.predict_to((index + 1) as f64).unwrap();
                        filter.update(sensor, set).unwrap();
                        filter.reduce();
                    }
                    clock.since(&start)
                })
            })
        });
        group.bench_function(format!("{}/tracker", demo.name), |b| {
            b.iter_custom(|iters| {
                per_scan(iters, || {
                    let config = TrackerConfig {
                        first_interval_s: 1.0,
                        ..TrackerConfig::default()
                    };
                    let mut tracker = LabelledTracker::new((demo.fresh_filter)(), config).unwrap();
                    let start = clock.now();
                    for (index, set) in demo.scans.iter().enumerate() {
                        tracker.step((index + 1) as f64, sensor, set).unwrap();
                    }
                    clock.since(&start)
                })
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(BenchClock::from_env())
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = bench_scans
}
criterion_main!(benches);
