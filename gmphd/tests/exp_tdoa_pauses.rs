//! Two talkers who take turns, heard by four microphone pairs: the setting of Pham's 5.6.2 (the
//! geometry and models of `exp_tdoa.rs`), except that each talker pauses between talk spurts
//! and a pair hears only the talker who talks. Both talkers stay in the room all the time, so
//! the right count is two in every frame, also while one of them is silent.
//!
//! The plain GM-PHD filter takes each of the four pairs' sets without a silent talker as a miss
//! (`1 − p_D` each): the talker's weight is gone within a frame or two of a pause. With the
//! talkers' activity modelled (`gmphd::activity`) and each label updated as a Bernoulli
//! (`gmphd::existence`), a pause is weak evidence and a sure track outlasts it. Asserted: the
//! count right in at least 80 % of the frames with both, and below half of that without.

mod common;

use common::{confirmed_positions, Scores};
use gmphd::{
    ActivityModel, BirthTiming, Detection, FilterConfig, GmPhdFilter, GridBirth, GridBirthConfig,
    LabelledTracker, MicPair, PruneMergeCap, RandomWalk, Survival, TrackerConfig, UnscentedParams,
};
use nalgebra::{DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const RUNS: u64 = 10;
const FRAMES: usize = 80;
const FRAME_S: f64 = 0.256;
const WARM_UP_FRAMES: usize = 12;
const MOUTH_HEIGHT: f64 = 1.6;
/// σ of the talkers' random walk per frame, m (Pham: 0.1).
const RANDOM_WALK_STD_PER_FRAME: f64 = 0.1;
/// Frames of a talk spurt and of the pause after it (1.5 s each).
const SPURT_FRAMES: usize = 6;

/// Talker `i`'s mouth at frame `k`: a slow straight walk.
fn mouth(i: usize, k: usize) -> Vector3<f64> {
    let t = k as f64 * FRAME_S;
    let (start, velocity) = [([0.8, 0.7], [0.03, 0.05]), ([2.2, 2.3], [-0.02, -0.04])][i];
    Vector3::new(
        start[0] + velocity[0] * t,
        start[1] + velocity[1] * t,
        MOUTH_HEIGHT,
    )
}

/// Whether talker `i` talks in frame `k`: spurts and pauses of equal length, the second
/// talker a third of a cycle later, so that they overlap and both pause at times.
fn talks(i: usize, k: usize) -> bool {
    let phase = k + i * (2 * SPURT_FRAMES) / 3;
    (phase / SPURT_FRAMES).is_multiple_of(2)
}

fn microphone_pairs() -> Vec<MicPair> {
    common::pham_microphone_pairs(Detection::new(0.9, 1.0).unwrap())
}

/// The tracker of `exp_tdoa.rs`'s planar variant, with the pauses modelled or not.
fn tracker(pauses_modelled: bool) -> LabelledTracker {
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
    let noise_std = RANDOM_WALK_STD_PER_FRAME / FRAME_S.sqrt();
    let motion = RandomWalk::new(2, noise_std, MOUTH_HEIGHT).unwrap();
    let filter = GmPhdFilter::new(
        Box::new(motion),
        Box::new(birth),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 30).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    let filter = if pauses_modelled {
        filter
            .with_activity(ActivityModel {
                mean_active_s: SPURT_FRAMES as f64 * FRAME_S,
                mean_inactive_s: SPURT_FRAMES as f64 * FRAME_S,
            })
            .unwrap()
            .with_label_existence()
    } else {
        filter
    };
    let config = TrackerConfig {
        merge_threshold: 4.0,
        first_interval_s: FRAME_S,
        ..TrackerConfig::default()
    };
    LabelledTracker::new(filter, config).unwrap()
}

fn run(pauses_modelled: bool) -> Scores {
    let pairs = microphone_pairs();
    let mut scores = Scores::new(1.0, 1.0);
    for run in 0..RUNS {
        let mut rng = ChaCha8Rng::seed_from_u64(5620 + run);
        let mut tracker = tracker(pauses_modelled);
        for k in 1..=FRAMES {
            let t = k as f64 * FRAME_S;
            let talking: Vec<Vector3<f64>> = (0..2)
                .filter(|&i| talks(i, k))
                .map(|i| mouth(i, k))
                .collect();
            for pair in &pairs {
                let set = common::simulate_set(pair, &talking, &mut rng);
                tracker.step(t, pair, &set).unwrap();
            }
            if k > WARM_UP_FRAMES {
                let truth: Vec<DVector<f64>> = (0..2)
                    .map(|i| DVector::from_column_slice(&mouth(i, k).as_slice()[..2]))
                    .collect();
                scores.record(&truth, &confirmed_positions(&tracker));
            }
        }
    }
    scores
}

#[test]
fn talkers_who_pause_keep_their_tracks() {
    let modelled = run(true);
    let plain = run(false);
    println!("two talkers taking turns, {RUNS} runs x {FRAMES} frames, OSPA c = 1 m, p = 1");
    println!(
        "  pauses modelled, Bernoulli labels: {}",
        modelled.summary("m")
    );
    println!(
        "  plain GM-PHD:                      {}",
        plain.summary("m")
    );
    assert!(
        modelled.cardinality_rate() >= 0.8,
        "count right in {:.3} of the frames",
        modelled.cardinality_rate()
    );
    assert!(modelled.mean_localisation() < 0.15);
    assert!(
        plain.cardinality_rate() < 0.5 * modelled.cardinality_rate(),
        "the plain filter's count is right in {:.3} of the frames",
        plain.cardinality_rate()
    );
}
