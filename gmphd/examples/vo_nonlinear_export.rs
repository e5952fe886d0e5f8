//! Writes the truth and measurement sets of Vo & Ma's nonlinear GM-PHD demo (coordinated
//! turns, bearing–range sensor; the `vo_nonlinear` scenario of `benches/scans.rs`) as
//! JSON, for N seeded runs × 100 steps, so that another implementation
//! (`tools/stonesoup/vo_nonlinear.py`) can be run and scored on exactly the same data.
//!
//! ```sh
//! cargo run --release -p gmphd --example vo_nonlinear_export -- vo_nonlinear.json [--runs N] [--score]
//! ```
//!
//! Targets, sensor, filter and scans come from `tests/common/vo_nonlinear.rs` (included
//! below, shared with the benchmark). Run `r` is seeded `7100 + r`: run 0 is the
//! benchmark's run, simulated in the benchmark's call order. Default: 20 runs.
//!
//! With `--score`, our bare `GmPhdFilter` (the benchmark's `vo_nonlinear/filter`) is run on
//! the same sets and scored with Vo & Ma's extraction and OSPA (c = 100 m, p = 1, on
//! positions), with the median wall-clock time per scan (predict + update + reduce),
//! measured as the Python side does; then the `LabelledTracker` (the benchmark's
//! `vo_nonlinear/tracker`) is scored on its confirmed tracks.
//!
//! JSON layout (positions in m, bearings in rad from the x axis, sensor at the origin):
//! `{"seeds": [...], "steps": 100, "truth": [[[x, y], ...] per step],
//!   "truth_states": [[[x, y, vx, vy, ω], ...] per step],
//!   "runs": [{"seed": s, "scans": [[[bearing, range], ...] per step]}], "parameters": {...}}`.
//! The truth is the same in every run (the targets move without process noise).

#[path = "../tests/common/mod.rs"]
mod common;

use std::f64::consts::PI;

use common::vo_nonlinear::{
    filter, scans, sensor, truth, truth_states, ACCEL_NOISE_STD, BIRTHS, BIRTH_STD, CLUTTER_RATE,
    DETECTION_PROBABILITY, MAX_COMPONENTS, MAX_RANGE, MERGE_THRESHOLD, NOISE_STD, PRUNE_THRESHOLD,
    SEED, STEPS, SURVIVAL_PROBABILITY, TURN_RATE_NOISE_STD,
};
use gmphd::{BearingRange, LabelledTracker, Measurement, TrackerConfig, UnscentedParams};
use nalgebra::DVector;
use serde_json::json;

/// `--score`: our bare filter, then our tracker, on the exported sets.
fn score(truth: &[Vec<DVector<f64>>], runs: &[Vec<Vec<Measurement>>], sensor: &BearingRange) {
    common::bare_filter::print_scores(truth, runs, sensor, filter);
    score_tracker(truth, runs, sensor);
}

/// Runs the `LabelledTracker` as the server runs it (the benchmark's `vo_nonlinear/tracker`
/// configuration: the default track manager) on the exported sets and scores its confirmed
/// tracks, the estimates the service reports.
fn score_tracker(
    truth: &[Vec<DVector<f64>>],
    runs: &[Vec<Vec<Measurement>>],
    sensor: &BearingRange,
) {
    let mut scores = common::Scores::new(100.0, 1.0);
    for scans in runs {
        let config = TrackerConfig {
            first_interval_s: 1.0,
            ..TrackerConfig::default()
        };
        let mut tracker = LabelledTracker::new(filter(), config).unwrap();
        for (index, (objects, measurements)) in truth.iter().zip(scans).enumerate() {
            tracker
                .step((index + 1) as f64, sensor, measurements)
                .unwrap();
            scores.record(objects, &common::confirmed_positions(&tracker));
        }
    }
    println!(
        "our LabelledTracker, confirmed tracks: {}",
        scores.summary("m")
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = || -> ! {
        eprintln!("usage: vo_nonlinear_export OUT.json [--runs N] [--score]");
        std::process::exit(2);
    };
    let mut path = None;
    let mut runs_wanted: u64 = 20;
    let mut score_too = false;
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        match arg.as_str() {
            "--score" => score_too = true,
            "--runs" => {
                runs_wanted = rest
                    .next()
                    .and_then(|n| n.parse().ok())
                    .unwrap_or_else(|| usage())
            }
            a if !a.starts_with("--") && path.is_none() => path = Some(a.to_owned()),
            _ => usage(),
        }
    }
    let Some(path) = path else { usage() };

    let world = truth();
    let sensor = sensor();
    let seeds: Vec<u64> = (0..runs_wanted).map(|run| SEED + run).collect();
    let runs: Vec<Vec<Vec<Measurement>>> = seeds
        .iter()
        .map(|&seed| scans(&sensor, &world, seed))
        .collect();
    let positions: Vec<Vec<DVector<f64>>> = truth_states()
        .iter()
        .map(|step| step.iter().map(|s| s.rows(0, 2).into_owned()).collect())
        .collect();
    let max_true_range = positions
        .iter()
        .flatten()
        .map(|p| p[0].hypot(p[1]))
        .fold(0.0, f64::max);

    let pair = |v: &DVector<f64>| [v[0], v[1]];
    let unscented = UnscentedParams::default();
    let document = json!({
        "source": "gmphd/tests/common/vo_nonlinear.rs (the vo_nonlinear scenario of gmphd/benches/scans.rs)",
        "seeds": seeds,
        "steps": STEPS,
        "parameters": {
            "dt_s": 1.0, "sigma_v": ACCEL_NOISE_STD, "sigma_turn": TURN_RATE_NOISE_STD,
            "p_survival": SURVIVAL_PROBABILITY, "p_detection": DETECTION_PROBABILITY,
            "sensor_position": [0.0, 0.0],
            "noise_std_bearing_range": NOISE_STD, "max_range": MAX_RANGE,
            "clutter_rate": CLUTTER_RATE,
            "clutter_region_bearing_range": [[-PI, PI], [0.0, MAX_RANGE]],
            "births": BIRTHS.iter().map(|(w, xy)| json!({"weight": w, "xy": xy})).collect::<Vec<_>>(),
            "birth_std": BIRTH_STD,
            "prune": PRUNE_THRESHOLD, "merge": MERGE_THRESHOLD, "max_components": MAX_COMPONENTS,
            "unscented": {"alpha": unscented.alpha, "beta": unscented.beta, "kappa": unscented.kappa},
            "ospa_c": 100.0, "ospa_p": 1.0
        },
        "truth": positions.iter().map(|step| step.iter().map(pair).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "truth_states": truth_states().iter().map(|step| step.iter().map(|s| s.as_slice().to_vec()).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "runs": seeds.iter().zip(&runs).map(|(seed, scans)| json!({
            "seed": seed,
            "scans": scans.iter().map(|set| set.iter().map(|m| pair(&m.z)).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    });
    std::fs::write(&path, serde_json::to_string(&document).unwrap()).unwrap();
    let total: usize = runs.iter().flatten().map(Vec::len).sum();
    let run0: usize = runs.first().map_or(0, |r| r.iter().map(Vec::len).sum());
    println!(
        "wrote {path}: {} runs x {STEPS} steps, {total} measurements ({run0} in run 0, the \
         benchmark's); largest true range {max_true_range:.1} m",
        runs.len(),
    );
    if score_too {
        score(&positions, &runs, &sensor);
    }
}
