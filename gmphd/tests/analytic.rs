//! One target, linear model, p_D = 1, no clutter, no births: the GM-PHD filter
//! must reduce to a Kalman filter, and its unscented update to the same numbers.

use gmphd::{BirthTiming, FilterError};
use gmphd::{
    ConstantVelocity, Detection, FilterConfig, Gaussian, GaussianMixture, GmPhdFilter, Label,
    Measurement, MeasurementModel, MixtureBirth, PositionSensor, PruneMergeCap, Survival,
    UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

const ACCEL_STD: f64 = 2.0;
const NOISE_STD: f64 = 3.0;
const TOLERANCE: f64 = 1e-9;

/// The same sensor, but claiming to be nonlinear so that the filter takes the
/// unscented path.
#[derive(Debug)]
struct ForcedUnscented(PositionSensor);

impl MeasurementModel for ForcedUnscented {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        self.0.measure_into(p, out)
    }
    fn noise_cov(&self) -> DMatrix<f64> {
        self.0.noise_cov()
    }
    fn detection_probability(&self, p: &Vector3<f64>) -> f64 {
        self.0.detection_probability(p)
    }
    fn clutter_rate(&self) -> f64 {
        self.0.clutter_rate()
    }
    fn clutter_density(&self) -> f64 {
        self.0.clutter_density()
    }
    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        self.0.sample_clutter(u)
    }
}

fn sensor() -> PositionSensor {
    PositionSensor::new(
        &[NOISE_STD, NOISE_STD],
        &[-1e4, -1e4],
        &[1e4, 1e4],
        Detection::new(1.0, 0.0).unwrap(),
    )
    .unwrap()
}

fn prior() -> (DVector<f64>, DMatrix<f64>) {
    (
        DVector::from_vec(vec![10.0, -20.0, 3.0, 1.0]),
        DMatrix::from_diagonal(&DVector::from_vec(vec![25.0, 25.0, 4.0, 4.0])),
    )
}

fn filter() -> GmPhdFilter {
    let motion = ConstantVelocity::new(2, ACCEL_STD).unwrap();
    let births = MixtureBirth::new(4, vec![], BirthTiming::PerStep).unwrap();
    let config = FilterConfig {
        survival: Survival::PerStep(1.0),
        unscented: UnscentedParams::default(),
    };
    let mut filter = GmPhdFilter::new(
        Box::new(motion),
        Box::new(births),
        Box::new(PruneMergeCap::new(1e-12, 0.0, 10).unwrap()),
        config,
        0.0,
    )
    .unwrap();
    let (mean, cov) = prior();
    filter
        .set_intensity(GaussianMixture::from_components(vec![Gaussian::new(
            1.0,
            mean,
            cov,
            Label(1),
        )]))
        .unwrap();
    filter
}

/// A textbook Kalman filter for the same model, written out independently.
struct KalmanFilter {
    mean: DVector<f64>,
    cov: DMatrix<f64>,
}

impl KalmanFilter {
    fn predict(&mut self, dt: f64) {
        let mut f = DMatrix::<f64>::identity(4, 4);
        f[(0, 2)] = dt;
        f[(1, 3)] = dt;
        let q = ACCEL_STD * ACCEL_STD;
        let block = [[dt.powi(3) / 3.0, dt * dt / 2.0], [dt * dt / 2.0, dt]];
        let mut noise = DMatrix::<f64>::zeros(4, 4);
        for axis in 0..2 {
            for (r, row) in block.iter().enumerate() {
                for (c, value) in row.iter().enumerate() {
                    noise[(axis + 2 * r, axis + 2 * c)] = q * value;
                }
            }
        }
        self.mean = &f * &self.mean;
        self.cov = &f * &self.cov * f.transpose() + noise;
    }

    fn update(&mut self, z: &DVector<f64>, noise_std: f64) {
        let mut h = DMatrix::<f64>::zeros(2, 4);
        h[(0, 0)] = 1.0;
        h[(1, 1)] = 1.0;
        let r = DMatrix::<f64>::identity(2, 2) * noise_std * noise_std;
        let s = &h * &self.cov * h.transpose() + r;
        let k = &self.cov * h.transpose() * s.try_inverse().unwrap();
        self.mean = &self.mean + &k * (z - &h * &self.mean);
        self.cov = (DMatrix::<f64>::identity(4, 4) - &k * &h) * &self.cov;
    }
}

/// Noisy measurements of a target moving at constant velocity, at irregular times.
fn scenario() -> Vec<(f64, DVector<f64>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, NOISE_STD).unwrap();
    let mut t = 0.0;
    [1.0, 0.5, 2.0, 1.0, 0.25, 3.0, 1.0, 1.0]
        .iter()
        .map(|dt| {
            t += dt;
            let z = DVector::from_vec(vec![
                12.0 + 3.0 * t + noise.sample(&mut rng),
                -19.0 + 1.2 * t + noise.sample(&mut rng),
            ]);
            (t, z)
        })
        .collect()
}

fn assert_close(a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str) {
    let diff = (a - b).amax();
    assert!(diff < TOLERANCE, "{what} differs by {diff}");
}

fn single_component(filter: &GmPhdFilter) -> &Gaussian {
    let mixture = filter.intensity();
    assert_eq!(
        mixture.len(),
        1,
        "p_D = 1 and no clutter leave exactly one component"
    );
    let component = &mixture.components[0];
    assert!((component.weight - 1.0).abs() < 1e-12);
    assert_eq!(component.label, Label(1));
    component
}

#[test]
fn linear_update_equals_kalman_filter() {
    let mut phd = filter();
    let (mean, cov) = prior();
    let mut kf = KalmanFilter { mean, cov };
    let mut last = 0.0;
    for (t, z) in scenario() {
        phd.predict_to(t).unwrap();
        phd.update(&sensor(), &[Measurement::new(z.clone())])
            .unwrap();
        phd.reduce();
        kf.predict(t - last);
        kf.update(&z, NOISE_STD);
        last = t;
        let c = single_component(&phd);
        assert_close(
            &DMatrix::from_column_slice(4, 1, c.mean.as_slice()),
            &DMatrix::from_column_slice(4, 1, kf.mean.as_slice()),
            "mean",
        );
        assert_close(&c.cov, &kf.cov, "covariance");
    }
}

#[test]
fn unscented_update_on_a_linear_sensor_equals_kalman_update() {
    let mut linear = filter();
    let mut unscented = filter();
    let forced = ForcedUnscented(sensor());
    assert!(forced.linear_position_dims().is_none());
    for (t, z) in scenario() {
        let set = [Measurement::new(z)];
        linear.predict_to(t).unwrap();
        linear.update(&sensor(), &set).unwrap();
        unscented.predict_to(t).unwrap();
        unscented.update(&forced, &set).unwrap();
        let (a, b) = (single_component(&linear), single_component(&unscented));
        assert!((&a.mean - &b.mean).amax() < TOLERANCE);
        assert_close(&a.cov, &b.cov, "covariance");
    }
}

#[test]
fn measurement_covariance_replaces_sensor_noise() {
    let mut phd = filter();
    let (mean, cov) = prior();
    let mut kf = KalmanFilter { mean, cov };
    let own_std = 0.5;
    let mut last = 0.0;
    for (t, z) in scenario().into_iter().take(3) {
        phd.predict_to(t).unwrap();
        let own = DMatrix::identity(2, 2) * own_std * own_std;
        phd.update(&sensor(), &[Measurement::with_cov(z.clone(), own)])
            .unwrap();
        kf.predict(t - last);
        kf.update(&z, own_std);
        last = t;
    }
    let c = single_component(&phd);
    assert!((&c.mean - &kf.mean).amax() < TOLERANCE);
    assert_close(&c.cov, &kf.cov, "covariance");
}
