//! A still person keeps one track with one label, also across a pause in the data (a server
//! restart, a network split), with the server's default tracker for its default room.
//!
//! Three defects made this fail before: (1) a clutter return's child (or a birth at a
//! clutter return) with a wrong velocity left the sensor's field of view, where p_D = 0 never
//! lowers its weight, so it lived on — confirmed as a false track, or merged back into the
//! person's track with its covariance of metres — fixed by `SurvivalRegion` (the site volume
//! plus 0.25 m, as the server uses it); (2) a confirmed track weakened by misses or a gap gave
//! no estimate, so the birth that explained the next detection better took the person over
//! under a new label — fixed in `LabelledTracker` (coasting confirmed tracks take part in
//! label association); (3) after a gap the head's prediction drifted just above the view,
//! where p_D at the mean is 0, so the track neither decayed nor took the detection — fixed by
//! averaging p_D over the component's spread there (`update/detection.rs`).
//!
//! Four more made a person's identity change after pauses of 0.5 s and more; fixed by (4)
//! confirmed identities winning over tentative ones where a current estimate descends from
//! both (`labels::associate_labels`); (5) a pause in the data not counting as coasting time,
//! so a track weakened by misses just before it is not deleted at the first set after it;
//! (6) within `max_coast_s` after a pause, a confirmed track whose label merging took coasts
//! on instead of being deleted at once, and (7) a coasting confirmed track continuing into
//! a newborn estimate within its predicted position's 99 % gate (the birth at the person's
//! first detection after the pause), predicted from its last state with enough weight
//! (`tracks::Anchor`) rather than from a clutter return's child.
//!
//! Measured: one label from 2 s to the end in 196 of 200 runs (40 seeds × gaps of 0, 0.5,
//! 0.7, 1 and 1.5 s): 129 with only (2), 160 with (1) and (2), 165 with (3), 170 once a
//! track whose label has no component left was deleted at once, 172 with (4), 193 with
//! (5)–(7), 196 with p_D averaged over the position's marginal only (the velocity's sigma
//! points had diluted it); every run without a gap. The 4 left (1 at 0.7 s, 3 at 1.5 s)
//! are mostly one case: the head's prediction drifts above the view (the sensor's region
//! ends at 2 m, the head is at 1.7 m, and a velocity estimate of 0.24 m/s over 1.6 s moves
//! it 0.4 m up) with a covariance of metres, so it hardly takes the detection or decays,
//! and the birth that does is confirmed beside it.

mod common;

use common::simulate_set;
use gmphd::tracks::TrackManagerConfig;
use gmphd::{
    AdaptiveBirthConfig, BirthTiming, ConstantVelocity, Detection, FilterConfig, GmPhdFilter,
    GridBirth, GridBirthConfig, LabelledTracker, PositionSensor, PruneMergeCap, Survival,
    SurvivalRegion, TrackerConfig, UnscentedParams,
};
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The server's default tracker for its default room (3 × 2 × 2 m).
fn tracker() -> LabelledTracker {
    let grid = GridBirth::new(&GridBirthConfig {
        region_min: vec![0.0, 0.0, 0.0],
        region_max: vec![3.0, 2.0, 2.0],
        cells: vec![4, 3, 1],
        state_dim: 6,
        velocity_std: 0.5,
        extra_std: 0.0,
        total_rate: 0.2,
        timing: BirthTiming::PerSecond,
    })
    .unwrap();
    let filter = GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 1.0).unwrap()),
        Box::new(grid),
        Box::new(PruneMergeCap::new(1e-5, 4.0, 100).unwrap()),
        FilterConfig {
            survival: Survival::PerSecond(0.99),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )
    .unwrap()
    .with_birth_interval(0.02)
    .unwrap()
    .with_survival_region(
        SurvivalRegion::new(vec![-0.25, -0.25, -0.25], vec![3.25, 2.25, 2.25]).unwrap(),
    )
    .unwrap()
    .with_adaptive_birth(AdaptiveBirthConfig {
        rate: 0.05,
        velocity_std: 1.0,
        min_weight: 1e-5,
        ..AdaptiveBirthConfig::default()
    })
    .unwrap();
    let config = TrackerConfig {
        tracks: TrackManagerConfig {
            confirm_threshold: 0.5,
            confirm_window: 5,
            confirm_hits: 3,
            confirm_at_once_threshold: None,
            delete_threshold: 0.15,
            delete_after_sets: 12,
            max_coast_s: 1.0,
        },
        ..TrackerConfig::default()
    };
    LabelledTracker::new(filter, config).unwrap()
}

#[test]
fn a_still_person_keeps_the_label_across_a_data_gap() {
    let sensor = PositionSensor::new(
        &[0.05, 0.05, 0.05],
        &[0.0, 0.0, 0.0],
        &[3.0, 2.0, 2.0],
        Detection::new(0.9, 2.0).unwrap(),
    )
    .unwrap();
    let person = [Vector3::new(1.5, 1.0, 1.7)];
    let mut kept = 0;
    let mut runs = 0;
    let mut failures = Vec::new();
    for gap_s in [0.0, 0.5, 0.7, 1.0, 1.5] {
        for seed in 0..40 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut tracker = tracker();
            let mut labels = Vec::new();
            let times = (1..=30)
                .map(|i| i as f64 * 0.1)
                .chain((1..=20).map(|i| 3.0 + gap_s + i as f64 * 0.1));
            for t in times {
                tracker
                    .step(t, &sensor, &simulate_set(&sensor, &person, &mut rng))
                    .unwrap();
                if t > 2.0 {
                    labels.push(
                        tracker
                            .confirmed_tracks()
                            .map(|t| t.label.0)
                            .collect::<Vec<_>>(),
                    );
                }
            }
            runs += 1;
            if labels.iter().all(|l| l.len() == 1 && *l == labels[0]) {
                kept += 1;
            } else {
                failures.push((gap_s, seed));
            }
        }
    }
    println!(
        "one track, one label from 2 s to the end in {kept} of {runs} runs; not in {failures:?}"
    );
    assert!(kept * 100 >= runs * 95, "{kept} of {runs}");
    assert!(
        failures.iter().all(|(gap, _)| *gap > 0.0),
        "without a gap: {failures:?}"
    );
}
