//! Nearly constant velocity with continuous white-noise acceleration.

use nalgebra::{DMatrix, DVector, Vector3};

use super::{check_dt, check_gaussian_dims, check_noise, check_spatial_dims, padded, MotionModel};
use crate::error::FilterError;
use crate::linalg::symmetrize_in_place;

/// State [p (dims), v (dims)], p' = p + dt v, v' = v, with per-axis process noise
/// Q(dt) = q · [[dt³/3, dt²/2], [dt²/2, dt]], q = accel_noise_std².
///
/// The continuous-time noise makes the model consistent for any sequence of time
/// steps: predicting over dt₁ then dt₂ gives the same result as over dt₁ + dt₂.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstantVelocity {
    dims: usize,
    accel_noise_std: f64,
    fixed_height: f64,
}

impl ConstantVelocity {
    /// `dims` is 2 (planar) or 3; `accel_noise_std` in m/s² per √s, ≥ 0.
    /// A planar state sits at height 0 unless [`ConstantVelocity::with_fixed_height`].
    pub fn new(dims: usize, accel_noise_std: f64) -> Result<Self, FilterError> {
        check_spatial_dims(dims)?;
        Ok(Self {
            dims,
            accel_noise_std: check_noise(accel_noise_std, "acceleration noise")?,
            fixed_height: 0.0,
        })
    }

    /// The height (world z) given to planar states.
    pub fn with_fixed_height(mut self, height: f64) -> Result<Self, FilterError> {
        if !height.is_finite() {
            return Err(FilterError::NonFinite {
                what: "fixed height",
            });
        }
        self.fixed_height = height;
        Ok(self)
    }

    /// Transition matrix F(dt).
    pub fn transition(&self, dt: f64) -> DMatrix<f64> {
        let d = self.dims;
        let mut f = DMatrix::identity(2 * d, 2 * d);
        for i in 0..d {
            f[(i, d + i)] = dt;
        }
        f
    }

    /// Process noise covariance Q(dt).
    pub fn process_noise(&self, dt: f64) -> DMatrix<f64> {
        let mut noise = DMatrix::zeros(2 * self.dims, 2 * self.dims);
        self.add_process_noise(&mut noise, dt);
        noise
    }

    /// Adds Q(dt) to `cov` in place.
    fn add_process_noise(&self, cov: &mut DMatrix<f64>, dt: f64) {
        let d = self.dims;
        let q = self.accel_noise_std * self.accel_noise_std;
        for i in 0..d {
            cov[(i, i)] += q * dt.powi(3) / 3.0;
            cov[(i, d + i)] += q * dt * dt / 2.0;
            cov[(d + i, i)] += q * dt * dt / 2.0;
            cov[(d + i, d + i)] += q * dt;
        }
    }
}

impl MotionModel for ConstantVelocity {
    fn state_dim(&self) -> usize {
        2 * self.dims
    }

    fn position_dims(&self) -> usize {
        self.dims
    }

    fn position(&self, x: &DVector<f64>) -> Vector3<f64> {
        padded(x, 0, self.dims, self.fixed_height)
    }

    fn velocity(&self, x: &DVector<f64>) -> Option<Vector3<f64>> {
        Some(padded(x, self.dims, self.dims, 0.0))
    }

    fn predict(
        &self,
        mean: &DVector<f64>,
        cov: &DMatrix<f64>,
        dt: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), FilterError> {
        check_dt(dt)?;
        check_gaussian_dims(mean, cov, self.state_dim())?;
        // F = [I dt·I; 0 I]: F P Fᵀ adds dt × the velocity rows to the position rows, then
        // dt × the velocity columns to the position columns — written out, so that a
        // prediction costs one copy of the mean and of the covariance and no products.
        let d = self.dims;
        let mut predicted_mean = mean.clone();
        let mut predicted_cov = cov.clone();
        for i in 0..d {
            predicted_mean[i] += dt * mean[d + i];
            for c in 0..2 * d {
                predicted_cov[(i, c)] += dt * predicted_cov[(d + i, c)];
            }
        }
        for j in 0..d {
            for r in 0..2 * d {
                predicted_cov[(r, j)] += dt * predicted_cov[(r, d + j)];
            }
        }
        self.add_process_noise(&mut predicted_cov, dt);
        symmetrize_in_place(&mut predicted_cov);
        Ok((predicted_mean, predicted_cov))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prediction_composes_over_split_steps() {
        let model = ConstantVelocity::new(2, 3.0).unwrap();
        let mean = DVector::from_vec(vec![1.0, 2.0, 3.0, -4.0]);
        let cov = DMatrix::identity(4, 4) * 2.0;
        let (m1, p1) = model.predict(&mean, &cov, 0.7).unwrap();
        let (m2, p2) = model.predict(&m1, &p1, 0.3).unwrap();
        let (m, p) = model.predict(&mean, &cov, 1.0).unwrap();
        assert!((m2 - &m).amax() < 1e-12 && (p2 - &p).amax() < 1e-12);
        assert!((m[0] - 4.0).abs() < 1e-12 && (m[1] + 2.0).abs() < 1e-12);
    }

    #[test]
    fn zero_step_is_identity_and_negative_is_rejected() {
        let model = ConstantVelocity::new(3, 1.0).unwrap();
        let mean = DVector::from_element(6, 1.5);
        let cov = DMatrix::identity(6, 6);
        let (m, p) = model.predict(&mean, &cov, 0.0).unwrap();
        assert_eq!(m, mean);
        assert_eq!(p, cov);
        assert!(matches!(
            model.predict(&mean, &cov, -0.1),
            Err(FilterError::NegativeTimeStep { .. })
        ));
        assert!(ConstantVelocity::new(4, 1.0).is_err());
    }

    #[test]
    fn planar_position_is_padded_with_the_fixed_height() {
        let model = ConstantVelocity::new(2, 1.0)
            .unwrap()
            .with_fixed_height(1.7)
            .unwrap();
        let x = DVector::from_vec(vec![1.0, 2.0, 3.0, 4.0]);
        assert_eq!(model.position(&x), Vector3::new(1.0, 2.0, 1.7));
        assert_eq!(model.velocity(&x), Some(Vector3::new(3.0, 4.0, 0.0)));
    }
}
