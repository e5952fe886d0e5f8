//! Nearly constant velocity with continuous white-noise acceleration.

use nalgebra::{Const, DMatrix, DVector, MatrixViewMut, Vector3};

use super::{check_dt, check_gaussian_dims, check_noise, check_spatial_dims, padded, MotionModel};
use crate::error::FilterError;
use crate::gaussian::Gaussian;
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
        add_process_noise(noise.as_mut_slice(), self.dims, self.noise_terms(dt));
        noise
    }

    /// Q(dt)'s entries for each axis: position variance, position–velocity covariance,
    /// velocity variance (white acceleration noise).
    fn noise_terms(&self, dt: f64) -> [f64; 3] {
        let q = self.accel_noise_std * self.accel_noise_std;
        [q * dt.powi(3) / 3.0, q * dt * dt / 2.0, q * dt]
    }

    /// F x and F P Fᵀ + Q in place, on a state of the right size (mean and column-major
    /// covariance as slices), with `noise` = [`Self::noise_terms`] of `dt`.
    fn predict_unchecked(&self, mean: &mut [f64], cov: &mut [f64], dt: f64, noise: [f64; 3]) {
        // Compiled for each spatial size, so that the loops have known lengths.
        match self.dims {
            2 => predict_sized::<2, 4, 16>(mean, cov, dt, noise),
            3 => predict_sized::<3, 6, 36>(mean, cov, dt, noise),
            _ => unreachable!("ConstantVelocity::new accepts 2 or 3 spatial dimensions"),
        }
    }
}

/// [`ConstantVelocity::predict_unchecked`] for D spatial dimensions, N = 2D states and
/// N² covariance entries: F adds dt times each velocity to its position, so F P Fᵀ is P
/// with dt times the velocity rows added to the position rows, then the same for the
/// columns; then Q is added and round-off asymmetry averaged away.
fn predict_sized<const D: usize, const N: usize, const NN: usize>(
    mean: &mut [f64],
    cov: &mut [f64],
    dt: f64,
    noise: [f64; 3],
) {
    advance_mean::<D>(mean, dt);
    let cov: &mut [f64; NN] = cov.try_into().expect("an N × N covariance");
    for c in 0..N {
        for i in 0..D {
            cov[i + c * N] += dt * cov[D + i + c * N];
        }
    }
    for j in 0..D {
        for r in 0..N {
            cov[r + j * N] += dt * cov[r + (D + j) * N];
        }
    }
    add_process_noise(cov, D, noise);
    symmetrize_in_place(&mut MatrixViewMut::<f64, Const<N>, Const<N>>::from_slice(
        cov,
    ));
}

/// F x in place for D spatial dimensions: dt times each velocity added to its position.
#[inline]
fn advance_mean<const D: usize>(mean: &mut [f64], dt: f64) {
    let (positions, velocities) = mean.split_at_mut(D);
    for (x, v) in positions.iter_mut().zip(&velocities[..D]) {
        *x += dt * v;
    }
}

/// Adds Q's per-axis `[position, cross, velocity]` entries to the column-major covariance
/// `cov` of a state with `d` positions and `d` velocities.
#[inline]
fn add_process_noise(cov: &mut [f64], d: usize, [position, cross, velocity]: [f64; 3]) {
    let n = 2 * d;
    for i in 0..d {
        cov[i + i * n] += position;
        cov[i + (d + i) * n] += cross;
        cov[d + i + i * n] += cross;
        cov[d + i + (d + i) * n] += velocity;
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
        let (mut mean, mut cov) = (mean.clone(), cov.clone());
        let noise = self.noise_terms(dt);
        self.predict_unchecked(mean.as_mut_slice(), cov.as_mut_slice(), dt, noise);
        Ok((mean, cov))
    }

    fn predict_all_in_place(
        &self,
        components: &mut [Gaussian],
        dt: f64,
    ) -> Result<(), FilterError> {
        // Every way to fail is checked before the first component changes.
        check_dt(dt)?;
        for component in components.iter() {
            check_gaussian_dims(&component.mean, &component.cov, self.state_dim())?;
        }
        let noise = self.noise_terms(dt);
        for component in components {
            self.predict_unchecked(
                component.mean.as_mut_slice(),
                component.cov.as_mut_slice(),
                dt,
                noise,
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;

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

    /// The in-place prediction is F P Fᵀ + Q (and F x) to round-off, and the same, bit for
    /// bit, as `predict` (which the trait's default is built on).
    #[test]
    fn in_place_prediction_is_the_kalman_prediction() {
        let model = ConstantVelocity::new(3, 0.7).unwrap();
        let root = DMatrix::from_fn(6, 6, |r, c| ((r * 7 + c * 3) % 5) as f64 * 0.3 + 0.1);
        let cov = &root * root.transpose() + DMatrix::identity(6, 6);
        let mean = DVector::from_fn(6, |i, _| i as f64 - 2.5);
        let dt = 0.04;
        let mut in_place = vec![Gaussian::new(0.3, mean.clone(), cov.clone(), Label(4))];
        model.predict_all_in_place(&mut in_place, dt).unwrap();
        let (by_predict_mean, by_predict_cov) = model.predict(&mean, &cov, dt).unwrap();
        assert_eq!(in_place[0].mean, by_predict_mean);
        assert_eq!(in_place[0].cov, by_predict_cov);
        let f = model.transition(dt);
        let expected_cov = &f * &cov * f.transpose() + model.process_noise(dt);
        assert!((&f * &mean - &in_place[0].mean).amax() < 1e-12);
        assert!((expected_cov - &in_place[0].cov).amax() < 1e-12);
        assert_eq!((in_place[0].weight, in_place[0].label), (0.3, Label(4)));
    }
}
