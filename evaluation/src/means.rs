//! Means of the scores over a run, from a stamp on (to leave out the time tracks take to form).

use crate::score::Score;

/// Mean OSPA of the scores stamped at or after `from`, with how many there were; `None` when
/// there were none. `f64::NEG_INFINITY` takes the whole run.
pub fn mean_ospa(scores: &[Score], from: f64) -> Option<(f64, usize)> {
    mean_from(scores, from, |s| s.ospa)
}

/// Mean GOSPA of the scores stamped at or after `from`, with how many there were; `None` when
/// there were none.
pub fn mean_gospa(scores: &[Score], from: f64) -> Option<(f64, usize)> {
    mean_from(scores, from, |s| s.gospa)
}

fn mean_from(scores: &[Score], from: f64, metric: fn(&Score) -> f64) -> Option<(f64, usize)> {
    // Summed in stamp order from zero, so the figures printed by every program agree to the bit.
    let (sum, n) = scores
        .iter()
        .filter(|s| s.stamp >= from)
        .map(metric)
        .fold((0.0, 0usize), |(sum, n), v| (sum + v, n + 1));
    (n > 0).then(|| (sum / n as f64, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scored(stamp: f64, ospa: f64, gospa: f64) -> Score {
        Score {
            stamp,
            ospa,
            gospa,
            truth_count: 1,
            track_count: 1,
        }
    }

    #[test]
    fn means_count_only_the_scores_from_the_stamp_on() {
        let scores = [
            scored(1.0, 0.9, 1.8),
            scored(2.0, 0.2, 0.4),
            scored(3.0, 0.4, 0.6),
        ];
        assert_eq!(mean_ospa(&scores, 2.0), Some((0.30000000000000004, 2)));
        assert_eq!(mean_gospa(&scores, 2.5), Some((0.6, 1)));
        let (all, n) = mean_ospa(&scores, f64::NEG_INFINITY).unwrap();
        assert_eq!(n, 3);
        assert!((all - 0.5).abs() < 1e-12);
        assert_eq!(mean_ospa(&scores, 4.0), None);
        assert_eq!(mean_gospa(&[], f64::NEG_INFINITY), None);
    }
}
