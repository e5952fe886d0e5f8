//! Gating of component–measurement pairs, parallel determinism of the update, and
//! `update_and_reduce` against `update` then `reduce`.

use gmphd::reduce::Ancestry;
use gmphd::update::{update_gated, UpdateStep};
use gmphd::{
    BearingRange, BirthTiming, ConstantVelocity, Detection, FilterConfig, FilterError, Gating,
    Gaussian, GaussianMixture, GmPhdFilter, Label, Lidar, Measurement, MeasurementModel, MicPair,
    MixtureBirth, MotionModel, PinholeCamera, PositionSensor, PruneMergeCap, Survival,
    UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3x4, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// A camera 2.5 m high outside a 3 × 2 m room's corner, looking at its middle.
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

/// `count` components of the 3-D constant-velocity state spread over the room.
fn mixture(count: usize, rng: &mut ChaCha8Rng) -> GaussianMixture {
    let components = (0..count)
        .map(|i| {
            let p = [
                rng.gen_range(0.0..3.0),
                rng.gen_range(0.0..2.0),
                rng.gen_range(1.2..2.0),
            ];
            let mean = DVector::from_vec(vec![p[0], p[1], p[2], 0.1, -0.2, 0.0]);
            let spread = rng.gen_range(0.5..2.0);
            let variances = [0.05, 0.05, 0.05, 0.3, 0.3, 0.3].map(|s: f64| (s * spread).powi(2));
            let cov = DMatrix::from_diagonal(&DVector::from_row_slice(&variances));
            Gaussian::new(rng.gen_range(0.01..1.0), mean, cov, Label(i as u64 + 1))
        })
        .collect();
    GaussianMixture::from_components(components)
}

/// A measurement of every other component's position (noisy), then `clutter` uniform ones.
fn measurements(
    sensor: &dyn MeasurementModel,
    motion: &dyn MotionModel,
    prior: &GaussianMixture,
    clutter: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let root = sensor.noise_cov().cholesky().unwrap().unpack();
    let mut set: Vec<Measurement> = prior
        .iter()
        .step_by(2)
        .map(|c| {
            let white = DVector::from_fn(sensor.dim(), |_, _| rng.sample(StandardNormal));
            Measurement::new(sensor.measure(&motion.position(&c.mean)) + &root * white)
        })
        .collect();
    for _ in 0..clutter {
        let u: Vec<f64> = (0..sensor.dim()).map(|_| rng.gen::<f64>()).collect();
        set.push(Measurement::new(sensor.sample_clutter(&u).unwrap()));
    }
    set
}

#[test]
fn one_and_two_threads_give_identical_updates() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let motion = ConstantVelocity::new(3, 1.0).unwrap();
    let sensor = camera();
    let prior = mixture(300, &mut rng);
    let set = measurements(&sensor, &motion, &prior, 40, &mut rng);
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| update_gated(&prior, &step, &Gating::default(), &set).unwrap())
    };
    let (serial, parallel) = (run(1), run(2));
    assert!(serial.posterior.len() > prior.len());
    assert_eq!(serial, parallel, "same components, same order, same bits");
}

#[test]
fn gating_drops_only_negligible_weight() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let motion = ConstantVelocity::new(3, 1.0).unwrap();
    let sensor = camera();
    let prior = mixture(100, &mut rng);
    let set = measurements(&sensor, &motion, &prior, 10, &mut rng);
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let exact = update_gated(&prior, &step, &Gating::OFF, &set).unwrap();
    let gated = update_gated(&prior, &step, &Gating::default(), &set).unwrap();
    let (w_exact, w_gated) = (
        exact.posterior.total_weight(),
        gated.posterior.total_weight(),
    );
    println!(
        "camera, 100 components x {} measurements: exact {} components (weight {w_exact:.6}), gated {} (weight {w_gated:.6})",
        set.len(),
        exact.posterior.len(),
        gated.posterior.len()
    );
    assert!(gated.posterior.len() * 5 < exact.posterior.len());
    // The pairs outside the 99.99 % gates carried almost nothing.
    assert!((w_exact - w_gated).abs() < 1e-3 * w_exact);
    for (u_exact, u_gated) in exact.association.iter().zip(&gated.association) {
        assert!((u_exact - u_gated).abs() < 1e-3, "{u_exact} vs {u_gated}");
    }
    // Every component of weight ≥ 1e-3 in the exact posterior is in the gated one, with
    // the same mean and covariance.
    for heavy in exact.posterior.iter().filter(|c| c.weight >= 1e-3) {
        let twin = gated
            .posterior
            .iter()
            .find(|c| c.label == heavy.label && (&c.mean - &heavy.mean).amax() < 1e-12)
            .expect("heavy component kept");
        // A kept weight grows by the skipped terms' share of its measurement's normaliser:
        // each at most e^(−γ/2) = 1e-4 of its component's peak, and up to 99 of them.
        assert!((twin.weight - heavy.weight).abs() < 5e-3 * heavy.weight);
        assert!((&twin.cov - &heavy.cov).amax() < 1e-12);
    }
}

#[test]
fn without_clutter_a_measurement_outside_every_gate_is_not_lost() {
    let motion = ConstantVelocity::new(2, 1.0).unwrap();
    let sensor = PositionSensor::new(
        &[1.0, 1.0],
        &[-100.0, -100.0],
        &[100.0, 100.0],
        Detection::new(1.0, 0.0).unwrap(),
    )
    .unwrap();
    let prior = GaussianMixture::from_components(vec![Gaussian::new(
        1.0,
        DVector::zeros(4),
        DMatrix::identity(4, 4),
        Label(1),
    )]);
    // 20 standard deviations away: far outside the gate, but nothing else can explain it.
    let set = [Measurement::new(DVector::from_vec(vec![20.0, 20.0]))];
    let step = UpdateStep {
        motion: &motion,
        sensor: &sensor,
        unscented: &UnscentedParams::default(),
    };
    let gated = update_gated(&prior, &step, &Gating::default(), &set).unwrap();
    let exact = update_gated(&prior, &step, &Gating::OFF, &set).unwrap();
    assert_eq!(gated, exact);
    assert_eq!(gated.posterior.len(), 1);
}

fn filter() -> GmPhdFilter {
    let births = vec![(
        0.1,
        DVector::from_vec(vec![1.5, 1.0, 1.6, 0.0, 0.0, 0.0]),
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, 0.2, 0.5, 0.5, 0.5])),
    )];
    GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 1.0).unwrap()),
        Box::new(MixtureBirth::new(6, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

#[test]
fn update_and_reduce_equals_update_then_reduce() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let motion = ConstantVelocity::new(3, 1.0).unwrap();
    let sensor = camera();
    let (mut separate, mut together) = (filter(), filter());
    let prior = mixture(60, &mut rng);
    separate.set_intensity(prior.clone()).unwrap();
    together.set_intensity(prior.clone()).unwrap();
    for k in 1..=10 {
        let set = measurements(&sensor, &motion, separate.intensity(), 5, &mut rng);
        separate.predict_to(k as f64 * 0.1).unwrap();
        together.predict_to(k as f64 * 0.1).unwrap();
        separate.update(&sensor, &set).unwrap();
        separate.reduce();
        let ancestry = together.update_and_reduce(&sensor, &set).unwrap();
        assert_eq!(separate.intensity(), together.intensity(), "step {k}");
        // Each reduced component descends from components of positive weight, its own
        // label among them.
        let Ancestry::Recorded(sets) = ancestry else {
            panic!("PruneMergeCap records its merges");
        };
        assert_eq!(sets.len(), together.intensity().len());
        for (set, component) in sets.iter().zip(together.intensity().iter()) {
            let members = set.heaviest_first();
            assert!(members.iter().all(|&(_, w)| w > 0.0));
            assert!(set.contains(component.label));
            let total: f64 = members.iter().map(|&(_, w)| w).sum();
            assert!((total - component.weight).abs() <= 1e-9 * total.max(1.0));
        }
    }
}

#[test]
fn bad_gating_is_a_typed_error() {
    let gate_of_one = Gating {
        probability: Some(1.0),
        ..Gating::default()
    };
    assert!(filter().with_gating(gate_of_one).is_err());
    let negative_floor = Gating {
        min_weight: -1e-9,
        ..Gating::default()
    };
    assert!(filter().with_gating(negative_floor).is_err());
    let filter = filter().with_gating(Gating::OFF).unwrap();
    assert_eq!(filter.gating(), &Gating::OFF);
}

/// A sensor exactly like the one it wraps, except that it gives no update hints (no index
/// dimension), so the update tests every pair.
#[derive(Debug)]
struct Unindexed<'a>(&'a dyn MeasurementModel);

impl MeasurementModel for Unindexed<'_> {
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
    fn angular_entries(&self) -> &[usize] {
        self.0.angular_entries()
    }
    fn linear_position_dims(&self) -> Option<usize> {
        self.0.linear_position_dims()
    }
    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        self.0.sample_clutter(u)
    }
}

#[test]
fn the_candidate_index_changes_nothing() {
    let detection = || Detection::new(0.9, 8.0).unwrap();
    let sensors: Vec<Box<dyn MeasurementModel>> = vec![
        Box::new(camera()),
        Box::new(PositionSensor::new(&[0.1; 3], &[0.0; 3], &[3.0, 2.0, 2.0], detection()).unwrap()),
        Box::new(
            Lidar::new(
                [-1.0, 1.0, 1.5],
                [1.0, 0.0, 0.0, 0.0],
                [0.05, 0.01, 0.01],
                20.0,
                [-0.6, 0.6],
                detection(),
            )
            .unwrap(),
        ),
        // Its bearing wraps (the room lies across ±π seen from here): it indexes by range.
        Box::new(BearingRange::new([4.0, 1.0, 0.0], [0.05, 0.1], 10.0, detection()).unwrap()),
        Box::new(
            MicPair::new(
                [1.25, 0.0, 1.2],
                [1.75, 0.0, 1.2],
                MicPair::DEFAULT_SPEED_OF_SOUND,
                6.25e-5,
                detection(),
            )
            .unwrap(),
        ),
    ];
    let motion = ConstantVelocity::new(3, 1.0).unwrap();
    let unscented = UnscentedParams::default();
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for sensor in &sensors {
        let prior = mixture(120, &mut rng);
        let mut set = measurements(sensor.as_ref(), &motion, &prior, 30, &mut rng);
        // One measurement with its own covariance, which is never indexed.
        let own = set[0].z.clone();
        set.push(Measurement::with_cov(own, sensor.noise_cov() * 4.0));
        let unindexed = Unindexed(sensor.as_ref());
        let update = |sensor: &dyn MeasurementModel| {
            let step = UpdateStep {
                motion: &motion,
                sensor,
                unscented: &unscented,
            };
            update_gated(&prior, &step, &Gating::default(), &set).unwrap()
        };
        let indexed = update(sensor.as_ref());
        assert!(sensor.update_hints().index_dim.is_some());
        assert_eq!(indexed, update(&unindexed), "{sensor:?}");
        assert!(indexed.posterior.len() > prior.len(), "{sensor:?}");
    }
}
