//! Property tests: whatever the scenario — any sensor kind, empty sets, no clutter,
//! heavy clutter, extreme noise, TDOA-peaked likelihoods, irregular and zero time
//! steps, with the plain PHD update or with activity and Bernoulli labels — the intensity stays a
//! valid Gaussian mixture after every step.

mod common;

use gmphd::{
    ActivityModel, BearingRange, BirthTiming, ConstantVelocity, CoordinatedTurn, Detection,
    FilterConfig, GmPhdFilter, GridBirth, GridBirthConfig, Lidar, MeasurementModel, MicPair,
    PinholeCamera, PositionSensor, PruneMergeCap, RandomWalk, Survival, UnscentedParams,
};
use gmphd::{GaussianMixture, MotionModel};
use nalgebra::{Matrix3x4, Vector3};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const MAX_COMPONENTS: usize = 20;

/// A sensor family with the motion model and birth box that suit it.
struct Scenario {
    motion: Box<dyn MotionModel>,
    sensors: Vec<Box<dyn MeasurementModel>>,
    box_min: [f64; 3],
    box_max: [f64; 3],
    birth: GridBirthConfig,
}

fn grid(
    min: &[f64],
    max: &[f64],
    state_dim: usize,
    velocity_std: f64,
    extra_std: f64,
) -> GridBirthConfig {
    GridBirthConfig {
        region_min: min.to_vec(),
        region_max: max.to_vec(),
        cells: vec![3; min.len()],
        state_dim,
        velocity_std,
        extra_std,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    }
}

fn scenario(kind: usize, detection: Detection, noise_scale: f64) -> Scenario {
    match kind {
        0 => Scenario {
            motion: Box::new(ConstantVelocity::new(2, 2.0).unwrap()),
            sensors: vec![Box::new(
                PositionSensor::new(
                    &[2.0 * noise_scale, 3.0 * noise_scale],
                    &[-100.0, -100.0],
                    &[100.0, 100.0],
                    detection,
                )
                .unwrap(),
            )],
            box_min: [-100.0, -100.0, 0.0],
            box_max: [100.0, 100.0, 0.0],
            birth: grid(&[-100.0, -100.0], &[100.0, 100.0], 4, 5.0, 0.0),
        },
        1 => Scenario {
            motion: Box::new(ConstantVelocity::new(3, 0.5).unwrap()),
            sensors: vec![Box::new(
                PinholeCamera::new(
                    Matrix3x4::new(
                        500.0, 0.0, 320.0, 0.0, 0.0, 500.0, 240.0, 0.0, 0.0, 0.0, 1.0, 0.0,
                    ),
                    [640.0, 480.0],
                    [2.0 * noise_scale, 2.0 * noise_scale],
                    detection,
                )
                .unwrap(),
            )],
            box_min: [-2.0, -1.5, 4.0],
            box_max: [2.0, 1.5, 8.0],
            birth: grid(&[-2.0, -1.5, 4.0], &[2.0, 1.5, 8.0], 6, 0.5, 0.0),
        },
        2 => Scenario {
            motion: Box::new(RandomWalk::new(2, 0.1, 1.5).unwrap()),
            // Two orthogonal pairs of Pham's room; TDOA noise 6e-5 s, scaled.
            sensors: vec![
                Box::new(
                    MicPair::new(
                        [1.25, 0.0, 1.5],
                        [1.75, 0.0, 1.5],
                        343.0,
                        6e-5 * noise_scale,
                        detection,
                    )
                    .unwrap(),
                ),
                Box::new(
                    MicPair::new(
                        [0.0, 1.25, 1.5],
                        [0.0, 1.75, 1.5],
                        343.0,
                        6e-5 * noise_scale,
                        detection,
                    )
                    .unwrap(),
                ),
            ],
            box_min: [0.2, 0.2, 1.5],
            box_max: [2.8, 2.8, 1.5],
            birth: grid(&[0.0, 0.0], &[3.0, 3.0], 2, 0.0, 0.0),
        },
        3 => Scenario {
            motion: Box::new(ConstantVelocity::new(3, 1.0).unwrap()),
            sensors: vec![Box::new(
                Lidar::new(
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0, 0.0],
                    [0.1 * noise_scale, 0.01 * noise_scale, 0.01 * noise_scale],
                    50.0,
                    [-0.5, 0.5],
                    detection,
                )
                .unwrap(),
            )],
            box_min: [5.0, -10.0, -1.0],
            box_max: [30.0, 10.0, 1.0],
            birth: grid(&[5.0, -10.0, -1.0], &[30.0, 10.0, 1.0], 6, 2.0, 0.0),
        },
        _ => Scenario {
            motion: Box::new(
                CoordinatedTurn::new(5.0, 0.02, 0.0, UnscentedParams::default()).unwrap(),
            ),
            sensors: vec![
                Box::new(
                    BearingRange::new(
                        [0.0, 0.0, 0.0],
                        [0.05 * noise_scale, 10.0 * noise_scale],
                        3000.0,
                        detection,
                    )
                    .unwrap(),
                ),
                Box::new(
                    BearingRange::new(
                        [1000.0, 1000.0, 0.0],
                        [0.05 * noise_scale, 10.0 * noise_scale],
                        3000.0,
                        detection,
                    )
                    .unwrap(),
                ),
            ],
            box_min: [-1000.0, -1000.0, 0.0],
            box_max: [1000.0, 1000.0, 0.0],
            birth: grid(&[-1000.0, -1000.0], &[1000.0, 1000.0], 5, 20.0, 0.05),
        },
    }
}

/// The invariants of a GM-PHD intensity.
fn check_mixture(mixture: &GaussianMixture, state_dim: usize) -> Result<(), TestCaseError> {
    let total = mixture.total_weight();
    prop_assert!(total.is_finite(), "total weight {total}");
    for c in mixture.iter() {
        prop_assert!(
            c.weight >= 0.0 && c.weight.is_finite(),
            "weight {}",
            c.weight
        );
        prop_assert!((0.0..=1.0).contains(&c.activity), "activity {}", c.activity);
        prop_assert_eq!(c.mean.len(), state_dim);
        prop_assert!(c.mean.iter().all(|x| x.is_finite()), "mean {}", c.mean);
        let scale = c.cov.amax();
        prop_assert!(scale.is_finite());
        prop_assert!(
            (&c.cov - c.cov.transpose()).amax() <= 1e-12 * scale,
            "asymmetric covariance"
        );
        prop_assert!(
            c.cov.clone().cholesky().is_some(),
            "covariance not positive definite: {}",
            c.cov
        );
    }
    Ok(())
}

/// Whether the filter models activity and updates labels as Bernoulli existences.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Options {
    Plain,
    ActivityAndExistence,
}

fn run(
    seed: u64,
    kind: usize,
    clutter_rate: f64,
    noise_scale: f64,
    p_d: f64,
    steps: usize,
    options: Options,
) -> Result<(), TestCaseError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let detection = Detection::new(p_d, clutter_rate).unwrap();
    let Scenario {
        motion,
        sensors,
        box_min,
        box_max,
        birth,
    } = scenario(kind, detection, noise_scale);
    let state_dim = motion.state_dim();
    let mut filter = GmPhdFilter::new(
        motion,
        Box::new(GridBirth::new(&birth).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, MAX_COMPONENTS).unwrap()),
        FilterConfig {
            survival: Survival::PerSecond(0.95),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    if options == Options::ActivityAndExistence {
        filter = filter
            .with_activity(ActivityModel::default())
            .unwrap()
            .with_label_existence();
    }
    let objects: Vec<Vector3<f64>> = (0..rng.gen_range(0..4))
        .map(|_| {
            Vector3::from_fn(|i, _| {
                if box_min[i] < box_max[i] {
                    rng.gen_range(box_min[i]..box_max[i])
                } else {
                    box_min[i]
                }
            })
        })
        .collect();
    let mut t = 0.0;
    for _ in 0..steps {
        // Zero steps happen: a second report at the same stamp.
        t += [0.0, 0.05, 1.0, 3.0][rng.gen_range(0..4)];
        filter.predict_to(t).unwrap();
        check_mixture(filter.intensity(), state_dim)?;
        for sensor in &sensors {
            let set = if rng.gen::<f64>() < 0.2 {
                Vec::new()
            } else {
                common::simulate_set(sensor.as_ref(), &objects, &mut rng)
            };
            filter.update(sensor.as_ref(), &set).unwrap();
            check_mixture(filter.intensity(), state_dim)?;
        }
        filter.reduce();
        check_mixture(filter.intensity(), state_dim)?;
        prop_assert!(filter.intensity().len() <= MAX_COMPONENTS);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: RngSeed::Fixed(0x6d70_6864),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn intensity_stays_a_valid_mixture(
        seed in any::<u64>(),
        kind in 0usize..5,
        clutter_rate in prop::sample::select(vec![0.0, 0.5, 5.0, 40.0]),
        noise_scale in prop::sample::select(vec![1e-3, 1.0, 50.0]),
        p_d in 0.05f64..=1.0,
        steps in 3usize..12,
        modelled in any::<bool>(),
    ) {
        let options = if modelled { Options::ActivityAndExistence } else { Options::Plain };
        run(seed, kind, clutter_rate, noise_scale, p_d, steps, options)?;
    }
}

#[test]
fn tdoa_peaked_likelihoods_in_heavy_clutter() {
    // The stress case of very peaked likelihoods explicitly: 6e-5 s noise (densities ~1e4 per second
    // of delay) and 6e-8 s (~1e7), with and without clutter, for many seeds.
    for seed in 0..12 {
        for (noise_scale, clutter) in [(1.0, 0.0), (1.0, 20.0), (1e-3, 0.0), (1e-3, 20.0)] {
            for options in [Options::Plain, Options::ActivityAndExistence] {
                run(seed, 2, clutter, noise_scale, 0.9, 10, options).unwrap();
            }
        }
    }
}
