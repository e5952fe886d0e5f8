//! Per-scan cost of Vo & Ma's two GM-PHD demos (the performance goals name both).
//!
//! * `vo_linear`: the linear demo as in `tests/exp_vo_demo.rs` — 12 targets (the demo's
//!   `gen_truth.m`), 2-D constant velocity (T = 1 s, σ_v = 5 m/s²), p_S 0.99, four birth
//!   components of weight 0.03, σ = 10 m position sensor with p_D 0.98 and 60 clutter
//!   returns per scan over [−1000, 1000]², pruning T = 1e-5, merging U = 4, J_max = 100.
//! * `vo_nonlinear`: the unscented demo as in `tests/common/vo_nonlinear.rs` (shared with the
//!   `vo_nonlinear_export` example) — 10 targets on coordinated turns (initial states
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

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use gmphd::{GmPhdFilter, LabelledTracker, Measurement, MeasurementModel, TrackerConfig};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use support::clock::BenchClock;
use support::common::{vo_demo, vo_nonlinear};

const SCANS: usize = 100;

/// One scenario: its sensor, its simulated scans and how to build a fresh filter.
struct Demo {
    name: &'static str,
    sensor: Box<dyn MeasurementModel>,
    scans: Vec<Vec<Measurement>>,
    fresh_filter: fn() -> GmPhdFilter,
}

fn demos() -> Vec<Demo> {
    let position = vo_demo::sensor();
    let radar = vo_nonlinear::sensor();
    // The linear demo's run as `tests/exp_vo_demo.rs`'s first (seed 7000).
    let mut rng = ChaCha8Rng::seed_from_u64(7000);
    let linear_scans = vo_demo::truth()
        .iter()
        .map(|objects| vo_demo::scan(objects, &position, &mut rng))
        .collect();
    vec![
        Demo {
            name: "vo_linear",
            scans: linear_scans,
            sensor: Box::new(position),
            fresh_filter: vo_demo::filter,
        },
        Demo {
            name: "vo_nonlinear",
            scans: vo_nonlinear::scans(&radar, &vo_nonlinear::truth(), vo_nonlinear::SEED),
            sensor: Box::new(radar),
            fresh_filter: vo_nonlinear::filter,
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
