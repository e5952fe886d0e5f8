//! Code shared by the integration tests: running the real binary and reading replay output.
// Each test binary uses a different part of this module.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::process::{Command, Output};

use protocol::{MeasurementSet, ReplayLine, SensorDescriptor};

/// A fixed scenario start, so that stamps (and so output bytes) do not depend on the wall clock.
pub const START: &str = "1763700000";

/// Runs `edge-agent` with `args` and returns its output (no Zenoh: every test passes `--output`).
pub fn edge_agent(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_edge-agent"))
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("the edge-agent binary runs")
}

/// Runs `edge-agent` with `args`, requires success and returns stdout.
pub fn edge_agent_ok(args: &[&str]) -> Vec<u8> {
    let output = edge_agent(args);
    assert!(
        output.status.success(),
        "edge-agent {args:?} failed ({}): {}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
}

/// A replay file split into its parts, after checking the rules of a well-formed one.
pub struct Replay {
    /// Descriptor lines, in order.
    pub descriptors: Vec<SensorDescriptor>,
    /// Descriptors announced after data (a front end's refined figures), in order.
    pub refined_descriptors: Vec<SensorDescriptor>,
    /// Measurement lines, in order.
    pub sets: Vec<MeasurementSet>,
    /// Number of truth lines.
    pub truth_lines: usize,
}

/// Parses replay bytes and checks: every line decodes and validates as a protocol `ReplayLine`; all
/// descriptors come first, except a known sensor's refined one; stamps never decrease; each sensor's `seq` runs 0, 1, 2, …; every set validates
/// against its sensor's descriptor.
pub fn check_replay(bytes: &[u8]) -> Replay {
    let text = std::str::from_utf8(bytes).expect("replay output is UTF-8");
    let mut replay = Replay {
        descriptors: Vec::new(),
        refined_descriptors: Vec::new(),
        sets: Vec::new(),
        truth_lines: 0,
    };
    let mut last_stamp = f64::NEG_INFINITY;
    let mut next_seq: BTreeMap<String, u64> = BTreeMap::new();
    for (number, line) in text.lines().enumerate() {
        let parsed: ReplayLine = serde_json::from_str(line)
            .unwrap_or_else(|e| panic!("line {} does not decode: {e}: {line}", number + 1));
        parsed
            .validate()
            .unwrap_or_else(|e| panic!("line {} is invalid: {e}", number + 1));
        if let Some(stamp) = parsed.stamp() {
            assert!(
                stamp >= last_stamp,
                "line {}: stamp {stamp} before {last_stamp}",
                number + 1
            );
            last_stamp = stamp;
        }
        match parsed {
            ReplayLine::Descriptor(d) => {
                // After data, only a known sensor's refined descriptor may follow; its numbering goes on.
                if replay.sets.is_empty() && replay.truth_lines == 0 {
                    next_seq.insert(d.sensor.to_string(), 0);
                    replay.descriptors.push(d);
                } else {
                    assert!(
                        next_seq.contains_key(d.sensor.as_str()),
                        "line {}: descriptor of a new sensor after data",
                        number + 1
                    );
                    replay.refined_descriptors.push(d);
                }
            }
            ReplayLine::Measurements(set) => {
                let descriptor = replay
                    .descriptors
                    .iter()
                    .find(|d| d.sensor == set.sensor)
                    .unwrap_or_else(|| panic!("line {}: set of an unknown sensor", number + 1));
                set.validate_against(descriptor)
                    .unwrap_or_else(|e| panic!("line {}: {e}", number + 1));
                let expected = next_seq.get_mut(set.sensor.as_str()).expect("known sensor");
                assert_eq!(
                    set.seq,
                    *expected,
                    "line {}: seq not consecutive",
                    number + 1
                );
                *expected += 1;
                replay.sets.push(set);
            }
            ReplayLine::Truth(_) => replay.truth_lines += 1,
        }
    }
    replay
}
