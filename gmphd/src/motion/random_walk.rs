//! Random walk of the position alone (Pham 5.5: speakers, A = I).

use nalgebra::{DMatrix, DVector, Vector3};

use super::{check_dt, check_gaussian_dims, check_noise, check_spatial_dims, padded, MotionModel};
use crate::error::FilterError;
use crate::linalg::symmetrize;

/// State [p (dims)], p' = p + noise with Q(dt) = σ² dt I (σ in m per √s), a
/// Brownian motion so that the spread grows consistently with elapsed time.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomWalk {
    dims: usize,
    noise_std: f64,
    fixed_height: f64,
}

impl RandomWalk {
    /// `dims` is 2 or 3; `noise_std` ≥ 0 in m/√s; `fixed_height` is the world z of
    /// a planar state (ignored for 3-D).
    pub fn new(dims: usize, noise_std: f64, fixed_height: f64) -> Result<Self, FilterError> {
        check_spatial_dims(dims)?;
        if !fixed_height.is_finite() {
            return Err(FilterError::NonFinite {
                what: "fixed height",
            });
        }
        Ok(Self {
            dims,
            noise_std: check_noise(noise_std, "random walk noise")?,
            fixed_height,
        })
    }
}

impl MotionModel for RandomWalk {
    fn state_dim(&self) -> usize {
        self.dims
    }

    fn position_dims(&self) -> usize {
        self.dims
    }

    fn position(&self, x: &DVector<f64>) -> Vector3<f64> {
        padded(x, 0, self.dims, self.fixed_height)
    }

    fn velocity(&self, _x: &DVector<f64>) -> Option<Vector3<f64>> {
        None
    }

    fn predict(
        &self,
        mean: &DVector<f64>,
        cov: &DMatrix<f64>,
        dt: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), FilterError> {
        check_dt(dt)?;
        check_gaussian_dims(mean, cov, self.dims)?;
        let noise = DMatrix::identity(self.dims, self.dims) * (self.noise_std.powi(2) * dt);
        Ok((mean.clone(), symmetrize(&(cov + noise))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_grows_linearly_with_time() {
        let model = RandomWalk::new(2, 0.1, 1.6).unwrap();
        let mean = DVector::from_vec(vec![1.0, 2.0]);
        let (m, p) = model.predict(&mean, &DMatrix::zeros(2, 2), 4.0).unwrap();
        assert_eq!(m, mean);
        assert!((p[(0, 0)] - 0.04).abs() < 1e-15 && p[(0, 1)] == 0.0);
        assert_eq!(model.position(&mean), Vector3::new(1.0, 2.0, 1.6));
        assert!(model.velocity(&mean).is_none());
    }
}
