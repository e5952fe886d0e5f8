//! `fusion-server replay`: the live pipeline run offline over a replay file (PROTOCOL.md "Replay
//! files"), deterministic: the engine's clock is the largest stamp read so far, never the wall clock.

use std::collections::BTreeMap;
use std::io::{BufRead, Write};

use evaluation::{mean_gospa, mean_ospa, score, Score};
use protocol::{ReplayLine, TrackSet, TruthSet};

use crate::config::ServerConfig;
use crate::engine::Engine;

/// What a replay produced besides its output lines.
#[derive(Debug, Default)]
pub struct ReplayReport {
    /// Input lines read.
    pub lines: usize,
    /// Input lines that could not be used (each also logged).
    pub bad_lines: usize,
    /// Output track sets written.
    pub outputs: usize,
    /// One score per output track set that has a truth within [`evaluation::TRUTH_TOLERANCE_S`].
    pub scores: Vec<Score>,
    /// The output track sets (kept for plotting).
    pub tracks: Vec<TrackSet>,
    /// The truth sets read.
    pub truth: Vec<TruthSet>,
}

impl ReplayReport {
    /// Mean OSPA over all scored track sets.
    pub fn mean_ospa(&self) -> Option<f64> {
        self.mean_ospa_from(f64::NEG_INFINITY)
    }

    /// Mean GOSPA over all scored track sets.
    pub fn mean_gospa(&self) -> Option<f64> {
        mean_gospa(&self.scores, f64::NEG_INFINITY).map(|(mean, _)| mean)
    }

    /// Mean OSPA over scored track sets stamped at or after `from`.
    pub fn mean_ospa_from(&self, from: f64) -> Option<f64> {
        mean_ospa(&self.scores, from).map(|(mean, _)| mean)
    }
}

/// Runs the pipeline over `input`, writing one `TrackSet` JSON line per processed set to `output`.
///
/// Each line is the final answer for its set: what processing every set in stamp order gives,
/// whatever order the file lists them in (within `ingest.max_lateness_s`), numbered in stamp
/// order.
pub fn replay(
    config: ServerConfig,
    input: impl BufRead,
    mut output: impl Write,
) -> anyhow::Result<ReplayReport> {
    let mut engine = Engine::new(config, 0.0, false)?;
    let mut report = ReplayReport::default();
    let mut clock = 0.0_f64;
    let mut truth: BTreeMap<u64, TruthSet> = BTreeMap::new();
    let mut emitted = Vec::new();
    for (index, line) in input.lines().enumerate() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        report.lines += 1;
        let parsed: ReplayLine = match serde_json::from_str(&line) {
            Ok(parsed) => parsed,
            Err(e) => {
                report.bad_lines += 1;
                tracing::warn!(line = index + 1, error = %e, "replay line skipped");
                continue;
            }
        };
        match parsed {
            ReplayLine::Descriptor(descriptor) => {
                if let Err(e) = engine.learn_descriptor(descriptor, false) {
                    report.bad_lines += 1;
                    tracing::warn!(line = index + 1, error = %e, "descriptor skipped");
                }
            }
            ReplayLine::Measurements(set) => {
                if set.stamp.is_finite() {
                    clock = clock.max(set.stamp);
                }
                if let Err(e) = engine.admit_decoded(None, set, clock) {
                    report.bad_lines += 1;
                    tracing::warn!(line = index + 1, error = %e, "set skipped");
                }
                engine.step(clock);
                emitted.extend(engine.take_settled());
            }
            ReplayLine::Truth(set) => {
                if set.stamp.is_finite() && set.stamp >= 0.0 {
                    truth.insert(set.stamp.to_bits(), set);
                }
            }
        }
        for tracks in emitted.drain(..) {
            write_line(&mut output, &tracks)?;
            report.outputs += 1;
            report.tracks.push(tracks);
        }
    }
    engine.flush(clock);
    for tracks in engine.settle_all() {
        write_line(&mut output, &tracks)?;
        report.outputs += 1;
        report.tracks.push(tracks);
    }
    output.flush()?;
    report.scores = score(&report.tracks, &truth)?;
    report.truth = truth.into_values().collect();
    Ok(report)
}

fn write_line(output: &mut impl Write, tracks: &TrackSet) -> anyhow::Result<()> {
    serde_json::to_writer(&mut *output, tracks)?;
    output.write_all(b"\n")?;
    Ok(())
}
