//! The covariance each published TDOA carries: the descriptor's noise for a frame's strongest peak,
//! more for a weaker one (`frontends::mic::relative_variances`, `noise_by_peak_height`).

/// How a microphone pair's TDOAs are given their covariances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TdoaNoise {
    /// The descriptor's TDOA noise standard deviation, seconds.
    noise_std: f64,
    /// Whether weaker peaks get a larger variance (the front end's `noise_by_peak_height`).
    by_peak_height: bool,
}

impl TdoaNoise {
    /// Covariances from the descriptor's `noise_std` (s), scaled by peak height when `by_peak_height`.
    pub fn new(noise_std: f64, by_peak_height: bool) -> Self {
        Self {
            noise_std,
            by_peak_height,
        }
    }

    /// The 1 × 1 covariances of a frame's TDOAs from their variances relative to its strongest peak;
    /// `None` (the descriptor's noise for every TDOA) when scaling is off or changes nothing.
    pub fn covariances(&self, relative_variances: &[f64]) -> Option<Vec<Vec<Vec<f64>>>> {
        if !self.by_peak_height || relative_variances.iter().all(|&r| r == 1.0) {
            return None;
        }
        let variance = self.noise_std * self.noise_std;
        Some(
            relative_variances
                .iter()
                .map(|r| vec![vec![variance * r]])
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_weaker_peak_gets_a_wider_variance_and_the_strongest_the_descriptors() {
        let noise = TdoaNoise::new(6.25e-5, true);
        let covariances = noise.covariances(&[1.0, 3.0]).unwrap();
        assert_eq!(covariances[0], vec![vec![6.25e-5 * 6.25e-5]]);
        assert_eq!(covariances[1], vec![vec![3.0 * 6.25e-5 * 6.25e-5]]);
    }

    #[test]
    fn nothing_to_scale_sends_the_descriptors_noise() {
        assert_eq!(TdoaNoise::new(6.25e-5, true).covariances(&[1.0]), None);
        assert_eq!(TdoaNoise::new(6.25e-5, true).covariances(&[]), None);
        assert_eq!(
            TdoaNoise::new(6.25e-5, false).covariances(&[1.0, 2.0]),
            None
        );
    }
}
