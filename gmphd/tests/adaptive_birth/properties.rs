//! Properties of the birth weights over random scenes and every invertible sensor kind.

use std::f64::consts::FRAC_PI_2;

use gmphd::adaptive_birth::birth_weights;
use gmphd::{
    AdaptiveBirthConfig, BearingRange, Detection, Gaussian, GaussianMixture, Label, Lidar,
    Measurement, MeasurementModel, PositionSensor,
};
use nalgebra::{DMatrix, DVector, Vector3};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::common::simulate_set;
use super::filter;

/// One sensor of each invertible kind, with a ceiling LIDAR whose elevation reaches its
/// axis (where the inverse covariance is singular).
fn invertible_sensor(kind: usize, clutter_rate: f64) -> Box<dyn MeasurementModel> {
    let detection = Detection::new(0.9, clutter_rate).unwrap();
    match kind {
        0 => Box::new(
            PositionSensor::new(&[0.2; 3], &[0.0; 3], &[20.0, 20.0, 3.0], detection).unwrap(),
        ),
        1 => Box::new(PositionSensor::new(&[0.2; 2], &[0.0; 2], &[20.0; 2], detection).unwrap()),
        2 => Box::new(
            Lidar::new(
                [10.0, 10.0, 3.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.05, 0.01, 0.01],
                15.0,
                [0.1, FRAC_PI_2],
                detection,
            )
            .unwrap(),
        ),
        _ => Box::new(BearingRange::new([0.0, 0.0, 1.0], [0.01, 0.3], 40.0, detection).unwrap()),
    }
}

fn birth_weight_stays_in_bounds(
    seed: u64,
    kind: usize,
    clutter_rate: f64,
    rate: f64,
    tracks: usize,
) -> Result<(), TestCaseError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sensor = invertible_sensor(kind, clutter_rate);
    let mut filter = filter(false)
        .with_adaptive_birth(AdaptiveBirthConfig {
            rate,
            ..AdaptiveBirthConfig::default()
        })
        .unwrap();
    let objects: Vec<Vector3<f64>> = (0..3)
        .map(|_| {
            Vector3::new(
                rng.gen_range(2.0..18.0),
                rng.gen_range(2.0..18.0),
                rng.gen_range(0.5..2.5),
            )
        })
        .collect();
    let prior: Vec<Gaussian> = objects
        .iter()
        .take(tracks)
        .enumerate()
        .map(|(i, p)| {
            let mut mean = DVector::zeros(6);
            mean.rows_mut(0, 3).copy_from(p);
            Gaussian::new(
                rng.gen_range(0.1..1.0),
                mean,
                DMatrix::identity(6, 6) * 0.1,
                Label(i as u64 + 1),
            )
        })
        .collect();
    filter
        .set_intensity(GaussianMixture::from_components(prior))
        .unwrap();
    filter.predict_to(0.1).unwrap();
    let mut measurements = simulate_set(sensor.as_ref(), &objects, &mut rng);
    if kind == 2 {
        // Straight below the LIDAR: azimuth is undefined there.
        measurements.push(Measurement::new(DVector::from_vec(vec![
            1.5, 0.3, FRAC_PI_2,
        ])));
    }
    filter.update(sensor.as_ref(), &measurements).unwrap();
    prop_assert_eq!(filter.last_association().len(), measurements.len());
    prop_assert!(filter
        .last_association()
        .iter()
        .all(|u| (0.0..=1.0).contains(u)));
    let birth = filter.adaptive_birth().unwrap();
    let total = birth.pending_weight();
    prop_assert!(total.is_finite() && total >= 0.0, "total {}", total);
    prop_assert!(
        total <= rate * (1.0 + 1e-12),
        "total {} above the rate {}",
        total,
        rate
    );
    for candidate in birth.pending() {
        prop_assert!(
            candidate.cov.clone().cholesky().is_some(),
            "covariance not SPD"
        );
    }
    // The births survive a prediction as a valid mixture.
    filter.predict_to(0.2).unwrap();
    for component in filter.intensity().iter() {
        prop_assert!(component.weight.is_finite() && component.weight >= 0.0);
        prop_assert!(component.cov.clone().cholesky().is_some());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: RngSeed::Fixed(0xad_b127),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn total_birth_weight_is_finite_non_negative_and_at_most_the_rate(
        seed in any::<u64>(),
        kind in 0usize..4,
        clutter_rate in prop::sample::select(vec![0.0, 1.0, 20.0]),
        rate in 0.0f64..5.0,
        tracks in 0usize..4,
    ) {
        birth_weight_stays_in_bounds(seed, kind, clutter_rate, rate, tracks)?;
    }

    #[test]
    fn birth_weights_are_bounded_for_any_association(
        rate in 0.0f64..10.0,
        association in prop::collection::vec(
            prop_oneof![-1.0f64..2.0, Just(f64::NAN), Just(f64::INFINITY)], 0..20),
    ) {
        let weights = birth_weights(rate, &association).unwrap();
        prop_assert_eq!(weights.len(), association.len());
        prop_assert!(weights.iter().all(|w| w.is_finite() && *w >= 0.0));
        prop_assert!(weights.iter().sum::<f64>() <= rate * (1.0 + 1e-12));
    }
}
