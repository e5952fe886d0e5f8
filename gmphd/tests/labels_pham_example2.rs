//! Pham's thesis ch. 4.4, Example 2: label continuity with up to seven crossing
//! objects in clutter, over 200 seeded Monte-Carlo runs.
//!
//! The thesis gives the example only in outline (a maximum of seven objects that
//! appear and disappear at different times, crossing paths, 10 clutter returns per
//! step, 100 steps) and reports the mean number of labels per true track over 1000
//! trials: 1.26 for its method, 1.33 for Clark's. The set-up here fills in the
//! details in the style of Vo & Ma's linear example: surveillance region
//! [−1000, 1000]² m, Δ = 1 s, constant-velocity objects (noiseless truth, filter
//! σ_a = 5 m/s²), position measurements with σ = 10 m, p_D = 0.98, p_S = 0.99,
//! Poisson clutter with mean 10 per step, four birth components of weight 0.03 at
//! the corners where objects enter, P_γ = diag(50², 50², 20², 20²), T = 1e-5,
//! U = 4, J_max = 100. All seven objects exist for k in 50..=90. Objects 1 and 2
//! cross the centre two steps apart (closest approach 32 m ≈ 3σ), objects 3 and 6
//! pass 32 m apart at k = 85, and other paths cross at larger separations. The
//! crossings are deliberately not simultaneous: when two objects occupy the same
//! point at the same step, which label belongs to which object is unobservable
//! and the per-step association with the truth below would count an arbitrary
//! "switch" there.
//!
//! Each step the labelled tracker (`LabelledTracker`: filter, Pham ch. 4
//! association, track manager) is run, its estimates are extracted from the
//! relabelled intensity and associated with the truth
//! within 50 m, and [`LabelContinuity`] counts the distinct labels per true
//! object; the same is done for the tracker's confirmed tracks. For comparison the
//! same measurements are run through the filter alone, whose labels are those
//! components inherit from birth (merges keep the heaviest's).
//!
//! Measured (200 runs): 1.049 labels per true track for the per-step estimates,
//! 1.044 for the confirmed tracks, 1.048 with the filter's own labels. In this
//! scenario the filter's labels already rarely change; the association keeps
//! them (fewer switches, 101 vs 112) rather than improving on them. The
//! assertion's bound is ≤ 1.15.

use gmphd::extract::{StateExtractor, WeightThresholdExtractor};
use gmphd::metrics::LabelContinuity;
use gmphd::{
    BirthTiming, ConstantVelocity, Detection, FilterConfig, GaussianMixture, GmPhdFilter, Label,
    LabelledTracker, Measurement, MeasurementModel, MixtureBirth, PositionSensor, PruneMergeCap,
    Survival, TrackerConfig, UnscentedParams,
};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

const STEPS: usize = 100;
const RUNS: u64 = 200;
const P_DETECT: f64 = 0.98;
const CLUTTER_RATE: f64 = 10.0;
const NOISE_STD: f64 = 10.0;
const ASSOCIATION_CUTOFF: f64 = 50.0;
const CORNER: f64 = 800.0;

/// (start position, velocity, first step, last step) of each object.
const OBJECTS: [([f64; 2], [f64; 2], usize, usize); 7] = [
    ([-CORNER, -CORNER], [16.0, 16.0], 1, 100),
    ([CORNER, -CORNER], [-16.0, 16.0], 3, 100),
    ([-CORNER, CORNER], [16.0, -10.0], 10, 90),
    ([CORNER, CORNER], [-12.0, -16.0], 20, 100),
    ([-CORNER, -CORNER], [20.0, 8.0], 30, 100),
    ([CORNER, -CORNER], [-10.0, 20.0], 44, 98),
    ([-CORNER, CORNER], [8.0, -20.0], 50, 100),
];

/// (object id, position) of the objects alive at step `k`.
fn truth_at(k: usize) -> Vec<(u64, DVector<f64>)> {
    OBJECTS
        .iter()
        .enumerate()
        .filter(|(_, o)| (o.2..=o.3).contains(&k))
        .map(|(id, ([x, y], [vx, vy], first, _))| {
            let age = (k - first) as f64;
            (
                id as u64,
                DVector::from_vec(vec![x + vx * age, y + vy * age]),
            )
        })
        .collect()
}

fn sensor() -> PositionSensor {
    PositionSensor::new(
        &[NOISE_STD, NOISE_STD],
        &[-1000.0, -1000.0],
        &[1000.0, 1000.0],
        Detection::new(P_DETECT, CLUTTER_RATE).unwrap(),
    )
    .unwrap()
}

fn filter() -> GmPhdFilter {
    let cov = DMatrix::from_diagonal(&DVector::from_vec(vec![2500.0, 2500.0, 400.0, 400.0]));
    let births = [[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]]
        .iter()
        .map(|[sx, sy]| {
            (
                0.03,
                DVector::from_vec(vec![sx * CORNER, sy * CORNER, 0.0, 0.0]),
                cov.clone(),
            )
        })
        .collect();
    GmPhdFilter::new(
        Box::new(ConstantVelocity::new(2, 5.0).unwrap()),
        Box::new(MixtureBirth::new(4, births, BirthTiming::PerStep).unwrap()),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
}

fn scan(
    truth: &[(u64, DVector<f64>)],
    sensor: &PositionSensor,
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let noise = Normal::new(0.0, NOISE_STD).unwrap();
    let mut set = Vec::new();
    for (_, p) in truth {
        if rng.gen_bool(P_DETECT) {
            set.push(Measurement::new(p.map(|v| v + noise.sample(rng))));
        }
    }
    let clutter = Poisson::new(CLUTTER_RATE).unwrap().sample(rng) as usize;
    for _ in 0..clutter {
        let u = [rng.gen::<f64>(), rng.gen::<f64>()];
        set.push(Measurement::new(sensor.sample_clutter(&u).unwrap()));
    }
    set
}

/// Labelled position estimates of an intensity.
fn labelled_positions(intensity: &GaussianMixture) -> Vec<(Label, DVector<f64>)> {
    WeightThresholdExtractor::default()
        .extract(intensity)
        .unwrap()
        .into_iter()
        .map(|e| (e.label, e.mean.rows(0, 2).into_owned()))
        .collect()
}

/// Labelled positions of the tracker's confirmed tracks.
fn confirmed_positions(tracker: &LabelledTracker) -> Vec<(Label, DVector<f64>)> {
    tracker
        .confirmed_tracks()
        .map(|track| (track.label, track.mean.rows(0, 2).into_owned()))
        .collect()
}

#[test]
fn pham_example_2_mean_labels_per_track() {
    let sensor = sensor();
    let (mut tracked_labels, mut tracked_tracks, mut tracked_switches) = (0, 0, 0);
    let (mut plain_labels, mut plain_tracks, mut plain_switches) = (0, 0, 0);
    let (mut confirmed_labels, mut confirmed_tracks) = (0, 0);
    for run in 0..RUNS {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + run);
        let mut tracker = LabelledTracker::new(filter(), TrackerConfig::default()).unwrap();
        let mut plain = filter();
        let mut with_association = LabelContinuity::new();
        let mut without_association = LabelContinuity::new();
        let mut on_confirmed_tracks = LabelContinuity::new();
        for k in 1..=STEPS {
            let truth = truth_at(k);
            let measurements = scan(&truth, &sensor, &mut rng);
            let t = k as f64;
            tracker.step(t, &sensor, &measurements).unwrap();
            let estimates = labelled_positions(tracker.filter().intensity());
            plain.predict_to(t).unwrap();
            plain.update(&sensor, &measurements).unwrap();
            plain.reduce();
            with_association
                .associate_step(&truth, &estimates, ASSOCIATION_CUTOFF)
                .unwrap();
            without_association
                .associate_step(
                    &truth,
                    &labelled_positions(plain.intensity()),
                    ASSOCIATION_CUTOFF,
                )
                .unwrap();
            on_confirmed_tracks
                .associate_step(&truth, &confirmed_positions(&tracker), ASSOCIATION_CUTOFF)
                .unwrap();
        }
        tracked_labels += with_association.total_labels();
        tracked_tracks += with_association.tracks_seen();
        tracked_switches += with_association.label_switches();
        confirmed_labels += on_confirmed_tracks.total_labels();
        confirmed_tracks += on_confirmed_tracks.tracks_seen();
        plain_labels += without_association.total_labels();
        plain_tracks += without_association.tracks_seen();
        plain_switches += without_association.label_switches();
    }
    let tracked_mean = tracked_labels as f64 / tracked_tracks as f64;
    let plain_mean = plain_labels as f64 / plain_tracks as f64;
    let confirmed_mean = confirmed_labels as f64 / confirmed_tracks as f64;
    println!(
        "Pham Example 2 ({RUNS} runs): mean labels per true track {tracked_mean:.3} with label \
         association ({tracked_switches} switches), {confirmed_mean:.3} on the confirmed tracks, \
         {plain_mean:.3} with the filter's own labels ({plain_switches} switches); \
         thesis: 1.26 (Pham), 1.33 (Clark)"
    );
    assert_eq!(
        tracked_tracks,
        7 * RUNS as usize,
        "every object was tracked in every run"
    );
    assert!(tracked_mean <= 1.15, "mean labels per track {tracked_mean}");
}
