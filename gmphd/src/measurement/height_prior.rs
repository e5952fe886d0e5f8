//! The height given to a point inverted from a sensor that does not measure height.

use nalgebra::{Matrix2, Matrix3, Vector3};

use serde::Serialize;

use super::positive;
use crate::error::{invalid, FilterError};

/// Standard deviation (m) of [`HeightPrior::default`]: large, so that a 3-D state born
/// from a planar measurement lets the other sensors decide its height.
pub const DEFAULT_HEIGHT_STD: f64 = 10.0;

/// What is known about the height of an object seen by a planar sensor (a 2-D
/// [`PositionSensor`](super::PositionSensor), a [`BearingRange`](super::BearingRange)):
/// a point inverted from its measurement gets `height` with standard deviation `std`,
/// independent of the measured horizontal position. Irrelevant to 2-D states, which
/// keep only the horizontal part.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HeightPrior {
    height: f64,
    std: f64,
}

impl Default for HeightPrior {
    /// The ground plane, z = 0, with [`DEFAULT_HEIGHT_STD`].
    fn default() -> Self {
        Self {
            height: 0.0,
            std: DEFAULT_HEIGHT_STD,
        }
    }
}

impl HeightPrior {
    /// A prior of mean `height` (m, finite) and standard deviation `std` (m, > 0).
    pub fn new(height: f64, std: f64) -> Result<Self, FilterError> {
        if !height.is_finite() {
            return Err(invalid(
                "height prior",
                format!("height {height} is not finite"),
            ));
        }
        Ok(Self {
            height,
            std: positive(std, "height prior standard deviation")?,
        })
    }

    /// Mean height, metres.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Standard deviation of the height, metres.
    pub fn std(&self) -> f64 {
        self.std
    }

    /// The 3-D point and covariance of the horizontal position (`x`, `y`) with covariance `cov_xy`.
    pub(crate) fn complete(
        &self,
        x: f64,
        y: f64,
        cov_xy: &Matrix2<f64>,
    ) -> (Vector3<f64>, Matrix3<f64>) {
        let mut cov = Matrix3::zeros();
        cov.fixed_view_mut::<2, 2>(0, 0).copy_from(cov_xy);
        cov[(2, 2)] = self.std * self.std;
        (Vector3::new(x, y, self.height), cov)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn completes_a_planar_point_and_rejects_bad_priors() {
        let prior = HeightPrior::new(1.5, 0.5).unwrap();
        let (p, cov) = prior.complete(1.0, 2.0, &Matrix2::new(1.0, 0.1, 0.1, 2.0));
        assert_eq!(p, Vector3::new(1.0, 2.0, 1.5));
        assert_eq!(cov[(0, 1)], 0.1);
        assert_eq!(cov[(2, 2)], 0.25);
        assert_eq!(cov[(0, 2)], 0.0);
        assert!(HeightPrior::new(f64::NAN, 1.0).is_err());
        assert!(HeightPrior::new(0.0, 0.0).is_err());
        assert_eq!(HeightPrior::default().std(), DEFAULT_HEIGHT_STD);
    }
}
