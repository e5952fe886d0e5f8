//! Each track set scored against the truth set nearest in time.

use std::collections::BTreeMap;

use gmphd::metrics::{gospa, ospa, MetricParams};
use nalgebra::DVector;
use protocol::{TrackSet, TruthSet};

/// Accuracy of one track set against the truth nearest in time.
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

/// A truth set farther than this from a track set's stamp is not used to score it.
pub const TRUTH_TOLERANCE_S: f64 = 0.05;

/// Scores each track set against the truth set nearest in time (within [`TRUTH_TOLERANCE_S`]).
///
/// `truth` is keyed by the bits of each set's stamp (`stamp.to_bits()`), which for the finite,
/// non-negative stamps kept there orders the map by stamp. Track sets with no truth near enough
/// get no score.
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
    // Only finite, non-negative stamps order like their bits.
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

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{Site, Track, TruthObject, PROTOCOL_VERSION};

    fn tracks_at(stamp: f64, positions: &[[f64; 3]]) -> TrackSet {
        TrackSet {
            version: PROTOCOL_VERSION,
            site: Site::default(),
            seq: 0,
            stamp,
            expected_count: positions.len() as f64,
            tracks: positions
                .iter()
                .enumerate()
                .map(|(i, &position)| Track {
                    id: i as u64,
                    position,
                    velocity: None,
                    position_covariance: [[0.0; 3]; 3],
                    weight: 1.0,
                    first_seen: stamp,
                })
                .collect(),
        }
    }

    fn truth_at(stamp: f64, positions: &[[f64; 3]]) -> (u64, TruthSet) {
        let objects = positions
            .iter()
            .enumerate()
            .map(|(i, &position)| TruthObject {
                id: i as u64,
                position,
            })
            .collect();
        let set = TruthSet {
            version: PROTOCOL_VERSION,
            stamp,
            objects,
        };
        (stamp.to_bits(), set)
    }

    #[test]
    fn each_set_is_scored_against_the_nearest_truth_within_the_tolerance() {
        let truth = BTreeMap::from([
            truth_at(10.0, &[[0.0, 0.0, 1.0]]),
            truth_at(10.1, &[[0.0, 0.0, 1.0], [5.0, 0.0, 1.0]]),
        ]);
        let tracks = [
            // Nearest the first truth set: one track 0.3 m off.
            tracks_at(10.02, &[[0.3, 0.0, 1.0]]),
            // Nearest the second: one of two objects missed.
            tracks_at(10.09, &[[0.0, 0.0, 1.0]]),
            // Nothing within 50 ms.
            tracks_at(10.2, &[[0.0, 0.0, 1.0]]),
        ];
        let scores = score(&tracks, &truth).unwrap();
        assert_eq!(scores.len(), 2);
        assert_eq!(scores[0].stamp, 10.02);
        assert!((scores[0].ospa - 0.3).abs() < 1e-12);
        assert_eq!((scores[0].truth_count, scores[0].track_count), (1, 1));
        // A miss costs the cut-off (1 m) over the two objects; GOSPA charges c/2 per miss.
        assert!((scores[1].ospa - 0.5).abs() < 1e-12);
        assert!((scores[1].gospa - 0.5).abs() < 1e-12);
        assert_eq!((scores[1].truth_count, scores[1].track_count), (2, 1));
    }

    #[test]
    fn sets_stamped_before_the_epoch_or_not_at_all_get_no_score() {
        let truth = BTreeMap::from([truth_at(0.0, &[[0.0, 0.0, 1.0]])]);
        let tracks = [tracks_at(-0.01, &[]), tracks_at(f64::NAN, &[])];
        assert!(score(&tracks, &truth).unwrap().is_empty());
    }
}
