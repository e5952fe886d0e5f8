//! Direct position measurements (GPS-like, or a fused 3-D detector): linear.

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Vector3};

use super::{
    check_uniforms, diagonal_noise, invertible_input, Detection, HeightPrior, MeasurementModel,
    UpdateHints,
};
use serde::Serialize;

use crate::error::{invalid, FilterError};

/// Measures the first `dims` world coordinates of an object, z = p[..dims] + noise,
/// inside an axis-aligned region box (outside it the object is not detected).
///
/// A 2-D sensor does not see heights: its inverted points take the height of its
/// [`HeightPrior`] (by default the ground plane with a 10 m standard deviation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PositionSensor {
    dims: usize,
    noise_cov: DMatrix<f64>,
    region_min: Vec<f64>,
    region_max: Vec<f64>,
    detection: Detection,
    height_prior: HeightPrior,
}

impl PositionSensor {
    /// `noise_std`, `region_min` and `region_max` each have `dims` (2 or 3) entries.
    pub fn new(
        noise_std: &[f64],
        region_min: &[f64],
        region_max: &[f64],
        detection: Detection,
    ) -> Result<Self, FilterError> {
        let dims = noise_std.len();
        if dims != 2 && dims != 3 {
            return Err(invalid(
                "position sensor dimension",
                format!("{dims} noise entries given, expected 2 or 3"),
            ));
        }
        for (what, bound) in [("region min", region_min), ("region max", region_max)] {
            if bound.len() != dims {
                return Err(FilterError::DimensionMismatch {
                    what,
                    expected: dims,
                    found: bound.len(),
                });
            }
        }
        let ordered = region_min
            .iter()
            .zip(region_max)
            .all(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo < hi);
        if !ordered {
            return Err(invalid(
                "position sensor region",
                "every min must be finite and below its max",
            ));
        }
        Ok(Self {
            dims,
            noise_cov: diagonal_noise(noise_std)?,
            region_min: region_min.to_vec(),
            region_max: region_max.to_vec(),
            detection,
            height_prior: HeightPrior::default(),
        })
    }

    /// Sets the height given to points inverted from a 2-D sensor's measurements
    /// (ignored by a 3-D sensor, which measures the height).
    pub fn with_height_prior(mut self, height_prior: HeightPrior) -> Self {
        self.height_prior = height_prior;
        self
    }

    fn inside(&self, p: &Vector3<f64>) -> bool {
        (0..self.dims).all(|i| p[i] >= self.region_min[i] && p[i] <= self.region_max[i])
    }
}

impl MeasurementModel for PositionSensor {
    fn dim(&self) -> usize {
        self.dims
    }

    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        out.copy_from_slice(&p.as_slice()[..self.dims]);
    }

    fn noise_cov(&self) -> DMatrix<f64> {
        self.noise_cov.clone()
    }

    fn detection_probability(&self, p: &Vector3<f64>) -> f64 {
        if self.inside(p) {
            self.detection.probability
        } else {
            0.0
        }
    }

    fn clutter_rate(&self) -> f64 {
        self.detection.clutter_rate
    }

    fn clutter_density(&self) -> f64 {
        let volume: f64 = self
            .region_min
            .iter()
            .zip(&self.region_max)
            .map(|(lo, hi)| hi - lo)
            .product();
        1.0 / volume
    }

    /// Indexed by x. (Linear: nothing to remember of its projections.)
    fn update_hints(&self) -> UpdateHints {
        UpdateHints {
            index_dim: Some(0),
            projection_key: None,
        }
    }

    fn linear_position_dims(&self) -> Option<usize> {
        Some(self.dims)
    }

    fn invert_with_noise(
        &self,
        z: &DVector<f64>,
        noise: &DMatrix<f64>,
    ) -> Option<(Vector3<f64>, Matrix3<f64>)> {
        if !invertible_input(z, noise, self.dims) {
            return None;
        }
        // h is the identity on the measured coordinates, so J = I and the covariance is R.
        if self.dims == 3 {
            Some((
                Vector3::new(z[0], z[1], z[2]),
                Matrix3::from_fn(|r, c| noise[(r, c)]),
            ))
        } else {
            let cov_xy = Matrix2::from_fn(|r, c| noise[(r, c)]);
            Some(self.height_prior.complete(z[0], z[1], &cov_xy))
        }
    }

    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        check_uniforms(u, self.dims)?;
        Ok(DVector::from_iterator(
            self.dims,
            (0..self.dims)
                .map(|i| self.region_min[i] + u[i] * (self.region_max[i] - self.region_min[i])),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sensor() -> PositionSensor {
        PositionSensor::new(
            &[10.0, 10.0],
            &[-1000.0, -1000.0],
            &[1000.0, 1000.0],
            Detection::new(0.98, 60.0).unwrap(),
        )
        .unwrap()
    }

    #[test]
    fn measures_leading_coordinates_and_region() {
        let s = sensor();
        let p = Vector3::new(1.0, 2.0, 3.0);
        assert_eq!(s.measure(&p).as_slice(), &[1.0, 2.0]);
        assert_eq!(s.detection_probability(&p), 0.98);
        assert_eq!(
            s.detection_probability(&Vector3::new(2000.0, 0.0, 0.0)),
            0.0
        );
        assert!((s.clutter_intensity() - 60.0 / 4e6).abs() < 1e-15);
        let c = s.sample_clutter(&[0.0, 0.5]).unwrap();
        assert_eq!(c.as_slice(), &[-1000.0, 0.0]);
    }

    #[test]
    fn rejects_bad_configuration() {
        let d = Detection::new(0.9, 1.0).unwrap();
        assert!(PositionSensor::new(&[1.0], &[0.0], &[1.0], d).is_err());
        assert!(PositionSensor::new(&[1.0, -1.0], &[0.0, 0.0], &[1.0, 1.0], d).is_err());
        assert!(PositionSensor::new(&[1.0, 1.0], &[0.0, 2.0], &[1.0, 1.0], d).is_err());
        assert!(Detection::new(0.0, 1.0).is_err());
        assert!(Detection::new(0.5, -1.0).is_err());
        assert!(sensor().sample_clutter(&[0.5]).is_err());
    }
}
