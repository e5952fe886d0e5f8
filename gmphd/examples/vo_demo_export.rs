//! Writes the truth and measurement sets of `tests/exp_vo_demo.rs` (Vo & Ma's linear
//! GM-PHD demo, 50 seeded runs × 100 steps) as JSON, so that another implementation
//! (`tools/stonesoup/vo_linear.py`) can be run and scored on exactly the same data.
//!
//! ```sh
//! cargo run --release -p gmphd --example vo_demo_export -- vo_demo.json [--score]
//! ```
//!
//! The simulation is the test's own: targets, sensor, filter and scans come from
//! `tests/common/vo_demo.rs` (included below, shared with the tests), with the test's
//! seeds (`7000 + run`) and call order.
//!
//! With `--score`, our bare `GmPhdFilter` (the filter inside `exp_vo_demo.rs`'s tracker)
//! is run on the same sets and scored with Vo & Ma's extraction and the tests' OSPA
//! (c = 100 m, p = 1), with the median wall-clock time per scan (predict + update +
//! reduce), measured as the Python side does.
//!
//! JSON layout (positions in m, the state order of this crate's tests, [x, y]):
//! `{"seeds": [...], "steps": 100, "truth": [[[x, y], ...] per step],
//!   "runs": [{"seed": s, "scans": [[[x, y], ...] per step]}], "parameters": {...}}`.
//! The truth is the same in every run (the demo's targets move without process noise).

#[path = "../tests/common/mod.rs"]
mod common;

use common::vo_demo::{
    filter, scan, sensor, truth, BIRTH_POSITIONS, CLUTTER_RATE, DETECTION_PROBABILITY,
    MERGE_THRESHOLD, NOISE_STD, STEPS,
};
use gmphd::Measurement;
use nalgebra::DVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::json;

/// Monte-Carlo runs of `tests/exp_vo_demo.rs`, seeded `7000 + run` there.
const RUNS: u64 = 50;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.iter().find(|a| !a.starts_with("--")) else {
        eprintln!("usage: vo_demo_export OUT.json [--score]");
        std::process::exit(2);
    };
    let truth = truth();
    let sensor = sensor();
    // Exactly the test's loop: one generator per run, seeded 7000 + run, one scan per step.
    let seeds: Vec<u64> = (0..RUNS).map(|run| 7000 + run).collect();
    let runs: Vec<Vec<Vec<Measurement>>> = seeds
        .iter()
        .map(|&seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            truth
                .iter()
                .map(|objects| scan(objects, &sensor, &mut rng))
                .collect()
        })
        .collect();

    let xy = |v: &DVector<f64>| [v[0], v[1]];
    let document = json!({
        "source": "gmphd/tests/exp_vo_demo.rs (simulate_set of gmphd/tests/common/mod.rs)",
        "seeds": seeds,
        "steps": STEPS,
        "parameters": {
            "dt_s": 1.0, "sigma_v": 5.0, "p_survival": 0.99, "p_detection": DETECTION_PROBABILITY,
            "measurement_sigma": NOISE_STD, "clutter_rate": CLUTTER_RATE,
            "region": [[-1000.0, 1000.0], [-1000.0, 1000.0]],
            "birth_weight": 0.03, "birth_means_xy": BIRTH_POSITIONS,
            "birth_cov_diag": 100.0, "prune": 1e-5, "merge": MERGE_THRESHOLD, "max_components": 100,
            "ospa_c": 100.0, "ospa_p": 1.0
        },
        "truth": truth.iter().map(|step| step.iter().map(xy).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "runs": seeds.iter().zip(&runs).map(|(seed, scans)| json!({
            "seed": seed,
            "scans": scans.iter().map(|set| set.iter().map(|m| xy(&m.z)).collect::<Vec<_>>()).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    });
    std::fs::write(path, serde_json::to_string(&document).unwrap()).unwrap();
    let total: usize = runs.iter().flatten().map(Vec::len).sum();
    println!(
        "wrote {path}: {} runs x {STEPS} steps, {total} measurements; run 0 step 1 has {} (first {:?})",
        runs.len(),
        runs[0][0].len(),
        xy(&runs[0][0][0].z)
    );
    if args.iter().any(|a| a == "--score") {
        common::bare_filter::print_scores(&truth, &runs, &sensor, filter);
    }
}
