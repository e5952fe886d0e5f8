//! Measurement-driven birth (Ristic, Clark, Vo & Vo 2012): the inverse sensor models, births
//! only where the intensity does not explain a measurement, and new objects picked up within a
//! few sets — also far outside the static birth volume, where a grid birth never finds them.

mod common;
// A test crate's root looks for modules next to it; these live in a folder of their own so
// that Cargo does not build them as separate test binaries.
#[path = "adaptive_birth/inverse_models.rs"]
mod inverse_models;
#[path = "adaptive_birth/properties.rs"]
mod properties;

use common::simulate_set;
use gmphd::adaptive_birth::birth_weights;
use gmphd::{
    AdaptiveBirthConfig, BirthTiming, ConstantVelocity, Detection, FilterConfig, Gaussian,
    GaussianMixture, GmPhdFilter, GridBirth, GridBirthConfig, Label, LabelledTracker, Measurement,
    MixtureBirth, PositionSensor, PruneMergeCap, Survival, TrackerConfig, UnscentedParams,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const SET_INTERVAL_S: f64 = 0.1;
const SETS: usize = 30;
/// A confirmed track within this distance of an object counts as tracking it.
const MATCH_RADIUS_M: f64 = 2.0;

/// A 3-D position sensor over a 400 m × 300 m × 3 m area with 5 clutter returns per set.
fn wide_sensor() -> PositionSensor {
    PositionSensor::new(
        &[0.3, 0.3, 0.3],
        &[-50.0, -250.0, 0.0],
        &[350.0, 50.0, 3.0],
        Detection::new(0.95, 5.0).unwrap(),
    )
    .unwrap()
}

/// Constant velocity in 3-D with a grid birth over the 10 m × 10 m × 3 m box at the origin
/// (0.2 births per second), and measurement-driven birth if `adaptive`.
fn filter(adaptive: bool) -> GmPhdFilter {
    let grid = GridBirth::new(&GridBirthConfig {
        region_min: vec![0.0, 0.0, 0.0],
        region_max: vec![10.0, 10.0, 3.0],
        cells: vec![2, 2, 1],
        state_dim: 6,
        velocity_std: 1.0,
        extra_std: 0.0,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    let filter = GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 0.5).unwrap()),
        Box::new(grid),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerSecond(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    if adaptive {
        filter
            .with_adaptive_birth(AdaptiveBirthConfig::default())
            .unwrap()
    } else {
        filter
    }
}

/// A 3-D position sensor over a 20 m × 20 m × 3 m area around the grid box with 10 clutter
/// returns per set: clutter as dense as the grid birth's weak components.
fn cluttered_sensor() -> PositionSensor {
    PositionSensor::new(
        &[0.3, 0.3, 0.3],
        &[-5.0, -5.0, 0.0],
        &[15.0, 15.0, 3.0],
        Detection::new(0.95, 10.0).unwrap(),
    )
    .unwrap()
}

/// Runs one object from `start` at `velocity` past `sensor` for `SETS` sets and returns, per
/// set, whether a confirmed track was within `MATCH_RADIUS_M` of it, and the number of
/// confirmed tracks at the end.
fn track_one_object(
    sensor: &PositionSensor,
    adaptive: bool,
    start: [f64; 3],
    velocity: [f64; 3],
) -> (Vec<bool>, usize) {
    let mut tracker = LabelledTracker::new(filter(adaptive), TrackerConfig::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0xb127);
    let mut tracked = Vec::with_capacity(SETS);
    for set in 1..=SETS {
        let t = set as f64 * SET_INTERVAL_S;
        let truth = Vector3::from(start) + Vector3::from(velocity) * t;
        let measurements = simulate_set(sensor, &[truth], &mut rng);
        tracker.step(t, sensor, &measurements).unwrap();
        let motion = tracker.filter().motion();
        tracked.push(
            tracker
                .confirmed_tracks()
                .any(|track| (motion.position(&track.mean) - truth).norm() < MATCH_RADIUS_M),
        );
    }
    (tracked, tracker.confirmed_tracks().count())
}

/// The first set (1-based) from which the object stays tracked to the end.
fn sets_to_lasting_confirmation(tracked: &[bool]) -> Option<usize> {
    let lost_after = tracked.iter().rposition(|&t| !t);
    match lost_after {
        None => Some(1),
        Some(i) if i + 1 < tracked.len() => Some(i + 2),
        Some(_) => None,
    }
}

#[test]
fn far_object_is_confirmed_only_with_adaptive_birth() {
    let start = [300.0, -200.0, 1.5];
    let velocity = [1.0, 0.5, 0.0];
    let sensor = wide_sensor();
    let (with, with_count) = track_one_object(&sensor, true, start, velocity);
    let (without, without_count) = track_one_object(&sensor, false, start, velocity);
    let with_sets = sets_to_lasting_confirmation(&with);
    println!(
        "object 360 m outside the grid box: confirmed from set {with_sets:?} with adaptive birth \
         ({with_count} confirmed at the end); tracked in {} of {SETS} sets without ({without_count} confirmed)",
        without.iter().filter(|&&t| t).count()
    );
    assert!(with_sets.is_some_and(|s| s <= 4), "{with:?}");
    assert_eq!(with_count, 1, "no track from clutter");
    assert!(without.iter().all(|&t| !t), "grid birth cannot reach it");
    assert_eq!(without_count, 0);
}

#[test]
fn adaptive_birth_picks_up_an_object_in_the_grid_box_no_later() {
    let start = [4.0, 6.0, 1.5];
    let velocity = [0.5, -0.5, 0.0];
    let sensor = cluttered_sensor();
    let (with, _) = track_one_object(&sensor, true, start, velocity);
    let (without, _) = track_one_object(&sensor, false, start, velocity);
    let with_sets = sets_to_lasting_confirmation(&with).expect("tracked with adaptive birth");
    let without_sets = sets_to_lasting_confirmation(&without).unwrap_or(SETS + 1);
    println!(
        "object inside the grid box, 10 clutter returns per set: confirmed from set {with_sets} \
         with adaptive birth, from set {without_sets} with the grid alone ({} = never)",
        SETS + 1
    );
    assert!(with_sets <= 6);
    assert!(with_sets <= without_sets);
}

/// A filter without static births, holding one object at `p` (weight 1, 0.2 m std), at t = 0.
fn filter_with_one_track(p: Vector3<f64>, rate: f64) -> GmPhdFilter {
    let mut filter = GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 0.5).unwrap()),
        Box::new(MixtureBirth::new(6, Vec::new(), BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(1.0),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
    .with_adaptive_birth(AdaptiveBirthConfig {
        rate,
        ..AdaptiveBirthConfig::default()
    })
    .unwrap();
    let mut mean = DVector::zeros(6);
    mean.rows_mut(0, 3).copy_from(&p);
    let cov = DMatrix::from_diagonal(&DVector::from_vec(vec![0.04, 0.04, 0.04, 0.25, 0.25, 0.25]));
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

fn at(p: Vector3<f64>) -> Measurement {
    Measurement::new(DVector::from_column_slice(p.as_slice()))
}

#[test]
fn an_explained_measurement_yields_almost_no_birth_weight() {
    let rate = 0.1;
    let track = Vector3::new(100.0, -100.0, 1.5);
    let stray = Vector3::new(0.0, 0.0, 1.0);
    let sensor = wide_sensor();
    let near_track = |filter: &GmPhdFilter| -> f64 {
        let birth = filter.adaptive_birth().unwrap();
        birth
            .pending()
            .iter()
            .filter(|c| (c.mean.rows(0, 3) - track).norm() < 5.0)
            .map(|c| c.weight)
            .sum()
    };

    let mut filter = filter_with_one_track(track, rate);
    filter.predict_to(0.1).unwrap();
    let offset = Vector3::new(0.1, -0.1, 0.05);
    filter
        .update(&sensor, &[at(track + offset), at(stray)])
        .unwrap();
    let association = filter.last_association().to_vec();
    println!(
        "U(z) of the track's measurement {:.9}, of the stray one {:.2e}; birth weight at the track {:.2e}, in all {:.4}",
        association[0],
        association[1],
        near_track(&filter),
        filter.adaptive_birth().unwrap().pending_weight()
    );
    assert!(association[0] > 0.999);
    assert!(association[1] < 1e-6);
    assert!(near_track(&filter) < 1e-3 * rate);
    let total = filter.adaptive_birth().unwrap().pending_weight();
    assert!(
        (total - rate).abs() < 1e-3 * rate,
        "the stray measurement takes ν_b"
    );

    // Alone in its set the explained measurement still gives (almost) nothing: the
    // normaliser is floored at one.
    let mut alone = filter_with_one_track(track, rate);
    alone.predict_to(0.1).unwrap();
    alone.update(&sensor, &[at(track + offset)]).unwrap();
    assert!(alone.adaptive_birth().unwrap().pending_weight() < 1e-3 * rate);
}

#[test]
fn pending_births_are_predicted_labelled_once_and_checkpointed() {
    let sensor = wide_sensor();
    let newcomer = Vector3::new(200.0, -30.0, 1.0);
    let mut filter = filter_with_one_track(Vector3::new(0.0, 0.0, 1.0), 0.5);
    filter.predict_to(1.0).unwrap();
    filter.update(&sensor, &[at(newcomer)]).unwrap();
    let pending = filter.adaptive_birth().unwrap().pending().to_vec();
    assert_eq!(pending.len(), 1);
    assert!((pending[0].weight - 0.5).abs() < 1e-9);

    // A second sensor at the same stamp: no prediction, the births stay pending.
    filter.predict_to(1.0).unwrap();
    assert_eq!(filter.adaptive_birth().unwrap().pending().len(), 1);

    // Checkpoint and restore keep them.
    let state = filter.state();
    assert_eq!(state.pending_births, pending);
    let mut restored = filter_with_one_track(Vector3::zeros(), 0.5);
    restored.restore(state.clone()).unwrap();
    assert_eq!(restored.state(), state);
    // A filter without adaptive birth ignores them.
    let mut plain = self::filter(false);
    plain.restore(state).unwrap();
    assert!(plain.state().pending_births.is_empty());

    // The next prediction adds them once, freshly labelled, carried over the interval.
    let first_free = filter.next_label();
    filter.predict_to(1.5).unwrap();
    assert!(filter.adaptive_birth().unwrap().pending().is_empty());
    let born: Vec<&Gaussian> = filter
        .intensity()
        .iter()
        .filter(|c| c.label.0 >= first_free)
        .collect();
    assert_eq!(born.len(), 1);
    assert!((born[0].weight - 0.5).abs() < 1e-9);
    assert!(
        (born[0].mean.rows(0, 3) - newcomer).norm() < 1e-9,
        "zero mean velocity"
    );
    let grown = born[0].cov[(0, 0)] - pending[0].cov[(0, 0)];
    assert!(
        grown >= 0.25 * 1.0,
        "position spread grows by dt² σ_v²: {grown}"
    );
    filter.predict_to(2.0).unwrap();
    let labels_after: Vec<u64> = filter.intensity().iter().map(|c| c.label.0).collect();
    assert_eq!(
        labels_after.iter().filter(|&&l| l >= first_free).count(),
        1,
        "born once"
    );
}

#[test]
fn invalid_configuration_is_rejected() {
    let base = AdaptiveBirthConfig::default();
    for bad in [
        AdaptiveBirthConfig { rate: -0.1, ..base },
        AdaptiveBirthConfig {
            rate: f64::NAN,
            ..base
        },
        AdaptiveBirthConfig {
            position_inflation: 0.5,
            ..base
        },
        AdaptiveBirthConfig {
            velocity_std: -1.0,
            ..base
        },
        AdaptiveBirthConfig {
            min_weight: f64::INFINITY,
            ..base
        },
    ] {
        assert!(filter(false).with_adaptive_birth(bad).is_err(), "{bad:?}");
    }
    assert!(birth_weights(-1.0, &[0.5]).is_err());
}
