//! Sequential multi-sensor update (Pham 5.3.2) and checkpoint / restore.

mod common;

use gmphd::{
    BirthTiming, ConstantVelocity, Detection, FilterConfig, FilterError, FilterState, Gaussian,
    GaussianMixture, GmPhdFilter, Label, Measurement, MixtureBirth, PositionSensor, PruneMergeCap,
    Survival, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn position_sensor(
    noise_std: f64,
    detection_probability: f64,
    clutter_rate: f64,
) -> PositionSensor {
    PositionSensor::new(
        &[noise_std, noise_std],
        &[-500.0, -500.0],
        &[500.0, 500.0],
        Detection::new(detection_probability, clutter_rate).unwrap(),
    )
    .unwrap()
}

fn filter(birth_weight: f64) -> GmPhdFilter {
    let births = vec![(
        birth_weight,
        DVector::zeros(4),
        DMatrix::from_diagonal(&DVector::from_vec(vec![1e4, 1e4, 100.0, 100.0])),
    )];
    GmPhdFilter::new(
        Box::new(ConstantVelocity::new(2, 1.0).unwrap()),
        Box::new(MixtureBirth::new(4, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 50).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(1.0),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

/// Kalman measurement update of (mean, cov) with a direct 2-D position reading.
fn kalman_update(
    mean: &DVector<f64>,
    cov: &DMatrix<f64>,
    z: &DVector<f64>,
    std: f64,
) -> (DVector<f64>, DMatrix<f64>) {
    let h = DMatrix::<f64>::identity(2, 4);
    let s = &h * cov * h.transpose() + DMatrix::<f64>::identity(2, 2) * std * std;
    let k = cov * h.transpose() * s.try_inverse().unwrap();
    (
        mean + &k * (z - &h * mean),
        (DMatrix::<f64>::identity(4, 4) - &k * &h) * cov,
    )
}

#[test]
fn sequential_update_equals_fusing_both_sensors_in_a_kalman_filter() {
    // One object, p_D = 1, no clutter, no births: each sensor's update is a Kalman
    // update, and two in a row are the Kalman filter of the stacked measurement.
    let mut phd = filter(0.0);
    let mean = DVector::from_vec(vec![5.0, -5.0, 1.0, 0.0]);
    let cov = DMatrix::from_diagonal(&DVector::from_vec(vec![50.0, 50.0, 4.0, 4.0]));
    phd.set_intensity(GaussianMixture::from_components(vec![Gaussian::new(
        1.0,
        mean.clone(),
        cov.clone(),
        Label(1),
    )]))
    .unwrap();
    let (near, far) = (
        position_sensor(2.0, 1.0, 0.0),
        position_sensor(7.0, 1.0, 0.0),
    );
    phd.predict_to(1.0).unwrap();
    let z1 = DVector::from_vec(vec![6.5, -4.0]);
    let z2 = DVector::from_vec(vec![4.0, -6.5]);
    phd.update(&near, &[Measurement::new(z1.clone())]).unwrap();
    // A second prediction to the same stamp must change nothing.
    phd.predict_to(1.0).unwrap();
    phd.update(&far, &[Measurement::new(z2.clone())]).unwrap();

    let f = ConstantVelocity::new(2, 1.0).unwrap();
    let predicted_mean = f.transition(1.0) * &mean;
    let predicted_cov =
        f.transition(1.0) * &cov * f.transition(1.0).transpose() + f.process_noise(1.0);
    let (m1, p1) = kalman_update(&predicted_mean, &predicted_cov, &z1, 2.0);
    let (m2, p2) = kalman_update(&m1, &p1, &z2, 7.0);

    let posterior = phd.intensity();
    assert_eq!(posterior.len(), 1);
    let c = &posterior.components[0];
    assert!((c.weight - 1.0).abs() < 1e-12);
    assert!((&c.mean - &m2).amax() < 1e-9);
    assert!((&c.cov - &p2).amax() < 1e-9);
}

#[test]
fn a_second_prediction_to_the_same_stamp_adds_no_births() {
    let mut phd = filter(0.1);
    phd.predict_to(1.0).unwrap();
    let after_first = phd.intensity().clone();
    phd.predict_to(1.0).unwrap();
    assert_eq!(phd.intensity(), &after_first);
    assert_eq!(after_first.len(), 1);
    assert!(matches!(
        phd.predict_to(0.5),
        Err(FilterError::TimeWentBackwards { .. })
    ));
}

#[test]
fn two_sensors_track_two_objects_in_clutter() {
    // The sequential corrector multiplies the weight of an object a sensor misses
    // by (1 - p_D), so with p_D well below 1 an object drops under 0.5 whenever
    // any sensor misses it; high p_D keeps this test about fusion, not misses.
    let sensors = [
        position_sensor(5.0, 0.99, 5.0),
        position_sensor(8.0, 0.97, 5.0),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut phd = filter(0.05);
    let start = [
        Vector3::new(-100.0, 0.0, 0.0),
        Vector3::new(150.0, 100.0, 0.0),
    ];
    let velocity = [Vector3::new(3.0, 1.0, 0.0), Vector3::new(-2.0, -4.0, 0.0)];
    let mut good_steps = 0;
    for k in 1..=40 {
        let t = k as f64;
        let objects: Vec<Vector3<f64>> = start
            .iter()
            .zip(&velocity)
            .map(|(p, v)| p + v * t)
            .collect();
        phd.predict_to(t).unwrap();
        for sensor in &sensors {
            let set = common::simulate_set(sensor, &objects, &mut rng);
            phd.update(sensor, &set).unwrap();
        }
        phd.reduce();
        let confident: Vec<&Gaussian> = phd.intensity().iter().filter(|c| c.weight > 0.5).collect();
        let all_found = objects.iter().all(|o| {
            confident
                .iter()
                .any(|c| (Vector3::new(c.mean[0], c.mean[1], 0.0) - o).norm() < 15.0)
        });
        if k > 10 && confident.len() == 2 && all_found {
            good_steps += 1;
        }
    }
    println!("two sensors, two objects: both found and nothing else in {good_steps}/30 steps");
    assert!(good_steps >= 25, "only {good_steps} good steps");
}

#[test]
fn checkpoint_restores_an_identical_filter() {
    let sensor = position_sensor(5.0, 0.9, 20.0);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let object = [Vector3::new(10.0, 20.0, 0.0)];
    let mut original = filter(0.05);
    let sets: Vec<Vec<Measurement>> = (0..20)
        .map(|_| common::simulate_set(&sensor, &object, &mut rng))
        .collect();
    for (k, set) in sets.iter().take(10).enumerate() {
        original.predict_to((k + 1) as f64).unwrap();
        original.update(&sensor, set).unwrap();
        original.reduce();
    }
    // JSON keeps every number to within an ulp (serde_json's default parser is not
    // correctly rounded); the binary encoding is exact and is what we compare runs on.
    let json = serde_json::to_string(&original.state()).unwrap();
    let from_json: FilterState = serde_json::from_str(&json).unwrap();
    assert_eq!(from_json.intensity.len(), original.intensity().len());
    for (a, b) in from_json.intensity.iter().zip(original.intensity().iter()) {
        assert!((a.weight - b.weight).abs() <= 1e-15 * b.weight);
        assert!((&a.mean - &b.mean).amax() <= 1e-12 * b.mean.amax().max(1.0));
        assert_eq!(a.label, b.label);
    }
    let bytes = postcard::to_stdvec(&original.state()).unwrap();
    let saved: FilterState = postcard::from_bytes(&bytes).unwrap();
    assert_eq!(saved, original.state());
    let mut restored = filter(0.05);
    restored.restore(saved).unwrap();
    for (k, set) in sets.iter().enumerate().skip(10) {
        for phd in [&mut original, &mut restored] {
            phd.predict_to((k + 1) as f64).unwrap();
            phd.update(&sensor, set).unwrap();
            phd.reduce();
        }
    }
    assert_eq!(original.state(), restored.state());
    assert!(
        original.state().next_label > 20,
        "one fresh label per birth"
    );
}

#[test]
fn restore_rejects_a_malformed_checkpoint() {
    let mut phd = filter(0.05);
    let wrong_dim = FilterState {
        intensity: GaussianMixture::from_components(vec![Gaussian::new(
            0.5,
            DVector::zeros(3),
            DMatrix::identity(3, 3),
            Label(1),
        )]),
        time: 0.0,
        next_label: 2,
        pending_births: Vec::new(),
        birth_owed_s: 0.0,
        newborn_labels: 0..0,
    };
    assert!(phd.restore(wrong_dim).is_err());
    let negative = FilterState {
        intensity: GaussianMixture::from_components(vec![Gaussian::new(
            -0.5,
            DVector::zeros(4),
            DMatrix::identity(4, 4),
            Label(1),
        )]),
        time: 0.0,
        next_label: 2,
        pending_births: Vec::new(),
        birth_owed_s: 0.0,
        newborn_labels: 0..0,
    };
    assert!(phd.restore(negative).is_err());
}
