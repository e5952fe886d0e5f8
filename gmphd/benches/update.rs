//! Cost of one GM-PHD sensor update and of mixture reduction.
//!
//! Update: J ∈ {30, 100, 1000} predicted components of the fusion server's 3-D
//! constant-velocity state, |Z| ∈ {10, 50, 200} measurements, for a linear 3-D
//! position sensor (exact Kalman update), a 640 × 480 pinhole camera and a TDOA
//! microphone pair (both unscented, 13 sigma points per component).
//! Reduction: Vo & Ma's prune / merge / cap (T = 1e-5, U = 4, J_max = 100) of
//! 10 000 components, once as 100 clusters of 100 overlapping components that all
//! survive pruning (merging does the work) and once as the real output of an
//! update of 100 components by 99 measurements of a coarse (σ = 0.5 m) position
//! sensor (mostly pruning).
//!
//! The update grid runs with the filter's default gating ([`Gating::default`]: 99.99 %
//! χ² gate, weight floor 1e-9); `update_exact` repeats two cells of it without gating
//! (every pair emitted, as before gating existed), to show what gating saves.
//!
//! Inputs are seeded; sample sizes are small so that `cargo bench -p gmphd`
//! finishes in a few minutes. `GMPHD_BENCH_CLOCK=cpu` measures process CPU time instead
//! of wall time (see `support/clock.rs`).

mod support;

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use gmphd::reduce::Reducer;
use gmphd::update::{update_intensity, UpdateStep, Updater};
use gmphd::{
    ConstantVelocity, Detection, Gating, Gaussian, GaussianMixture, Label, Measurement,
    MeasurementModel, MicPair, PinholeCamera, PositionSensor, PruneMergeCap, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3x4, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use support::clock::BenchClock;

const COMPONENT_COUNTS: [usize; 3] = [30, 100, 1000];
const MEASUREMENT_COUNTS: [usize; 3] = [10, 50, 200];
/// The volume the objects live in (a room, heads at 1.2–2 m).
const VOLUME_MIN: [f64; 3] = [0.0, 0.0, 1.2];
const VOLUME_MAX: [f64; 3] = [3.0, 2.0, 2.0];

fn random_point(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|i, _| rng.gen_range(VOLUME_MIN[i]..VOLUME_MAX[i]))
}

/// `count` predicted components spread over the volume, moving at walking speed.
fn predicted_mixture(count: usize, rng: &mut ChaCha8Rng) -> GaussianMixture {
    let components = (0..count)
        .map(|i| {
            let p = random_point(rng);
            let v: [f64; 3] = [0, 1, 2].map(|_| 0.5 * rng.sample::<f64, _>(StandardNormal));
            let mean = DVector::from_vec(vec![p.x, p.y, p.z, v[0], v[1], v[2]]);
            let spread = rng.gen_range(0.5..2.0);
            let variances = [0.05, 0.05, 0.05, 0.3, 0.3, 0.3].map(|s: f64| (s * spread).powi(2));
            let cov = DMatrix::from_diagonal(&DVector::from_row_slice(&variances));
            Gaussian::new(rng.gen_range(0.01..1.0), mean, cov, Label(i as u64 + 1))
        })
        .collect();
    GaussianMixture::from_components(components)
}

/// `count` measurements of random points in the volume, with the sensor's noise.
fn measurements(
    sensor: &dyn MeasurementModel,
    count: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let root = sensor.noise_cov().cholesky().unwrap().unpack();
    (0..count)
        .map(|_| {
            let white = DVector::from_fn(sensor.dim(), |_, _| rng.sample(StandardNormal));
            Measurement::new(sensor.measure(&random_point(rng)) + &root * white)
        })
        .collect()
}

/// A camera 2.5 m high outside the volume's corner, looking at its centre
/// (f = 500 px, OpenCV axes).
fn camera() -> PinholeCamera {
    let centre = Vector3::new(-1.5, -1.5, 2.5);
    let forward = (Vector3::new(1.5, 1.0, 1.4) - centre).normalize();
    let right = forward.cross(&Vector3::z()).normalize();
    let down = forward.cross(&right);
    let rotation = Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
    let intrinsics = Matrix3::new(500.0, 0.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0);
    let mut extrinsics = Matrix3x4::zeros();
    extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    extrinsics.set_column(3, &(-rotation * centre));
    let detection = Detection::new(0.95, 3.0).unwrap();
    PinholeCamera::new(
        intrinsics * extrinsics,
        [640.0, 480.0],
        [3.0, 3.0],
        detection,
    )
    .unwrap()
}

fn sensors() -> Vec<(&'static str, Box<dyn MeasurementModel>)> {
    let position = PositionSensor::new(
        &[0.05, 0.05, 0.05],
        &VOLUME_MIN,
        &VOLUME_MAX,
        Detection::new(0.9, 5.0).unwrap(),
    )
    .unwrap();
    let tdoa = MicPair::new(
        [1.25, 0.0, 1.2],
        [1.75, 0.0, 1.2],
        MicPair::DEFAULT_SPEED_OF_SOUND,
        6.25e-5,
        Detection::new(0.7, 2.0).unwrap(),
    )
    .unwrap();
    vec![
        ("position3d_linear", Box::new(position)),
        ("camera_unscented", Box::new(camera())),
        ("tdoa_unscented", Box::new(tdoa)),
    ]
}

/// The cells of the grid that `update_exact` repeats without gating.
const EXACT_CELLS: [(usize, usize); 2] = [(100, 50), (1000, 200)];

fn bench_updates(c: &mut Criterion<BenchClock>) {
    let motion = ConstantVelocity::new(3, 2.0).unwrap();
    let unscented = UnscentedParams::default();
    let gating = Gating::default();
    for (name, sensor) in sensors() {
        for (kind, exact) in [("update", false), ("update_exact", true)] {
            let mut group = c.benchmark_group(format!("{kind}/{name}"));
            for j in COMPONENT_COUNTS {
                for z in MEASUREMENT_COUNTS {
                    if exact && !EXACT_CELLS.contains(&(j, z)) {
                        continue;
                    }
                    let mut rng = ChaCha8Rng::seed_from_u64((j * 1000 + z) as u64);
                    let predicted = predicted_mixture(j, &mut rng);
                    let set = measurements(sensor.as_ref(), z, &mut rng);
                    let step = UpdateStep {
                        motion: &motion,
                        sensor: sensor.as_ref(),
                        unscented: &unscented,
                    };
                    // The filter's own updater, kept from one update to the next.
                    let mut updater = Updater::new(unscented, gating).unwrap();
                    let id = BenchmarkId::new(format!("J{j}"), format!("Z{z}"));
                    group.bench_with_input(id, &(predicted, set), |b, (predicted, set)| {
                        b.iter(|| {
                            if exact {
                                update_intensity(black_box(predicted), &step, black_box(set))
                            } else {
                                updater
                                    .update(black_box(predicted), &motion, step.sensor, set)
                                    .map(|outcome| outcome.posterior)
                            }
                        })
                    });
                }
            }
            group.finish();
        }
    }
}

/// 100 clusters of 100 components each, all heavier than the pruning threshold.
fn clustered_mixture(rng: &mut ChaCha8Rng) -> GaussianMixture {
    let centres = predicted_mixture(100, rng);
    let mut components = Vec::with_capacity(10_000);
    for centre in centres.iter() {
        for _ in 0..100 {
            let jitter = DVector::from_fn(6, |i, _| {
                let scale = centre.cov[(i, i)].sqrt() * 0.5;
                scale * rng.sample::<f64, _>(StandardNormal)
            });
            components.push(Gaussian::new(
                rng.gen_range(1e-4..1e-2),
                &centre.mean + jitter,
                centre.cov.clone(),
                centre.label,
            ));
        }
    }
    GaussianMixture::from_components(components)
}

fn bench_reduction(c: &mut Criterion<BenchClock>) {
    let reducer = PruneMergeCap::new(1e-5, 4.0, 100).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(10_000);
    let clustered = clustered_mixture(&mut rng);
    let motion = ConstantVelocity::new(3, 2.0).unwrap();
    // A coarse sensor (σ = 0.5 m), so that no detection term underflows to zero
    // weight and the update yields exactly 100 × (1 + 99) components.
    let coarse = PositionSensor::new(
        &[0.5, 0.5, 0.5],
        &VOLUME_MIN,
        &VOLUME_MAX,
        Detection::new(0.9, 5.0).unwrap(),
    )
    .unwrap();
    let step = UpdateStep {
        motion: &motion,
        sensor: &coarse,
        unscented: &UnscentedParams::default(),
    };
    let predicted = predicted_mixture(100, &mut rng);
    let set = measurements(&coarse, 99, &mut rng);
    let updated = update_intensity(&predicted, &step, &set).unwrap();
    let mut group = c.benchmark_group("reduce");
    for (name, mixture) in [
        ("10000_clustered", clustered),
        ("10000_after_update", updated),
    ] {
        assert_eq!(mixture.len(), 10_000);
        group.bench_function(name, |b| b.iter(|| reducer.reduce(black_box(&mixture))));
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .with_measurement(BenchClock::from_env())
        .sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    targets = bench_updates, bench_reduction
}
criterion_main!(benches);
