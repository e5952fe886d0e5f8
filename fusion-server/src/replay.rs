//! `fusion-server replay`: the live pipeline run offline over a replay file (PROTOCOL.md "Replay
//! files"), deterministic: the engine's clock is the largest stamp read so far, never the wall clock.

use std::collections::BTreeMap;
use std::io::{BufRead, Write};

use gmphd::metrics::{gospa, ospa, MetricParams};
use nalgebra::DVector;
use protocol::{ReplayLine, TrackSet, TruthSet};

use crate::config::ServerConfig;
use crate::engine::Engine;

/// Accuracy of one output track set against the truth nearest in time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Score {
    /// Stamp of the track set.
    pub stamp: f64,
    /// OSPA distance (c = 1 m, p = 1).
    pub ospa: f64,
    /// GOSPA distance (c = 1 m, p = 1, α = 2).
    pub gospa: f64,
    /// Number of true objects.
    pub truth_count: usize,
    /// Number of tracks.
    pub track_count: usize,
}

/// What a replay produced besides its output lines.
#[derive(Debug, Default)]
pub struct ReplayReport {
    /// Input lines read.
    pub lines: usize,
    /// Input lines that could not be used (each also logged).
    pub bad_lines: usize,
    /// Output track sets written.
    pub outputs: usize,
    /// One score per output track set that has a truth within `TRUTH_TOLERANCE_S`.
    pub scores: Vec<Score>,
    /// The output track sets (kept for plotting).
    pub tracks: Vec<TrackSet>,
    /// The truth sets read.
    pub truth: Vec<TruthSet>,
}

/// A truth line farther than this from a track set's stamp is not used to score it.
pub const TRUTH_TOLERANCE_S: f64 = 0.05;

impl ReplayReport {
    /// Mean OSPA over all scored track sets.
    pub fn mean_ospa(&self) -> Option<f64> {
        mean(self.scores.iter().map(|s| s.ospa))
    }

    /// Mean GOSPA over all scored track sets.
    pub fn mean_gospa(&self) -> Option<f64> {
        mean(self.scores.iter().map(|s| s.gospa))
    }

    /// Mean OSPA over scored track sets stamped at or after `from`.
    pub fn mean_ospa_from(&self, from: f64) -> Option<f64> {
        mean(
            self.scores
                .iter()
                .filter(|s| s.stamp >= from)
                .map(|s| s.ospa),
        )
    }
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
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

/// Scores each track set against the truth set nearest in time (within `TRUTH_TOLERANCE_S`).
pub fn score(tracks: &[TrackSet], truth: &BTreeMap<u64, TruthSet>) -> anyhow::Result<Vec<Score>> {
    let params = MetricParams::new(1.0, 1.0)?;
    let mut scores = Vec::new();
    for set in tracks {
        let Some(nearest) = nearest_truth(truth, set.stamp) else {
            continue;
        };
        let truth_points: Vec<DVector<f64>> = nearest
            .objects
            .iter()
            .map(|o| DVector::from_column_slice(&o.position))
            .collect();
        let track_points: Vec<DVector<f64>> = set
            .tracks
            .iter()
            .map(|t| DVector::from_column_slice(&t.position))
            .collect();
        scores.push(Score {
            stamp: set.stamp,
            ospa: ospa(&truth_points, &track_points, params)?.distance,
            gospa: gospa(&truth_points, &track_points, params)?.distance,
            truth_count: truth_points.len(),
            track_count: track_points.len(),
        });
    }
    Ok(scores)
}

fn nearest_truth(truth: &BTreeMap<u64, TruthSet>, stamp: f64) -> Option<&TruthSet> {
    if !(stamp.is_finite() && stamp >= 0.0) {
        return None;
    }
    let key = stamp.to_bits();
    let before = truth.range(..=key).next_back().map(|(_, t)| t);
    let after = truth.range(key..).next().map(|(_, t)| t);
    [before, after]
        .into_iter()
        .flatten()
        .min_by(|a, b| (a.stamp - stamp).abs().total_cmp(&(b.stamp - stamp).abs()))
        .filter(|t| (t.stamp - stamp).abs() <= TRUTH_TOLERANCE_S)
}
