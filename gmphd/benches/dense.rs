//! One full asynchronous step of the dense scenario: `LabelledTracker::step` (predict to the
//! set's stamp, update with that one sensor's set, reduce, label continuity, track manager).
//!
//! The scenario is the dense one of the performance goals (`BENCHMARKS.md`), rebuilt
//! here from gmphd's own models after `simulator::dense` (which gmphd cannot depend on):
//! 50 targets walking in a 40 × 40 × 10 m volume (random accelerations of 0.3 m/s² per
//! axis, reflected at 1 m inside the walls), seen by 8 sensors at 30 Hz each, staggered
//! by 4 ms — 4 cameras high above the corners (f = 500 px, 640 × 480, σ = 2 px), 2 LIDARs
//! facing each other across the volume, 2 position sensors (σ = 0.5 m and 1 × 1 × 0.3 m)
//! — with p_D 0.9 (0.85
//! for the position sensors) and 20 clutter points per set. The filter is the one
//! `fusion-loadbench` makes the server build: 3-D constant velocity (σ_a = 1 m/s²), p_S 0.99
//! per second, an 8 × 8 × 2 birth grid (0.2 births/s, velocity σ 0.5 m/s, added every 0.02 s as
//! the server's default `birth_interval_s`), adaptive birth
//! (0.05 per set, velocity σ 1 m/s), T = 1e-5, U = 4, J_max = 1000, the server's track
//! manager.
//!
//! The tracker first runs `WARM_UP_S` seconds of the scenario (all targets present from
//! the start) to reach its steady state; the benchmark then restores that checkpoint (into
//! the same tracker) and times the next 8 sets (one of each sensor) and reports the mean time of one set. Real
//! time is 240 sets per second, so 20× real time needs ≤ 208 µs per set.

mod support;

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use gmphd::birth::{BirthTiming, GridBirth, GridBirthConfig};
use gmphd::tracks::TrackManagerConfig;
use gmphd::{
    AdaptiveBirthConfig, ConstantVelocity, Detection, FilterConfig, GmPhdFilter, LabelledTracker,
    Lidar, Measurement, MeasurementModel, PinholeCamera, PositionSensor, PruneMergeCap, Survival,
    TrackerConfig, TrackerState, UnscentedParams,
};
use nalgebra::{Matrix3, Matrix3x4, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use support::clock::BenchClock;

const VOLUME_MIN: [f64; 3] = [0.0, 0.0, 0.0];
const VOLUME_MAX: [f64; 3] = [40.0, 40.0, 10.0];
const TARGETS: usize = 50;
const RATE_HZ: f64 = 30.0;
const PHASE_STEP_S: f64 = 0.004;
const CLUTTER: f64 = 20.0;
const WARM_UP_S: f64 = 2.0;
/// Random acceleration of the walkers per axis, m/s².
const WALK_ACCEL_STD: f64 = 0.3;

/// A camera at `eye` looking at `target` (OpenCV axes: x right, y down, z forward).
fn camera(eye: Vector3<f64>, target: Vector3<f64>) -> PinholeCamera {
    let forward = (target - eye).normalize();
    let right = forward.cross(&Vector3::z()).normalize();
    let down = forward.cross(&right);
    let rotation = Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
    let intrinsics = Matrix3::new(500.0, 0.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0);
    let mut extrinsics = Matrix3x4::zeros();
    extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    extrinsics.set_column(3, &(-rotation * eye));
    let detection = Detection::new(0.9, CLUTTER).unwrap();
    PinholeCamera::new(
        intrinsics * extrinsics,
        [640.0, 480.0],
        [2.0, 2.0],
        detection,
    )
    .unwrap()
}

/// The 8 sensors in the order of their phase offsets.
fn sensors() -> Vec<Box<dyn MeasurementModel>> {
    let mut sensors: Vec<Box<dyn MeasurementModel>> = Vec::new();
    for [x, y] in [[-5.0, -5.0], [45.0, -5.0], [45.0, 45.0], [-5.0, 45.0]] {
        let eye = Vector3::new(x, y, 15.0);
        sensors.push(Box::new(camera(eye, Vector3::new(20.0, 20.0, 3.0))));
    }
    for (position, orientation) in [
        ([0.0, 20.0, 5.0], [1.0, 0.0, 0.0, 0.0]),
        ([40.0, 20.0, 5.0], [0.0, 0.0, 0.0, 1.0]),
    ] {
        let detection = Detection::new(0.9, CLUTTER).unwrap();
        let lidar = Lidar::new(
            position,
            orientation,
            [0.05, 0.005, 0.005],
            60.0,
            [-0.6, 0.6],
            detection,
        );
        sensors.push(Box::new(lidar.unwrap()));
    }
    for noise in [[0.5, 0.5, 0.5], [1.0, 1.0, 0.3]] {
        let detection = Detection::new(0.85, CLUTTER).unwrap();
        let position = PositionSensor::new(&noise, &VOLUME_MIN, &VOLUME_MAX, detection);
        sensors.push(Box::new(position.unwrap()));
    }
    sensors
}

/// The server's tracker for this site (see the module documentation).
fn tracker() -> LabelledTracker {
    let birth = GridBirth::new(&GridBirthConfig {
        region_min: VOLUME_MIN.to_vec(),
        region_max: VOLUME_MAX.to_vec(),
        cells: vec![8, 8, 2],
        state_dim: 6,
        velocity_std: 0.5,
        extra_std: 0.0,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    let filter = GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 1.0).unwrap()),
        Box::new(birth),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 1000).unwrap()),
        FilterConfig {
            survival: Survival::PerSecond(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
    .with_birth_interval(0.02)
    .unwrap()
    .with_adaptive_birth(AdaptiveBirthConfig {
        rate: 0.05,
        velocity_std: 1.0,
        min_weight: 1e-5,
        ..AdaptiveBirthConfig::default()
    })
    .unwrap();
    let config = TrackerConfig {
        tracks: TrackManagerConfig {
            confirm_threshold: 0.5,
            confirm_window: 5,
            confirm_hits: 3,
            confirm_at_once_threshold: None,
            delete_threshold: 0.15,
            delete_after_sets: 12,
            max_coast_s: 1.0,
        },
        ..TrackerConfig::default()
    };
    LabelledTracker::new(filter, config).unwrap()
}

/// Walking targets: positions and velocities, advanced in continuous time.
struct Walkers {
    positions: Vec<Vector3<f64>>,
    velocities: Vec<Vector3<f64>>,
    time: f64,
}

impl Walkers {
    fn new(rng: &mut ChaCha8Rng) -> Self {
        let positions = (0..TARGETS)
            .map(|_| {
                Vector3::from_fn(|i, _| rng.gen_range(VOLUME_MIN[i] + 1.0..VOLUME_MAX[i] - 1.0))
            })
            .collect();
        let velocities = (0..TARGETS)
            .map(|_| Vector3::from_fn(|_, _| 0.5 * rng.sample::<f64, _>(StandardNormal)))
            .collect();
        Self {
            positions,
            velocities,
            time: 0.0,
        }
    }

    fn advance_to(&mut self, t: f64, rng: &mut ChaCha8Rng) {
        let dt = t - self.time;
        self.time = t;
        for (p, v) in self.positions.iter_mut().zip(&mut self.velocities) {
            *v += Vector3::from_fn(|_, _| {
                WALK_ACCEL_STD * dt.sqrt() * rng.sample::<f64, _>(StandardNormal)
            });
            *p += *v * dt;
            for i in 0..3 {
                let (lo, hi) = (VOLUME_MIN[i] + 1.0, VOLUME_MAX[i] - 1.0);
                if p[i] < lo || p[i] > hi {
                    p[i] = p[i].clamp(lo, hi);
                    v[i] = -v[i];
                }
            }
        }
    }
}

/// The sets of the scenario from `first_frame` on, `frames` frames of all 8 sensors,
/// as (stamp, sensor index, measurements) in stamp order.
fn sets(
    sensors: &[Box<dyn MeasurementModel>],
    walkers: &mut Walkers,
    first_frame: usize,
    frames: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<(f64, usize, Vec<Measurement>)> {
    let mut out = Vec::new();
    for frame in first_frame..first_frame + frames {
        for (index, sensor) in sensors.iter().enumerate() {
            let t = frame as f64 / RATE_HZ + index as f64 * PHASE_STEP_S;
            walkers.advance_to(t, rng);
            let set = support::common::simulate_set(sensor.as_ref(), &walkers.positions, rng);
            out.push((t, index, set));
        }
    }
    out
}

/// Restores of the checkpoint behind each line of [`print_set_breakdown`].
const BREAKDOWN_ROUNDS: usize = 30;

/// Prints each timed set's median time over [`BREAKDOWN_ROUNDS`] restores of `checkpoint`,
/// with its sensor, size and the mixture's size before and after: where a step's time goes
/// (the sets that receive the birth grid's components cost about twice the others).
fn print_set_breakdown(
    tracker: &mut LabelledTracker,
    checkpoint: &TrackerState,
    timed: &[(f64, usize, Vec<Measurement>)],
    sensors: &[Box<dyn MeasurementModel>],
    clock: BenchClock,
) {
    let mut times = vec![Vec::with_capacity(BREAKDOWN_ROUNDS); timed.len()];
    let mut sizes = vec![(0, 0); timed.len()];
    for _ in 0..BREAKDOWN_ROUNDS {
        tracker.restore(checkpoint.clone()).unwrap();
        for (k, (t, index, set)) in timed.iter().enumerate() {
            let before = tracker.filter().intensity().len();
            let start = clock.now();
            tracker.step(*t, sensors[*index].as_ref(), set).unwrap();
            times[k].push(clock.since(&start));
            sizes[k] = (before, tracker.filter().intensity().len());
        }
    }
    for (k, (t, index, set)) in timed.iter().enumerate() {
        times[k].sort();
        println!(
            "dense: set at {t:.4} s, sensor {index}, {} measurements, {} -> {} components: median {:?}",
            set.len(),
            sizes[k].0,
            sizes[k].1,
            times[k][BREAKDOWN_ROUNDS / 2]
        );
    }
}

fn bench_dense_step(c: &mut Criterion<BenchClock>) {
    let clock = BenchClock::from_env();
    let sensors = sensors();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut walkers = Walkers::new(&mut rng);
    let warm_frames = (WARM_UP_S * RATE_HZ) as usize;
    let mut tracker = tracker();
    for (t, index, set) in sets(&sensors, &mut walkers, 1, warm_frames, &mut rng) {
        tracker.step(t, sensors[index].as_ref(), &set).unwrap();
    }
    let checkpoint = tracker.state();
    let timed = sets(&sensors, &mut walkers, warm_frames + 1, 1, &mut rng);
    let measured: usize = timed.iter().map(|(_, _, set)| set.len()).sum();
    println!(
        "dense: after {WARM_UP_S} s, {} components, {} confirmed tracks; timed sets hold {measured} measurements",
        tracker.filter().intensity().len(),
        tracker.confirmed_tracks().count()
    );
    print_set_breakdown(&mut tracker, &checkpoint, &timed, &sensors, clock);
    c.bench_function("dense/async_step", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                // Restored into the tracker that ran the warm-up: it keeps what a running
                // server's tracker keeps from set to set besides its state (the static
                // births' projections through each sensor).
                tracker.restore(checkpoint.clone()).unwrap();
                let start = clock.now();
                for (t, index, set) in &timed {
                    tracker.step(*t, sensors[*index].as_ref(), set).unwrap();
                }
                total += clock.since(&start);
            }
            total / timed.len() as u32
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(BenchClock::from_env())
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = bench_dense_step
}
criterion_main!(benches);
