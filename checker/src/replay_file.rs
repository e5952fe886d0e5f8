//! One replay file from several agents' outputs and the truth, as `fusion-server replay` reads it.

use protocol::{ReplayLine, TruthSet};

/// The truth sets and every agent's replay lines as one JSON Lines replay file, in stamp order.
///
/// A line is placed by the stamp of its agent's next measurement set at or after it, so that each
/// agent's own lines keep their order (a refined descriptor stays before the set that follows it);
/// at equal stamps the truth goes first.
pub fn replay_file(
    truth: impl IntoIterator<Item = TruthSet>,
    agents: Vec<Vec<ReplayLine>>,
) -> Vec<u8> {
    let mut keyed: Vec<(f64, usize, ReplayLine)> = truth
        .into_iter()
        .map(|truth| (truth.stamp, 0, ReplayLine::Truth(truth)))
        .collect();
    for lines in agents {
        // Walked backwards, so that each line is keyed by the stamp of the set at or after it; the
        // second key, larger for later lines, keeps the agent's order among equal stamps.
        let mut next_stamp = f64::INFINITY;
        for (from_end, line) in lines.into_iter().rev().enumerate() {
            if let ReplayLine::Measurements(set) = &line {
                next_stamp = set.stamp;
            }
            keyed.push((next_stamp, usize::MAX - from_end, line));
        }
    }
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut out = Vec::new();
    for (_, _, line) in keyed {
        serde_json::to_writer(&mut out, &line).expect("a replay line serialises");
        out.push(b'\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{MeasurementSet, SensorId, PROTOCOL_VERSION};

    fn set(sensor: &str, stamp: f64) -> ReplayLine {
        ReplayLine::Measurements(MeasurementSet::new(
            SensorId::new(sensor).unwrap(),
            0,
            stamp,
            Vec::new(),
        ))
    }

    fn stamps(file: &[u8]) -> Vec<(String, f64)> {
        std::str::from_utf8(file)
            .unwrap()
            .lines()
            .map(|line| match serde_json::from_str(line).unwrap() {
                ReplayLine::Measurements(set) => (set.sensor.to_string(), set.stamp),
                ReplayLine::Truth(truth) => ("truth".into(), truth.stamp),
                _ => ("other".into(), f64::NAN),
            })
            .collect()
    }

    #[test]
    fn lines_are_in_stamp_order_with_the_truth_first_at_a_tie() {
        let truth = [1.0, 2.0].map(|stamp| TruthSet {
            version: PROTOCOL_VERSION,
            stamp,
            objects: Vec::new(),
        });
        let agents = vec![
            vec![set("a", 1.0), set("a", 2.5)],
            vec![set("b", 0.5), set("b", 2.0)],
        ];
        let order = stamps(&replay_file(truth, agents));
        let names: Vec<_> = order.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["b", "truth", "a", "truth", "b", "a"]);
    }
}
