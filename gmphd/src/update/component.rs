//! One predicted component prepared for the update: its projection into measurement space
//! and the Cholesky factor of its innovation covariance, both needed for every pair.
//! (Gain and posterior covariance, needed only for components that get a detection child,
//! are in [`super::correction`].)
//!
//! Per component this allocates only what it keeps: nothing for a linear sensor's
//! projection (a slice of the component), three arrays for an unscented one, and one
//! buffer for the innovation factor.

use nalgebra::DMatrix;

use super::unscented::UnscentedMoments;
use crate::gaussian::Gaussian;
use crate::linalg::{lower_cholesky, robust_cholesky};

/// ln 2π.
const LN_TAU: f64 = 1.837_877_066_409_345_5;

/// A predicted component seen in measurement space (noise not included).
pub(super) enum Projection {
    /// H = [I_d 0]: ẑ, H P Hᵀ and P Hᵀ are slices of the component.
    Linear { dims: usize },
    /// The unscented transform's moments.
    Unscented(UnscentedMoments),
}

/// A predicted component the sensor can detect, prepared for the update.
pub(super) struct Detectable<'a> {
    pub(super) component: &'a Gaussian,
    /// log(p_D · w).
    pub(super) log_prior: f64,
    projection: Projection,
    /// With the sensor's default noise.
    pub(super) innovation: Innovation,
}

impl<'a> Detectable<'a> {
    /// Prepares `component` for a sensor with default noise `noise` and gate `gate` (γ).
    pub(super) fn new(
        component: &'a Gaussian,
        log_prior: f64,
        projection: Projection,
        noise: &DMatrix<f64>,
        gate: f64,
    ) -> Self {
        let mut detectable = Self {
            component,
            log_prior,
            projection,
            innovation: Innovation::default(),
        };
        detectable.innovation = detectable.innovation_with(noise, gate);
        detectable
    }

    /// True for H = [I_d 0] (then the Joseph-form covariance update applies).
    pub(super) fn is_linear(&self) -> bool {
        matches!(self.projection, Projection::Linear { .. })
    }

    /// Size of the state.
    pub(super) fn state_dim(&self) -> usize {
        self.component.dim()
    }

    /// Size of a measurement.
    pub(super) fn measurement_dim(&self) -> usize {
        match &self.projection {
            Projection::Linear { dims } => *dims,
            Projection::Unscented(moments) => moments.mean.len(),
        }
    }

    /// The predicted measurement ẑ.
    pub(super) fn predicted_z(&self) -> &[f64] {
        match &self.projection {
            Projection::Linear { dims } => &self.component.mean.as_slice()[..*dims],
            Projection::Unscented(moments) => moments.mean.as_slice(),
        }
    }

    /// Entry (r, c) of H P Hᵀ (noise not included).
    pub(super) fn z_cov(&self, r: usize, c: usize) -> f64 {
        match &self.projection {
            Projection::Linear { .. } => self.component.cov[(r, c)],
            Projection::Unscented(moments) => moments.cov[(r, c)],
        }
    }

    /// The state–measurement cross-covariance P Hᵀ, n × m, column-major: entry (r, c) is at
    /// r + c·n (for a linear sensor, the first m columns of P).
    pub(super) fn cross_cov(&self) -> &[f64] {
        let (n, m) = (self.state_dim(), self.measurement_dim());
        match &self.projection {
            Projection::Linear { .. } => &self.component.cov.as_slice()[..n * m],
            Projection::Unscented(moments) => moments.cross_cov.as_slice(),
        }
    }

    /// The innovation covariance H P Hᵀ + `noise`, factored, for the gate `gate`.
    pub(super) fn innovation_with(&self, noise: &DMatrix<f64>, gate: f64) -> Innovation {
        let m = self.measurement_dim();
        let s = |r: usize, c: usize| self.z_cov(r, c) + noise[(r, c)];
        let mut data = vec![0.0; m * m + m];
        if !lower_cholesky(m, s, &mut data[..m * m]) {
            // Not numerically positive definite (a tiny innovation against round-off):
            // the repaired factor, as everywhere else in the filter.
            let repaired = robust_cholesky(&DMatrix::from_fn(m, m, s)).unpack();
            data[..m * m].copy_from_slice(repaired.as_slice());
        }
        let log_det: f64 = (0..m).map(|i| 2.0 * data[i + i * m].ln()).sum();
        for i in 0..m {
            data[m * m + i] = (gate * s(i, i)).sqrt();
        }
        Innovation {
            dim: m,
            data,
            log_peak_inverse: 0.5 * (m as f64 * LN_TAU + log_det),
        }
    }
}

/// The innovation covariance S = H P Hᵀ + R of one component and noise, factored.
#[derive(Default)]
pub(super) struct Innovation {
    dim: usize,
    /// The lower Cholesky factor L of S (column-major, m × m), then √(γ S_ii) for each i:
    /// a residual entry beyond it puts the pair outside the gate γ, since
    /// rᵀ S⁻¹ r ≥ r_i² / S_ii (+∞ without a gate).
    data: Vec<f64>,
    /// ½ (m ln 2π + ln det S): −log of the density's peak.
    log_peak_inverse: f64,
}

impl Innovation {
    fn lower(&self) -> &[f64] {
        &self.data[..self.dim * self.dim]
    }

    /// √(γ S_ii): the gate's extent along measurement dimension `i` (+∞ without a gate).
    pub(super) fn half_width(&self, i: usize) -> f64 {
        self.data[self.dim * self.dim + i]
    }

    /// True when some entry of `residual` alone puts the pair outside the gate.
    pub(super) fn outside_box(&self, residual: &[f64]) -> bool {
        residual
            .iter()
            .zip(&self.data[self.dim * self.dim..])
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
        let m = self.dim;
        let l = self.lower();
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

    /// x ← S⁻¹ x, by forward then backward substitution with L.
    pub(super) fn solve_in_place(&self, x: &mut [f64]) {
        let m = self.dim;
        let l = self.lower();
        for i in 0..m {
            let mut v = x[i];
            for k in 0..i {
                v -= l[i + k * m] * x[k];
            }
            x[i] = v / l[i + i * m];
        }
        for i in (0..m).rev() {
            let mut v = x[i];
            for k in i + 1..m {
                v -= l[k + i * m] * x[k];
            }
            x[i] = v / l[i + i * m];
        }
    }
}
