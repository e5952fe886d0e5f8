//! The log-space update against the textbook GM-PHD update (Pham eq. 3.19)
//! written out in the linear domain, on a small mixture with clutter, several
//! measurements and a state-dependent detection probability.

use gmphd::update::{update_intensity, UpdateStep};
use gmphd::{
    ConstantVelocity, Detection, Gaussian, GaussianMixture, Label, Measurement, MeasurementModel,
    MotionModel, PositionSensor, UnscentedParams,
};
use nalgebra::{DMatrix, DVector};

fn component(weight: f64, x: f64, y: f64, label: u64) -> Gaussian {
    let cov = DMatrix::from_row_slice(
        4,
        4,
        &[
            30.0, 2.0, 5.0, 0.0, 2.0, 40.0, 0.0, 6.0, 5.0, 0.0, 9.0, 1.0, 0.0, 6.0, 1.0, 12.0,
        ],
    );
    Gaussian::new(
        weight,
        DVector::from_vec(vec![x, y, 1.0, -1.0]),
        cov,
        Label(label),
    )
}

/// N(z; mean, cov) evaluated directly.
fn density(z: &DVector<f64>, mean: &DVector<f64>, cov: &DMatrix<f64>) -> f64 {
    let d = z - mean;
    let inv = cov.clone().try_inverse().unwrap();
    let n = z.len() as f64;
    (-0.5 * d.dot(&(&inv * &d))).exp()
        / ((2.0 * std::f64::consts::PI).powf(n) * cov.determinant()).sqrt()
}

#[test]
fn log_space_update_matches_the_textbook_formula() {
    let motion = ConstantVelocity::new(2, 1.0).unwrap();
    let sensor = PositionSensor::new(
        &[4.0, 5.0],
        &[-100.0, -100.0],
        &[100.0, 100.0],
        Detection::new(0.9, 3.0).unwrap(),
    )
    .unwrap();
    let predicted = GaussianMixture::from_components(vec![
        component(0.7, 0.0, 0.0, 1),
        component(0.4, 12.0, -3.0, 2),
        // Outside the sensor region: p_D = 0, passes through unchanged.
        component(0.5, 150.0, 0.0, 3),
    ]);
    let zs: Vec<DVector<f64>> = [[1.0, 2.0], [10.0, -1.0], [6.0, 0.0], [-80.0, 90.0]]
        .iter()
        .map(|z| DVector::from_row_slice(z))
        .collect();
    let set: Vec<Measurement> = zs.iter().cloned().map(Measurement::new).collect();
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let posterior = update_intensity(&predicted, &step, &set).unwrap();

    // Textbook: (1 - p_D) v + Σ_z Σ_j p_D w q / (κ + Σ_l p_D w_l q_l).
    let h = DMatrix::<f64>::identity(2, 4);
    let r = sensor.noise_cov();
    let kappa = 3.0 / (200.0 * 200.0);
    let p_d: Vec<f64> = predicted
        .iter()
        .map(|c| sensor.detection_probability(&motion.position(&c.mean)))
        .collect();
    assert_eq!(p_d, vec![0.9, 0.9, 0.0]);
    let mut expected = Vec::new();
    for (c, pd) in predicted.iter().zip(&p_d) {
        expected.push(Gaussian::new(
            (1.0 - pd) * c.weight,
            c.mean.clone(),
            c.cov.clone(),
            c.label,
        ));
    }
    for z in &zs {
        let terms: Vec<f64> = predicted
            .iter()
            .zip(&p_d)
            .map(|(c, pd)| {
                pd * c.weight * density(z, &(&h * &c.mean), &(&h * &c.cov * h.transpose() + &r))
            })
            .collect();
        let normaliser = kappa + terms.iter().sum::<f64>();
        for ((c, pd), term) in predicted.iter().zip(&p_d).zip(&terms) {
            if *pd == 0.0 {
                continue;
            }
            let s = &h * &c.cov * h.transpose() + &r;
            let k = &c.cov * h.transpose() * s.try_inverse().unwrap();
            let mean = &c.mean + &k * (z - &h * &c.mean);
            let cov = (DMatrix::<f64>::identity(4, 4) - &k * &h) * &c.cov;
            expected.push(Gaussian::new(term / normaliser, mean, cov, c.label));
        }
    }
    assert_eq!(posterior.len(), expected.len());
    for (got, want) in posterior.iter().zip(&expected) {
        assert!(
            (got.weight - want.weight).abs() < 1e-12 * want.weight.max(1e-300) + 1e-300,
            "{} vs {}",
            got.weight,
            want.weight
        );
        assert!((&got.mean - &want.mean).amax() < 1e-9);
        assert!((&got.cov - &want.cov).amax() < 1e-9);
        assert_eq!(got.label, want.label);
    }
}

#[test]
fn an_empty_set_applies_only_the_missed_detection_term() {
    let motion = ConstantVelocity::new(2, 1.0).unwrap();
    let sensor = PositionSensor::new(
        &[4.0, 5.0],
        &[-100.0, -100.0],
        &[100.0, 100.0],
        Detection::new(0.9, 3.0).unwrap(),
    )
    .unwrap();
    let predicted = GaussianMixture::from_components(vec![component(0.7, 0.0, 0.0, 1)]);
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let posterior = update_intensity(&predicted, &step, &[]).unwrap();
    assert_eq!(posterior.len(), 1);
    assert!((posterior.components[0].weight - 0.07).abs() < 1e-15);
    assert_eq!(posterior.components[0].mean, predicted.components[0].mean);
}

#[test]
fn malformed_measurements_are_rejected_with_typed_errors() {
    let motion = ConstantVelocity::new(2, 1.0).unwrap();
    let sensor = PositionSensor::new(
        &[4.0, 5.0],
        &[-1.0, -1.0],
        &[1.0, 1.0],
        Detection::new(0.9, 0.0).unwrap(),
    )
    .unwrap();
    let predicted = GaussianMixture::from_components(vec![component(0.7, 0.0, 0.0, 1)]);
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let wrong_size = Measurement::new(DVector::from_vec(vec![1.0, 2.0, 3.0]));
    let not_finite = Measurement::new(DVector::from_vec(vec![f64::NAN, 2.0]));
    let bad_cov = Measurement::with_cov(
        DVector::from_vec(vec![0.0, 0.0]),
        DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]),
    );
    for bad in [wrong_size, not_finite, bad_cov] {
        assert!(update_intensity(&predicted, &step, &[bad]).is_err());
    }
}
