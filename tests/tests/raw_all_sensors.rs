//! All seven sensors of the default room from raw signals, end to end and deterministic: every
//! sensor's signal rendered from the truth (`checker::raw_inputs`, as `fusion-demo --raw` and the
//! compose raw profile render it: both cameras' frames, the four microphone pairs' reverberant
//! audio, the ceiling LIDAR's scans), each through its real `edge-agent` front end writing replay
//! lines (with the descriptor it announces), all merged in stamp order with the truth and fused by
//! the server's replay with its default configuration: mean 3-D OSPA (c = 1 m) and the share of
//! track sets with the right count once everybody is in, for several seeds.

use std::path::Path;

use checker::processes::binary;
use checker::raw_inputs::{agent_output_command, render_sensors, RawSensor};
use checker::replay_file::replay_file;
use fusion_server::config::ServerConfig;
use fusion_server::replay::replay;
use protocol::ReplayLine;
use simulator::{truth_set, Scenario};

/// Unix time of scenario time 0.
const START: f64 = 1_763_700_000.0;
/// Seconds rendered.
const DURATION_S: f64 = 20.0;
/// Scores count from here: every person has walked in (the last at 4.5 s) and been confirmed.
const SCORED_FROM_S: f64 = 6.0;

/// Mean OSPA, share of right counts and the number of scored track sets of one seed.
struct Figures {
    ospa: f64,
    right_count: f64,
    scored: usize,
}

/// One sensor's replay lines, as its agent wrote them.
fn agent_lines(sensor: &RawSensor, dir: &Path) -> Vec<ReplayLine> {
    let output = dir.join(format!("{}.jsonl", sensor.sensor));
    let status = agent_output_command(&binary("edge-agent").unwrap(), sensor, START, &output)
        .env("RUST_LOG", "warn")
        .status()
        .expect("edge-agent runs");
    assert!(status.success(), "edge-agent failed for {}", sensor.sensor);
    std::fs::read_to_string(&output)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect()
}

/// Every agent's lines and the truth in one replay file, in stamp order.
fn replay_input(scenario: &Scenario, seed: u64, agents: Vec<Vec<ReplayLine>>) -> Vec<u8> {
    let truth = (0..scenario.truth_count(DURATION_S)).map(|k| truth_set(scenario, seed, START, k));
    replay_file(truth, agents)
}

fn figures(seed: u64) -> Figures {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    let dir = tempfile::tempdir().unwrap();
    let sensors =
        render_sensors(&scenario, seed, DURATION_S, dir.path(), "raw_all_sensors").unwrap();
    // Two agents at a time: one per core.
    let agents: Vec<Vec<ReplayLine>> = sensors
        .chunks(2)
        .flat_map(|pair| {
            std::thread::scope(|scope| {
                let jobs: Vec<_> = pair
                    .iter()
                    .map(|sensor| scope.spawn(|| agent_lines(sensor, dir.path())))
                    .collect();
                jobs.into_iter()
                    .map(|j| j.join().unwrap())
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    let input = replay_input(&scenario, seed, agents);
    let report = replay(ServerConfig::default(), input.as_slice(), std::io::sink()).unwrap();
    assert_eq!(report.bad_lines, 0);
    let from = START + SCORED_FROM_S;
    let scored: Vec<_> = report.scores.iter().filter(|s| s.stamp >= from).collect();
    let right = scored
        .iter()
        .filter(|s| s.truth_count == s.track_count)
        .count();
    Figures {
        ospa: report.mean_ospa_from(from).unwrap(),
        right_count: right as f64 / scored.len().max(1) as f64,
        scored: scored.len(),
    }
}

#[test]
fn all_seven_sensors_track_the_room_from_raw_signals() {
    let mut worst_ospa: f64 = 0.0;
    let mut worst_count: f64 = 1.0;
    for seed in [1, 2] {
        let f = figures(seed);
        println!(
            "seed {seed}: mean OSPA {:.3} m, right count {:.1} % of {} track sets from {SCORED_FROM_S} s to {DURATION_S} s",
            f.ospa,
            100.0 * f.right_count,
            f.scored
        );
        worst_ospa = worst_ospa.max(f.ospa);
        worst_count = worst_count.min(f.right_count);
    }
    println!(
        "worst seed: mean OSPA {worst_ospa:.3} m, right count {:.1} %",
        100.0 * worst_count
    );
    // The goal is 0.05 m and 95 %. Today's figures (seeds 1 and 2): 0.021 and 0.036 m, 99.9 and 100 %, the
    // cameras' image tracker and the LIDAR carrying most of it (0.038 and 0.050 m while the LIDAR's points
    // were published as exact as its sensor, `objects.centre_std` 0); floors with a margin for other hosts.
    assert!(worst_ospa <= 0.08, "mean OSPA {worst_ospa:.3} m");
    assert!(
        worst_count >= 0.9,
        "right count {:.1} %",
        100.0 * worst_count
    );
}
