//! The unscented update on nonlinear sensors: TDOA microphone pairs tracking
//! speakers (Pham 5.5) and two bearing-range sensors tracking a turning object
//! with the coordinated-turn model (Pham 5.6.1).

mod common;

use gmphd::{
    BearingRange, BirthTiming, CoordinatedTurn, Detection, FilterConfig, GmPhdFilter, GridBirth,
    GridBirthConfig, MicPair, MixtureBirth, PruneMergeCap, RandomWalk, Survival, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector2, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Positions (x, y) of the components with weight > 0.5.
fn confident_positions(filter: &GmPhdFilter) -> Vec<Vector2<f64>> {
    filter
        .intensity()
        .iter()
        .filter(|c| c.weight > 0.5)
        .map(|c| Vector2::new(c.mean[0], c.mean[1]))
        .collect()
}

fn nearest_distance(estimates: &[Vector2<f64>], truth: Vector2<f64>) -> f64 {
    estimates
        .iter()
        .map(|e| (e - truth).norm())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn four_microphone_pairs_localise_two_speakers() {
    // A 3 m × 3 m room, one pair of microphones 0.5 m apart in the middle of each
    // wall at speaker height; TDOA noise std 6.3e-5 s (variance 4e-9 s², one sample
    // at 16 kHz, as in Pham 5.5), one spurious GCC peak per pair and frame.
    const HEIGHT: f64 = 1.5;
    let detection = Detection::new(0.97, 1.0).unwrap();
    let noise = 4e-9f64.sqrt();
    let pairs: Vec<MicPair> = [
        ([1.25, 0.0], [1.75, 0.0]),
        ([3.0, 1.25], [3.0, 1.75]),
        ([1.75, 3.0], [1.25, 3.0]),
        ([0.0, 1.75], [0.0, 1.25]),
    ]
    .iter()
    .map(|(a, b)| {
        MicPair::new(
            [a[0], a[1], HEIGHT],
            [b[0], b[1], HEIGHT],
            343.0,
            noise,
            detection,
        )
        .unwrap()
    })
    .collect();
    let birth = GridBirth::new(&GridBirthConfig {
        region_min: vec![0.0, 0.0],
        region_max: vec![3.0, 3.0],
        cells: vec![6, 6],
        state_dim: 2,
        velocity_std: 0.0,
        extra_std: 0.0,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    let mut filter = GmPhdFilter::new(
        Box::new(RandomWalk::new(2, 0.2, HEIGHT).unwrap()),
        Box::new(birth),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 60).unwrap()),
        FilterConfig {
            survival: Survival::PerSecond(0.95),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let frame = 0.256;
    let mut localised = 0;
    let frames = 60;
    for k in 1..=frames {
        let t = k as f64 * frame;
        let speakers = [
            Vector2::new(1.0 + 0.05 * t, 1.2 + 0.02 * t),
            Vector2::new(2.0 - 0.03 * t, 2.0),
        ];
        let world: Vec<Vector3<f64>> = speakers
            .iter()
            .map(|s| Vector3::new(s.x, s.y, HEIGHT))
            .collect();
        filter.predict_to(t).unwrap();
        for pair in &pairs {
            let set = common::simulate_set(pair, &world, &mut rng);
            filter.update(pair, &set).unwrap();
        }
        filter.reduce();
        let estimates = confident_positions(&filter);
        if k > 20
            && speakers
                .iter()
                .all(|s| nearest_distance(&estimates, *s) < 0.2)
        {
            localised += 1;
        }
    }
    println!(
        "TDOA: both speakers within 0.2 m in {localised}/{} frames",
        frames - 20
    );
    // Each pair misses a speaker with probability 0.03 and a miss divides its weight
    // by ~30, so both speakers are confirmed in ≈ 0.97^8 ≈ 78 % of the frames.
    assert!(
        localised >= 28,
        "both speakers localised in only {localised} frames"
    );
}

#[test]
fn two_bearing_range_sensors_track_a_turning_object() {
    let detection = Detection::new(0.98, 10.0).unwrap();
    let sensors = [
        BearingRange::new(
            [0.0, 0.0, 0.0],
            [1f64.to_radians(), 10.0],
            3000.0,
            detection,
        )
        .unwrap(),
        BearingRange::new(
            [1000.0, 1000.0, 0.0],
            [1f64.to_radians(), 10.0],
            3000.0,
            detection,
        )
        .unwrap(),
    ];
    let birth_cov = DMatrix::from_diagonal(&DVector::from_vec(vec![
        2500.0,
        2500.0,
        2500.0,
        2500.0,
        6f64.to_radians().powi(2),
    ]));
    let birth = MixtureBirth::new(
        5,
        vec![(
            0.1,
            DVector::from_vec(vec![0.0, 1500.0, 0.0, 0.0, 0.0]),
            birth_cov,
        )],
        BirthTiming::PerStep,
    )
    .unwrap();
    let motion =
        CoordinatedTurn::new(5.0, 1f64.to_radians(), 0.0, UnscentedParams::default()).unwrap();
    let mut filter = GmPhdFilter::new(
        Box::new(motion),
        Box::new(birth),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    // Truth: starts at the birth point, 20 m/s, turning at 3°/s.
    let mut truth = DVector::from_vec(vec![0.0, 1500.0, 20.0, 0.0, 3f64.to_radians()]);
    let (mut found, mut error_sum) = (0, 0.0);
    let steps = 40;
    for k in 1..=steps {
        if k > 1 {
            truth = CoordinatedTurn::transition(&truth, 1.0);
        }
        let world = [Vector3::new(truth[0], truth[1], 0.0)];
        filter.predict_to(k as f64).unwrap();
        for sensor in &sensors {
            let set = common::simulate_set(sensor, &world, &mut rng);
            filter.update(sensor, &set).unwrap();
        }
        filter.reduce();
        let estimates = confident_positions(&filter);
        let error = nearest_distance(&estimates, Vector2::new(truth[0], truth[1]));
        if k > 5 && estimates.len() == 1 && error < 50.0 {
            found += 1;
            error_sum += error;
        }
    }
    let mean_error = error_sum / found.max(1) as f64;
    println!(
        "bearing-range: tracked alone in {found}/{} steps, mean error {mean_error:.1} m",
        steps - 5
    );
    assert!(found >= 30, "tracked in only {found} steps");
    assert!(mean_error < 20.0);
}
