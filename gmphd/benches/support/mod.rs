//! Shared by the benchmarks: the clock they measure with, and measurement simulation (a
//! copy of the integration tests' `simulate_set`, so that benchmarks and accuracy tests see
//! the same kind of sets).
#![allow(dead_code)]

pub mod clock;

/// The allocator the fusion server runs with: the filter allocates a mean and a covariance
/// per child component, and glibc's malloc spends a third of an update on that.
#[global_allocator]
static ALLOCATOR: small_alloc::SmallAlloc = small_alloc::SmallAlloc;

use gmphd::{Measurement, MeasurementModel};
use nalgebra::{DVector, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};

/// One measurement set: each object detected with the sensor's p_D at its
/// position, measured with Gaussian noise, plus Poisson clutter over the region.
pub fn simulate_set(
    sensor: &dyn MeasurementModel,
    positions: &[Vector3<f64>],
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let noise_root = sensor
        .noise_cov()
        .cholesky()
        .expect("sensor noise is positive definite")
        .unpack();
    let mut set = Vec::new();
    for p in positions {
        if rng.gen::<f64>() < sensor.detection_probability(p) {
            let white = DVector::from_fn(sensor.dim(), |_, _| rng.sample::<f64, _>(StandardNormal));
            set.push(Measurement::new(sensor.measure(p) + &noise_root * white));
        }
    }
    let rate = sensor.clutter_rate();
    let clutter = if rate > 0.0 {
        Poisson::new(rate)
            .expect("clutter rate is positive")
            .sample(rng) as usize
    } else {
        0
    };
    for _ in 0..clutter {
        let u: Vec<f64> = (0..sensor.dim()).map(|_| rng.gen::<f64>()).collect();
        set.push(Measurement::new(
            sensor
                .sample_clutter(&u)
                .expect("uniforms in [0, 1) are valid"),
        ));
    }
    set
}
