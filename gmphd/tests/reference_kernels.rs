//! Every fast kernel of the filter against the textbook algorithm of `gmphd::reference`,
//! on random mixtures and measurement sets of every sensor kind: the update (linear and
//! unscented, on every size the update is compiled for and on the dynamic fallback, exact
//! and gated, with and without measurements' own covariances), the update as the filter
//! runs it (births, remembered birth projections, newborn labels), and the reduction.

mod common;

use gmphd::reference;
use gmphd::update::{update_gated, UpdateStep};
use gmphd::{
    BearingRange, BirthTiming, ConstantVelocity, CoordinatedTurn, Detection, FilterConfig, Gating,
    Gaussian, GaussianMixture, GmPhdFilter, GridBirth, GridBirthConfig, HeightPrior, Label, Lidar,
    Measurement, MeasurementModel, MicPair, MotionModel, PinholeCamera, PositionSensor,
    PruneMergeCap, RandomWalk, Reducer, Survival, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3x4, Vector3};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A motion model, a sensor of one kind and the box its objects live in.
struct Scene {
    motion: Box<dyn MotionModel>,
    sensor: Box<dyn MeasurementModel>,
    box_min: [f64; 3],
    box_max: [f64; 3],
}

/// Sensor kinds, each on the state size the filter meets it with.
const KINDS: usize = 8;

fn scene(kind: usize, detection: Detection) -> Scene {
    let cv = |dims| Box::new(ConstantVelocity::new(dims, 1.0).unwrap());
    let (motion, sensor, box_min, box_max): (
        Box<dyn MotionModel>,
        Box<dyn MeasurementModel>,
        _,
        _,
    ) = match kind {
        0 => (
            cv(2),
            Box::new(PositionSensor::new(&[0.5, 0.7], &[-50.0; 2], &[50.0; 2], detection).unwrap()),
            [-40.0, -40.0, 0.0],
            [40.0, 40.0, 0.0],
        ),
        1 => (
            cv(3),
            Box::new(
                PositionSensor::new(&[0.1, 0.1, 0.2], &[-10.0; 3], &[10.0; 3], detection).unwrap(),
            ),
            [-8.0, -8.0, -8.0],
            [8.0, 8.0, 8.0],
        ),
        2 => (
            cv(3),
            Box::new(look_down_camera(detection)),
            [0.0, 0.0, 0.0],
            [20.0, 20.0, 2.0],
        ),
        3 => (
            cv(3),
            Box::new(
                Lidar::new(
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0, 0.0],
                    [0.05, 0.01, 0.01],
                    50.0,
                    [-0.5, 0.5],
                    detection,
                )
                .unwrap(),
            ),
            [5.0, -10.0, -1.0],
            [30.0, 10.0, 1.0],
        ),
        4 => (
            Box::new(RandomWalk::new(2, 0.1, 1.5).unwrap()),
            Box::new(
                MicPair::new([1.25, 0.0, 1.5], [1.75, 0.0, 1.5], 343.0, 6e-5, detection).unwrap(),
            ),
            [0.2, 0.2, 1.5],
            [2.8, 2.8, 1.5],
        ),
        5 => (
            Box::new(CoordinatedTurn::new(5.0, 0.02, 0.0, UnscentedParams::default()).unwrap()),
            // Near the ±π bearing cut, where the residual wraps.
            Box::new(BearingRange::new([0.0, 0.0, 0.0], [0.05, 10.0], 3000.0, detection).unwrap()),
            [-1000.0, -300.0, 0.0],
            [-200.0, 300.0, 0.0],
        ),
        6 => (
            cv(2),
            Box::new(
                BearingRange::new([0.0, 0.0, 0.0], [0.02, 1.0], 100.0, detection)
                    .unwrap()
                    .with_height_prior(HeightPrior::new(1.0, 0.3).unwrap()),
            ),
            [-60.0, -60.0, 0.0],
            [60.0, 60.0, 0.0],
        ),
        _ => (
            cv(2),
            Box::new(
                PositionSensor::new(&[0.3, 0.3, 0.3], &[-20.0; 3], &[20.0; 3], detection)
                    .unwrap()
                    .with_height_prior(HeightPrior::new(1.0, 0.2).unwrap()),
            ),
            [-15.0, -15.0, 0.0],
            [15.0, 15.0, 0.0],
        ),
    };
    Scene {
        motion,
        sensor,
        box_min,
        box_max,
    }
}

/// A camera 15 m above (10, 10) looking straight down; at the floor it sees about 33 × 25 m.
fn look_down_camera(detection: Detection) -> PinholeCamera {
    let eye = Vector3::new(10.0, 10.0, 15.0);
    let rotation = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
    let mut extrinsics = Matrix3x4::zeros();
    extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    extrinsics.set_column(3, &(-rotation * eye));
    let intrinsics = Matrix3::new(250.0, 0.0, 320.0, 0.0, 250.0, 240.0, 0.0, 0.0, 1.0);
    PinholeCamera::new(
        intrinsics * extrinsics,
        [640.0, 480.0],
        [2.0, 2.0],
        detection,
    )
    .unwrap()
}

fn point_in(scene: &Scene, rng: &mut ChaCha8Rng) -> Vector3<f64> {
    Vector3::from_fn(|i, _| {
        let (lo, hi) = (scene.box_min[i], scene.box_max[i]);
        if lo < hi {
            rng.gen_range(lo..hi)
        } else {
            lo
        }
    })
}

/// `count` components with means in the scene's box (some near the objects) and random
/// correlated covariances of a size relative to the box's.
fn random_mixture(
    scene: &Scene,
    objects: &[Vector3<f64>],
    count: usize,
    rng: &mut ChaCha8Rng,
) -> GaussianMixture {
    let n = scene.motion.state_dim();
    let d = scene.motion.position_dims();
    let extent = (0..3)
        .map(|i| scene.box_max[i] - scene.box_min[i])
        .fold(0.0, f64::max);
    let components = (0..count)
        .map(|i| {
            let centre = match objects.get(i % (objects.len() + 1)) {
                Some(object) => {
                    object + Vector3::from_fn(|_, _| rng.gen_range(-0.02..0.02) * extent)
                }
                None => point_in(scene, rng),
            };
            let mean = DVector::from_fn(n, |r, _| {
                if r < d {
                    centre[r]
                } else {
                    rng.gen_range(-0.05..0.05)
                }
            });
            let scale = extent * rng.gen_range(0.002..0.05);
            let a = DMatrix::from_fn(n, n, |_, _| rng.gen_range(-1.0..1.0));
            let cov = (&a * a.transpose() + DMatrix::identity(n, n) * 0.1) * (scale * scale);
            Gaussian::new(rng.gen_range(0.01..1.0), mean, cov, Label(i as u64 + 1))
        })
        .collect();
    GaussianMixture::from_components(components)
}

/// A simulated set; every third measurement carries its own covariance when `own_noise`.
fn measurements(
    scene: &Scene,
    objects: &[Vector3<f64>],
    own_noise: bool,
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let mut set = common::simulate_set(scene.sensor.as_ref(), objects, rng);
    if own_noise {
        for m in set.iter_mut().step_by(3) {
            m.cov = Some(scene.sensor.noise_cov() * rng.gen_range(0.5..2.0));
        }
    }
    set
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-7 * scale.max(a.abs()).max(b.abs())
}

/// Weights below this are left out of the comparison. The exact update (no weight floor)
/// keeps children whose weight exp(log w) has underflowed into the subnormal numbers,
/// where the last few bits are all there is: the kernel and the reference compute log w
/// in different orders, so one may round such a child to the smallest subnormal and the
/// other to zero. Above it, weights are normal numbers that agree to rounding.
const NEGLIGIBLE_WEIGHT: f64 = 1e-280;

/// The two mixtures have the same components in the same order, to rounding, apart from
/// those of negligible weight; labels are compared when `labels`.
fn assert_same_mixture(
    fast: &GaussianMixture,
    reference: &GaussianMixture,
    labels: bool,
) -> Result<(), TestCaseError> {
    let weighty = |m: &GaussianMixture| -> Vec<Gaussian> {
        m.iter()
            .filter(|c| c.weight >= NEGLIGIBLE_WEIGHT)
            .cloned()
            .collect()
    };
    let (fast, reference) = (weighty(fast), weighty(reference));
    prop_assert_eq!(fast.len(), reference.len());
    let total: f64 = reference.iter().map(|c| c.weight).sum();
    for (f, r) in fast.iter().zip(reference.iter()) {
        prop_assert!(
            close(f.weight, r.weight, 1e-9 * total),
            "weight {} vs {}",
            f.weight,
            r.weight
        );
        let spread = r.cov.amax().sqrt();
        for (x, y) in f.mean.iter().zip(r.mean.iter()) {
            prop_assert!(close(*x, *y, spread), "mean {} vs {}", f.mean, r.mean);
        }
        for (x, y) in f.cov.iter().zip(r.cov.iter()) {
            prop_assert!(close(*x, *y, r.cov.amax()), "cov {} vs {}", f.cov, r.cov);
        }
        if labels {
            prop_assert_eq!(f.label, r.label);
        }
    }
    Ok(())
}

fn check_update(
    seed: u64,
    kind: usize,
    clutter_rate: f64,
    p_d: f64,
    gated: bool,
) -> Result<(), TestCaseError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let scene = scene(kind, Detection::new(p_d, clutter_rate).unwrap());
    let objects: Vec<Vector3<f64>> = (0..rng.gen_range(1..5))
        .map(|_| point_in(&scene, &mut rng))
        .collect();
    let count = rng.gen_range(1..25);
    let predicted = random_mixture(&scene, &objects, count, &mut rng);
    let set = measurements(&scene, &objects, rng.gen_bool(0.3), &mut rng);
    let unscented = UnscentedParams::default();
    let step = UpdateStep {
        motion: scene.motion.as_ref(),
        sensor: scene.sensor.as_ref(),
        unscented: &unscented,
    };
    let gating = if gated {
        Gating::default()
    } else {
        Gating::OFF
    };
    let fast = update_gated(&predicted, &step, &gating, &set).unwrap();
    let plain = reference::update(&predicted, &step, &gating, &set).unwrap();
    assert_same_mixture(&fast.posterior, &plain.posterior, true)?;
    prop_assert_eq!(fast.association.len(), plain.association.len());
    for (f, r) in fast.association.iter().zip(&plain.association) {
        prop_assert!(close(*f, *r, 1e-2), "U(z) {} vs {}", f, r);
    }
    Ok(())
}

/// The filter's own update (births, remembered projections of the static births, newborn
/// labels) and reduction, step by step against the reference on the same prior.
fn check_filter(
    seed: u64,
    kind: usize,
    clutter_rate: f64,
    gated: bool,
) -> Result<(), TestCaseError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let scene = scene(kind, Detection::new(0.9, clutter_rate).unwrap());
    let d = scene.motion.position_dims();
    let birth = GridBirth::new(&GridBirthConfig {
        region_min: scene.box_min[..d].to_vec(),
        region_max: scene.box_max[..d]
            .iter()
            .zip(&scene.box_min)
            .map(|(hi, lo)| hi.max(lo + 1.0))
            .collect(),
        cells: vec![3; d],
        state_dim: scene.motion.state_dim(),
        velocity_std: 0.5,
        extra_std: 0.02,
        total_rate: 0.5,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    let reducer = PruneMergeCap::new(1e-5, 4.0, 60).unwrap();
    let unscented = UnscentedParams::default();
    let gating = if gated {
        Gating::default()
    } else {
        Gating::OFF
    };
    let mut filter = GmPhdFilter::new(
        scene.motion,
        Box::new(birth),
        Box::new(reducer),
        FilterConfig {
            survival: Survival::PerSecond(0.99),
            unscented,
        },
        0.0,
    )
    .unwrap()
    .with_gating(gating)
    .unwrap();
    let scene = self::scene(kind, Detection::new(0.9, clutter_rate).unwrap());
    let objects: Vec<Vector3<f64>> = (0..rng.gen_range(1..4))
        .map(|_| point_in(&scene, &mut rng))
        .collect();
    for k in 1..=6 {
        filter.predict_to(0.5 * k as f64).unwrap();
        let prior = filter.intensity().clone();
        let set = measurements(&scene, &objects, false, &mut rng);
        filter.update(scene.sensor.as_ref(), &set).unwrap();
        let step = UpdateStep {
            motion: filter.motion(),
            sensor: scene.sensor.as_ref(),
            unscented: &unscented,
        };
        let plain = reference::update(&prior, &step, &gating, &set).unwrap();
        // Newborn components' children may have been given labels of their own.
        assert_same_mixture(filter.intensity(), &plain.posterior, false)?;
        let posterior = filter.intensity().clone();
        filter.reduce();
        let plain = reference::prune_merge_cap(&posterior, 1e-5, 4.0, 60);
        assert_same_mixture(filter.intensity(), &plain, true)?;
    }
    Ok(())
}

/// Clusters of narrow components, a few very wide ones and labels that repeat.
fn clustered_mixture(seed: u64, count: usize, dims: usize) -> GaussianMixture {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let components = (0..count)
        .map(|i| {
            let cluster = (i % 12) as f64;
            let wide = if rng.gen_bool(0.03) { 300.0 } else { 1.0 };
            let spread = 0.2 + rng.gen::<f64>();
            let mean = DVector::from_fn(dims, |r, _| {
                cluster * (3.0 - r as f64).max(0.5) + 2.0 * rng.gen::<f64>()
            });
            let a = DMatrix::from_fn(dims, dims, |_, _| rng.gen::<f64>() - 0.5);
            let cov =
                (&a * a.transpose() + DMatrix::identity(dims, dims)) * (spread * spread * wide);
            Gaussian::new(rng.gen::<f64>(), mean, cov, Label(rng.gen_range(0..40)))
        })
        .collect();
    GaussianMixture::from_components(components)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 96,
        rng_seed: RngSeed::Fixed(0x7265_6665),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn the_update_is_the_textbook_update(
        seed in any::<u64>(),
        kind in 0..KINDS,
        clutter_rate in prop::sample::select(vec![0.0, 0.5, 5.0, 40.0]),
        p_d in 0.05f64..=1.0,
        gated in any::<bool>(),
    ) {
        check_update(seed, kind, clutter_rate, p_d, gated)?;
    }

    #[test]
    fn the_filter_updates_and_reduces_as_the_textbook(
        seed in any::<u64>(),
        kind in 0..KINDS,
        clutter_rate in prop::sample::select(vec![0.0, 2.0, 20.0]),
        gated in any::<bool>(),
    ) {
        check_filter(seed, kind, clutter_rate, gated)?;
    }

    #[test]
    fn the_reduction_is_vo_and_mas_loop(
        seed in any::<u64>(),
        count in 1usize..400,
        dims in prop::sample::select(vec![2usize, 4, 5, 6, 7]),
        prune in prop::sample::select(vec![0.0, 1e-3, 0.2]),
        merge in prop::sample::select(vec![0.0, 1.0, 4.0, 16.0]),
        cap in 1usize..300,
    ) {
        let mixture = clustered_mixture(seed, count, dims);
        let reducer = PruneMergeCap::new(prune, merge, cap).unwrap();
        let plain = reference::prune_merge_cap(&mixture, prune, merge, cap);
        assert_same_mixture(&reducer.reduce(&mixture), &plain, true)?;
        assert_same_mixture(&reducer.reduce_recording(mixture).mixture, &plain, true)?;
    }
}
