//! Vo & Ma's linear demo scored on the `LabelledTracker`'s confirmed tracks.
//!
//! Scenario and filter as in `vo_demo.rs` (`common/vo_demo.rs`: the 12 targets of the
//! demo's `gen_truth.m`; 2-D constant velocity, T = 1 s, σ_v = 5 m/s²; p_S 0.99; four birth
//! components of weight 0.03, P = diag(10²); σ = 10 m; p_D 0.98; 60 clutter returns
//! per scan over [−1000, 1000]²; pruning T = 1e-5, merging U = 4, J_max = 100; 100
//! steps, 50 seeded runs), scored with OSPA (c = 100 m, p = 1) on positions.
//!
//! The estimate set is the tracker's confirmed tracks. For comparison the same runs
//! are also scored with Vo & Ma's own extraction (every component of weight > 0.5
//! gives round(w) copies) on the very same intensity.
//!
//! Track manager settings, chosen from the scenario's model parameters (not from
//! the truth of any run) and then compared on these runs:
//! * confirm: label weight > 0.3 in 2 of the last 3 scans. A new target's first
//!   scan gives its birth label ≈ 0.25–0.6 (birth weight 0.03 against clutter
//!   κ = 1.5e-5 m⁻²); one clutter return near a birth point rarely repeats, so two
//!   hits reject it (with 1 hit, ≈ 3 false tracks per run appear there). One scan
//!   above 0.8 confirms at once (MATLAB `trackerPHD`'s `ConfirmationThreshold`): a
//!   birth label cannot reach it on its first scan (at most ≈ 0.6 here), so it takes a
//!   target that was born one scan earlier and moved as its velocity predicted — a
//!   target faster than the birth prior's σ = 10 m/s (targets 7, 8, 11, 12 move at
//!   14–25 m/s) often gets its birth label above 0.3 only on its 2nd scan. Labels that
//!   split off a confirmed track (clutter beside it) are excluded.
//! * delete: after 2 consecutive scans below 0.05. A miss (p = 0.02) leaves a
//!   target's weight at ≈ 0.02 and the next detection lifts it well above 0.05, so
//!   a track survives one miss; a target that died is dropped on the 2nd scan.
//!
//! Targets 4 and 5 are born at k = 20 from the same birth component 15 m apart, and
//! targets 1 and 2 cross near k = 43; each birth child gets its own label
//! (`gmphd::newborn`), and a cluster that descends from an identity no estimate carries
//! any more is reported so that the identity can continue
//! (`labels::report_lost_identities`). Before those two the count was right
//! in 78.1 % of the steps, the twins sharing one label for 3–4 scans and the crossing
//! costing one identity and two scans of a new one's confirmation.
//!
//! Acceptance. Mean OSPA ≤ 19 m holds with margin (measured 13.75 m against 20.62 m
//! for Vo & Ma's extraction); the count is right in 81.3 % of the steps (94.9 % away from
//! births and deaths). What is left is mostly what no track manager can remove: a track
//! needs two scans of evidence, so every birth step is wrong, and the scan in which a
//! target dies still shows its track (k = 71).
//!
//! So the test asserts the count right in ≥ 80 % of all steps and ≥ 90 % of the
//! steps away from births and deaths, and prints every figure.

mod common;

use common::vo_demo::{filter, scan, sensor, truth, MERGE_THRESHOLD, STEPS};
use common::{confirmed_positions, vo_ma_positions, Scores};
use gmphd::tracks::TrackManagerConfig;
use gmphd::{LabelledTracker, TrackerConfig};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const RUNS: u64 = 50;
const OSPA_CUTOFF: f64 = 100.0;

fn tracker() -> LabelledTracker {
    let config = TrackerConfig {
        extraction_threshold: 0.5,
        merge_threshold: MERGE_THRESHOLD,
        first_interval_s: 1.0,
        // 9 and 16 were tried too (76.8 % and 78.8 % of counts right): below 25, clutter
        // next to a target gets identities of its own in the steady steps.
        separation_gate: 25.0,
        tracks: TrackManagerConfig {
            confirm_threshold: 0.3,
            confirm_window: 3,
            confirm_hits: 2,
            confirm_at_once_threshold: Some(0.8),
            delete_threshold: 0.05,
            delete_after_sets: 2,
            max_coast_s: f64::INFINITY,
        },
    };
    LabelledTracker::new(filter(), config).unwrap()
}

/// Steps at which targets are born (several at once) and die, from `TARGETS`.
const BIRTH_STEPS: [usize; 5] = [1, 20, 40, 60, 80];
const DEATH_STEP: usize = 71;
/// How many steps after a birth or death the count is scored as "transient".
const TRANSIENT_STEPS: usize = 5;

/// Whether step `k` (1-based) lies within `TRANSIENT_STEPS` of a birth or death.
fn is_transient(k: usize) -> bool {
    BIRTH_STEPS
        .iter()
        .chain(&[DEATH_STEP])
        .any(|&event| (event..event + TRANSIENT_STEPS).contains(&k))
}

#[test]
fn vo_ma_demo_scored_on_confirmed_tracks() {
    let truth = truth();
    let sensor = sensor();
    let mut tracked = Scores::new(OSPA_CUTOFF, 1.0);
    let mut plain = Scores::new(OSPA_CUTOFF, 1.0);
    // The confirmed-track scores split into the steps just after a birth or death and the rest.
    let mut transient = Scores::new(OSPA_CUTOFF, 1.0);
    let mut steady = Scores::new(OSPA_CUTOFF, 1.0);
    for run in 0..RUNS {
        let mut rng = ChaCha8Rng::seed_from_u64(7000 + run);
        let mut tracker = tracker();
        for (index, objects) in truth.iter().enumerate() {
            let k = index + 1;
            let measurements = scan(objects, &sensor, &mut rng);
            tracker.step(k as f64, &sensor, &measurements).unwrap();
            assert!(tracker.filter().intensity().len() <= 100);
            let confirmed = confirmed_positions(&tracker);
            tracked.record(objects, &confirmed);
            let phase = if is_transient(k) {
                &mut transient
            } else {
                &mut steady
            };
            phase.record(objects, &confirmed);
            plain.record(objects, &vo_ma_positions(tracker.filter().intensity(), 2));
        }
    }
    println!("Vo & Ma demo, {RUNS} runs x {STEPS} steps, OSPA c = {OSPA_CUTOFF} m, p = 1");
    println!("  confirmed tracks:   {}", tracked.summary("m"));
    println!(
        "    <{TRANSIENT_STEPS} steps after a birth/death: {}",
        transient.summary("m")
    );
    println!("    other steps:                 {}", steady.summary("m"));
    println!("  Vo & Ma extraction: {}", plain.summary("m"));
    assert!(
        tracked.mean_ospa() <= 19.0,
        "mean OSPA {:.2} m",
        tracked.mean_ospa()
    );
    assert!(
        tracked.cardinality_rate() >= 0.80,
        "count right in {:.3} of the steps",
        tracked.cardinality_rate()
    );
    assert!(
        steady.cardinality_rate() >= 0.9,
        "count right in {:.3} of the steady steps",
        steady.cardinality_rate()
    );
    assert!(tracked.mean_ospa() < plain.mean_ospa());
}
