//! Pham's thesis 5.6.2-like: two speakers in a 3 × 3 × 2.5 m room located from the
//! TDOAs of four microphone pairs.
//!
//! As in the thesis: four pairs with 0.5 m spacing, 60 frames of 256 ms, two
//! speakers appearing and disappearing at different times, random-walk motion
//! with Q = diag(0.01 m²) per frame (σ = 0.1 m per frame, 0.198 m/√s), TDOA noise
//! of one sample at 16 kHz (σ = 6.25e-5 s), p_D = 0.7, p_S = 0.95 per frame,
//! clutter uniform over each pair's TDOA range [−d/c, d/c] (here 2 spurious GCC
//! peaks per pair and frame), pruning T = 1e-5, merging U = 10, J_max = 30; each
//! frame is one prediction followed by the four pairs' updates in turn (Pham 5.3).
//! Ours: the pairs sit in the middle of each wall, alternately at 1.2 m and 2.0 m;
//! the speakers walk slowly (3–4 cm per frame), at least 1 m apart; births come from a 6 × 6 grid over
//! the floor plan (σ = 0.25 m per component, 0.2 births per second in the room).
//!
//! Two variants, 20 seeded runs each, scored at the end of every frame after the
//! first 5 on the `LabelledTracker`'s confirmed tracks (default track manager;
//! each pair's set is one set, so four per frame):
//! * 2-D: state = horizontal position at the known mouth height 1.6 m — asserts
//!   the speaker count right in ≥ 80 % of the frames and the localisation part of
//!   OSPA (c = 1 m, p = 1) below 0.15 m;
//! * 3-D: state = 3-D position, speakers' mouths at 1.25 m (seated) and 1.7 m,
//!   births over heights 1–2 m — figures printed, with loose sanity bounds only
//!   (four horizontal pairs at two heights observe height weakly).
//!
//! Measured on confirmed tracks: 2-D count right in 88.4 % of the frames,
//! localisation 0.119 m, mean OSPA 0.179 m; 3-D count right in 87.3 %,
//! localisation 0.224 m, mean OSPA 0.287 m. Vo & Ma's extraction on the same
//! intensity gets the count right in only ≈ 45 % of the frames: with p_D = 0.7 the
//! last pair of a frame has missed a speaker 30 % of the time, leaving its weight
//! near 0.3; the track manager bridges those misses.

mod common;

use common::{confirmed_positions, vo_ma_positions, Scores};
use gmphd::{
    BirthTiming, Detection, FilterConfig, GmPhdFilter, GridBirth, GridBirthConfig, LabelledTracker,
    MicPair, PruneMergeCap, RandomWalk, Survival, TrackerConfig, UnscentedParams,
};
use nalgebra::{DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const RUNS: u64 = 20;
const FRAMES: usize = 60;
const FRAME_S: f64 = 0.256;
const WARM_UP_FRAMES: usize = 5;
const OSPA_CUTOFF: f64 = 1.0;
const MERGE_THRESHOLD: f64 = 10.0;
const MOUTH_HEIGHT: f64 = 1.6;
/// Pham: Q = diag(0.01) m² per frame, i.e. σ = 0.1 m per frame.
const RANDOM_WALK_STD_PER_FRAME: f64 = 0.1;

/// A speaker: start position (x, y), velocity (m/s), seated or standing mouth
/// height (3-D variant), first and last frame (1-based, inclusive).
struct Speaker {
    start: [f64; 2],
    velocity: [f64; 2],
    height: f64,
    frames: (usize, usize),
}

const SPEAKERS: [Speaker; 2] = [
    Speaker {
        start: [0.8, 0.7],
        velocity: [0.05, 0.15],
        height: 1.25,
        frames: (1, 40),
    },
    Speaker {
        start: [2.3, 2.4],
        velocity: [-0.03, -0.12],
        height: 1.7,
        frames: (16, 60),
    },
];

/// Which state the filter estimates.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    /// Horizontal position at the known mouth height.
    Planar,
    /// Full 3-D position.
    Spatial,
}

impl Variant {
    fn dims(self) -> usize {
        match self {
            Self::Planar => 2,
            Self::Spatial => 3,
        }
    }

    /// True mouth positions at frame `k` (1-based).
    fn truth(self, k: usize) -> Vec<Vector3<f64>> {
        let t = k as f64 * FRAME_S;
        SPEAKERS
            .iter()
            .filter(|s| (s.frames.0..=s.frames.1).contains(&k))
            .map(|s| {
                let z = match self {
                    Self::Planar => MOUTH_HEIGHT,
                    Self::Spatial => s.height,
                };
                Vector3::new(
                    s.start[0] + s.velocity[0] * t,
                    s.start[1] + s.velocity[1] * t,
                    z,
                )
            })
            .collect()
    }
}

fn microphone_pairs() -> Vec<MicPair> {
    common::pham_microphone_pairs(Detection::new(0.7, 2.0).unwrap())
}

fn tracker(variant: Variant) -> LabelledTracker {
    let (region_min, region_max, cells) = match variant {
        Variant::Planar => (vec![0.0, 0.0], vec![3.0, 3.0], vec![6, 6]),
        Variant::Spatial => (vec![0.0, 0.0, 1.0], vec![3.0, 3.0, 2.0], vec![6, 6, 2]),
    };
    let birth = GridBirth::new(&GridBirthConfig {
        region_min,
        region_max,
        cells,
        state_dim: variant.dims(),
        velocity_std: 0.0,
        extra_std: 0.0,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    // RandomWalk's σ is per √s: Q(dt) = σ² dt I.
    let noise_std = RANDOM_WALK_STD_PER_FRAME / FRAME_S.sqrt();
    let motion = RandomWalk::new(variant.dims(), noise_std, MOUTH_HEIGHT).unwrap();
    let filter = GmPhdFilter::new(
        Box::new(motion),
        Box::new(birth),
        Box::new(PruneMergeCap::new(1e-5, MERGE_THRESHOLD, 30).unwrap()),
        FilterConfig {
            survival: Survival::PerStep(0.95),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap();
    let config = TrackerConfig {
        merge_threshold: MERGE_THRESHOLD,
        first_interval_s: FRAME_S,
        ..TrackerConfig::default()
    };
    LabelledTracker::new(filter, config).unwrap()
}

/// Runs one variant; returns (confirmed-track scores, Vo & Ma extraction scores).
fn run_variant(variant: Variant) -> (Scores, Scores) {
    let pairs = microphone_pairs();
    let dims = variant.dims();
    let mut tracked = Scores::new(OSPA_CUTOFF, 1.0);
    let mut plain = Scores::new(OSPA_CUTOFF, 1.0);
    for run in 0..RUNS {
        let mut rng = ChaCha8Rng::seed_from_u64(5600 + run);
        let mut tracker = tracker(variant);
        for k in 1..=FRAMES {
            let t = k as f64 * FRAME_S;
            let speakers = variant.truth(k);
            for pair in &pairs {
                let set = common::simulate_set(pair, &speakers, &mut rng);
                tracker.step(t, pair, &set).unwrap();
            }
            if k <= WARM_UP_FRAMES {
                continue;
            }
            let truth: Vec<DVector<f64>> = speakers
                .iter()
                .map(|p| DVector::from_column_slice(&p.as_slice()[..dims]))
                .collect();
            tracked.record(&truth, &confirmed_positions(&tracker));
            plain.record(&truth, &vo_ma_positions(tracker.filter().intensity(), dims));
        }
    }
    (tracked, plain)
}

#[test]
fn two_speakers_at_known_mouth_height() {
    let (tracked, plain) = run_variant(Variant::Planar);
    println!("TDOA 2-D (known height), {RUNS} runs x {FRAMES} frames, OSPA c = 1 m, p = 1");
    println!("  confirmed tracks:   {}", tracked.summary("m"));
    println!("  Vo & Ma extraction: {}", plain.summary("m"));
    assert!(
        tracked.cardinality_rate() >= 0.8,
        "count right in {:.3} of the frames",
        tracked.cardinality_rate()
    );
    assert!(
        tracked.mean_localisation() < 0.15,
        "localisation {:.3} m",
        tracked.mean_localisation()
    );
}

#[test]
fn two_speakers_in_three_dimensions() {
    let (tracked, plain) = run_variant(Variant::Spatial);
    println!("TDOA 3-D, {RUNS} runs x {FRAMES} frames, OSPA c = 1 m, p = 1");
    println!("  confirmed tracks:   {}", tracked.summary("m"));
    println!("  Vo & Ma extraction: {}", plain.summary("m"));
    // Sanity bounds only (no acceptance threshold for this variant): both speakers
    // are found most of the time and placed well within the cut-off.
    assert_eq!(tracked.steps(), RUNS as usize * (FRAMES - WARM_UP_FRAMES));
    assert!(tracked.cardinality_rate() >= 0.7);
    assert!(tracked.mean_localisation() < 0.5 * OSPA_CUTOFF);
}
