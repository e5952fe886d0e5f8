//! One predicted component prepared for the update: its predicted measurement and the
//! Cholesky factor of its innovation covariance (needed for every pair), and — only for
//! components that get a detection child — the gain and posterior covariance, which do
//! not depend on the measurement and are therefore computed once and shared by all of
//! the component's children.

use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

use super::unscented::{self, UnscentedScratch};
use super::UpdateStep;
use crate::error::FilterError;
use crate::gaussian::Gaussian;
use crate::linalg::{log_determinant, nearest_spd, robust_cholesky};

/// ln 2π.
const LN_TAU: f64 = 1.837_877_066_409_345_5;

/// A predicted component seen in measurement space (noise not included).
pub(super) struct Projection {
    predicted_z: DVector<f64>,
    z_cov: DMatrix<f64>,
    cross_cov: DMatrix<f64>,
    /// True when the sensor reads the first d state components directly (H = [I_d 0]);
    /// then the exact Kalman (Joseph form) covariance update is used.
    linear: bool,
}

impl Projection {
    /// H = [I_d 0]: the projection is a slice of the component.
    pub(super) fn linear(component: &Gaussian, dims: usize) -> Self {
        Self {
            predicted_z: component.mean.rows(0, dims).into_owned(),
            z_cov: component.cov.view((0, 0), (dims, dims)).into_owned(),
            cross_cov: component.cov.columns(0, dims).into_owned(),
            linear: true,
        }
    }

    /// The unscented transform of the component through position and measurement.
    pub(super) fn unscented(
        component: &Gaussian,
        step: &UpdateStep<'_>,
        scratch: &mut UnscentedScratch,
    ) -> Result<Self, FilterError> {
        let out = unscented::project(component, step, scratch)?;
        Ok(Self {
            predicted_z: out.mean,
            z_cov: out.cov,
            cross_cov: out.cross_cov,
            linear: false,
        })
    }

    /// The predicted measurement ẑ.
    pub(super) fn predicted_z(&self) -> &[f64] {
        self.predicted_z.as_slice()
    }

    /// Variance of the i-th predicted measurement entry (noise not included).
    pub(super) fn z_variance(&self, i: usize) -> f64 {
        self.z_cov[(i, i)]
    }
}

/// The innovation covariance S = H P Hᵀ + R of one component and noise, factored.
pub(super) struct Innovation {
    factor: Cholesky<f64, Dyn>,
    /// ½ (m ln 2π + ln det S): −log of the density's peak.
    log_peak_inverse: f64,
    /// √(γ S_ii): a residual entry beyond this puts the pair outside the gate γ, since
    /// rᵀ S⁻¹ r ≥ r_i² / S_ii (+∞ without a gate).
    half_width: Vec<f64>,
}

impl Innovation {
    /// Factors S = `z_cov` + `noise` for the gate `gate` (γ, possibly +∞).
    pub(super) fn new(projection: &Projection, noise: &DMatrix<f64>, gate: f64) -> Self {
        let s = &projection.z_cov + noise;
        let factor = robust_cholesky(&s);
        let m = s.nrows();
        Self {
            log_peak_inverse: 0.5 * (m as f64 * LN_TAU + log_determinant(&factor)),
            half_width: (0..m).map(|i| (gate * s[(i, i)]).sqrt()).collect(),
            factor,
        }
    }

    /// True when some entry of `residual` alone puts the pair outside the gate.
    pub(super) fn outside_box(&self, residual: &[f64]) -> bool {
        residual
            .iter()
            .zip(&self.half_width)
            .any(|(r, h)| r.abs() > *h)
    }

    /// The squared Mahalanobis distance rᵀ S⁻¹ r = |L⁻¹ r|² by forward substitution into
    /// `whitened`, or `None` as soon as the partial sum exceeds `limit` (or is NaN).
    pub(super) fn distance_sq(
        &self,
        residual: &[f64],
        whitened: &mut [f64],
        limit: f64,
    ) -> Option<f64> {
        let m = residual.len();
        // Column-major; only the lower triangle of `l_dirty` is meaningful.
        let l = self.factor.l_dirty().as_slice();
        let mut sum = 0.0;
        for i in 0..m {
            let mut v = residual[i];
            for (k, y) in whitened.iter().enumerate().take(i) {
                v -= l[i + k * m] * y;
            }
            v /= l[i + i * m];
            whitened[i] = v;
            sum += v * v;
            if sum > limit || sum.is_nan() {
                return None;
            }
        }
        Some(sum)
    }

    /// log N(r; 0, S) for a residual at squared Mahalanobis distance `distance_sq`.
    pub(super) fn log_density(&self, distance_sq: f64) -> f64 {
        -0.5 * distance_sq - self.log_peak_inverse
    }
}

/// Gain and posterior covariance of one component and noise (independent of z).
pub(super) struct Correction {
    gain: DMatrix<f64>,
    posterior_cov: DMatrix<f64>,
}

impl Correction {
    /// K = C S⁻¹ and the posterior covariance, Joseph form for a linear sensor.
    pub(super) fn new(
        projection: &Projection,
        innovation: &Innovation,
        prior_cov: &DMatrix<f64>,
        noise: &DMatrix<f64>,
    ) -> Self {
        // K = C S⁻¹, computed as (S⁻¹ Cᵀ)ᵀ with S symmetric.
        let gain = innovation
            .factor
            .solve(&projection.cross_cov.transpose())
            .transpose();
        let posterior = if projection.linear {
            // Joseph form (I − K H) P (I − K H)ᵀ + K R Kᵀ: stays symmetric positive
            // definite under round-off. K H is K in the first d columns, zero elsewhere.
            let n = prior_cov.nrows();
            let mut a = DMatrix::identity(n, n);
            let d = gain.ncols();
            a.columns_mut(0, d).zip_apply(&gain, |x, k| *x -= k);
            &a * prior_cov * a.transpose() + &gain * noise * gain.transpose()
        } else {
            // K S Kᵀ = K Cᵀ because K S = C.
            prior_cov - &gain * projection.cross_cov.transpose()
        };
        Self {
            gain,
            posterior_cov: nearest_spd(&posterior),
        }
    }

    /// The child of `component` for residual `r`: m + K r, the shared posterior covariance.
    pub(super) fn child(&self, component: &Gaussian, weight: f64, residual: &[f64]) -> Gaussian {
        let mut mean = component.mean.clone();
        let r = nalgebra::DVectorView::from_slice(residual, residual.len());
        mean.gemv(1.0, &self.gain, &r, 1.0);
        Gaussian::new(weight, mean, self.posterior_cov.clone(), component.label)
    }
}

/// A predicted component the sensor can detect, prepared for the update.
pub(super) struct Detectable<'a> {
    pub(super) component: &'a Gaussian,
    /// log(p_D · w).
    pub(super) log_prior: f64,
    pub(super) projection: Projection,
    /// With the sensor's default noise.
    pub(super) innovation: Innovation,
}
