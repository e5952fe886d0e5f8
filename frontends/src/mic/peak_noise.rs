//! How far a weaker correlation peak's TDOA is to be trusted, relative to the frame's strongest.
//!
//! The TDOA of a correlation peak is only as good as the coherence behind it. Knapp & Carter ("The
//! generalized correlation method for estimation of time delay", IEEE Trans. ASSP 24(4), 1976, eq. 25)
//! bound the variance of a delay estimated from a band of coherence γ by a term that grows as
//! (1 − γ²)/γ², and the height of a normalised GCC peak is the coherence the correlation found at that
//! delay. A frame's weaker peaks are also the ones that are more often an echo, a sidelobe of the
//! stronger talker, or two paths merged into one maximum. So each peak's variance is the variance of
//! the frame's strongest peak (the descriptor's `noise_std`, what a pair's TDOA error is when it hears
//! one talker clearly) times the ratio of the bound at the two heights. The strongest peak keeps the
//! descriptor's noise exactly; a peak at 0.6 of a strongest of 0.4 gets about 3.1 times its variance.

use super::pipeline::TdoaPeak;

/// Heights are clamped to this range: a peak of 1 would have no error at all (and 0 an infinite one).
const HEIGHT_RANGE: (f64, f64) = (1e-3, 0.99);

/// Knapp & Carter's variance term (1 − γ²)/γ² at peak height `strength` (clamped to `HEIGHT_RANGE`).
fn variance_term(strength: f64) -> f64 {
    let gamma = if strength.is_nan() {
        HEIGHT_RANGE.0
    } else {
        strength.clamp(HEIGHT_RANGE.0, HEIGHT_RANGE.1)
    };
    (1.0 - gamma * gamma) / (gamma * gamma)
}

/// Each peak's TDOA variance relative to that of the frame's strongest peak (≥ 1 for every peak, 1
/// for the strongest); empty for no peaks.
pub fn relative_variances(peaks: &[TdoaPeak]) -> Vec<f64> {
    let strongest = peaks
        .iter()
        .map(|peak| peak.strength)
        .filter(|s| !s.is_nan())
        .fold(f64::NEG_INFINITY, f64::max);
    let reference = variance_term(strongest);
    peaks
        .iter()
        .map(|peak| (variance_term(peak.strength) / reference).max(1.0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peaks(strengths: &[f64]) -> Vec<TdoaPeak> {
        strengths
            .iter()
            .map(|&strength| TdoaPeak {
                tdoa: 0.0,
                strength,
            })
            .collect()
    }

    #[test]
    fn the_strongest_peak_keeps_the_descriptors_noise() {
        let factors = relative_variances(&peaks(&[0.4, 0.3, 0.24]));
        assert_eq!(factors[0], 1.0);
        // (1 − 0.09)/0.09 over (1 − 0.16)/0.16.
        assert!((factors[1] - (0.91 / 0.09) / (0.84 / 0.16)).abs() < 1e-12);
        assert!(factors[2] > factors[1]);
    }

    #[test]
    fn the_ratio_follows_the_bound_not_the_rank() {
        // Two nearly equal peaks are trusted nearly alike, whichever comes first.
        let factors = relative_variances(&peaks(&[0.35, 0.34]));
        assert!(factors[1] < 1.1, "{factors:?}");
        // The same relative height costs more beside a clearer strongest peak, which the bound trusts more.
        let clear = relative_variances(&peaks(&[0.8, 0.48]))[1];
        let murky = relative_variances(&peaks(&[0.2, 0.12]))[1];
        assert!(clear > murky, "clear {clear}, murky {murky}");
    }

    #[test]
    fn odd_heights_give_finite_factors_of_at_least_one() {
        for strengths in [
            vec![],
            vec![1.0, 0.0],
            vec![f64::NAN, 0.3],
            vec![2.0, -1.0, 0.5],
        ] {
            let factors = relative_variances(&peaks(&strengths));
            assert_eq!(factors.len(), strengths.len());
            assert!(
                factors.iter().all(|f| f.is_finite() && *f >= 1.0),
                "{factors:?}"
            );
        }
    }
}
