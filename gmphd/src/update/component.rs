//! One predicted component prepared for the update: its projection into measurement space
//! and the Cholesky factor of its innovation covariance, both needed for every pair.
//! (Gain and posterior covariance, needed only for components that get a detection child,
//! are in [`super::correction`].)
//!
//! On the fixed sizes of [`super::dims`] nothing here is allocated; on the dynamic ones,
//! only what a component keeps: three arrays for an unscented projection (a linear one is
//! a slice of the component) and two for the innovation factor.

use nalgebra::{DMatrix, DefaultAllocator, Dim, OMatrix, OVector, U1};

use super::dims::{Dims, Storage};
use super::unscented::UnscentedMoments;
use crate::gaussian::Gaussian;
use crate::linalg::{lower_cholesky, robust_cholesky};

/// ln 2π.
const LN_TAU: f64 = 1.837_877_066_409_345_5;

/// A predicted component seen in measurement space (noise not included).
pub(super) enum Projection<D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    /// H = [I_m 0]: ẑ, H P Hᵀ and P Hᵀ are slices of the component.
    Linear,
    /// The unscented transform's moments.
    Unscented(UnscentedMoments<D>),
}

impl<D: Dims> Projection<D>
where
    DefaultAllocator: Storage<D>,
{
    /// Entry (r, c) of H P Hᵀ for `component` (noise not included).
    fn z_cov(&self, component: &Gaussian, r: usize, c: usize) -> f64 {
        match self {
            Projection::Linear => component.cov[(r, c)],
            Projection::Unscented(moments) => moments.cov[(r, c)],
        }
    }
}

/// A predicted component the sensor can detect, prepared for the update.
pub(super) struct Detectable<'a, D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    pub(super) component: &'a Gaussian,
    /// log(p_D · w).
    pub(super) log_prior: f64,
    dims: D,
    projection: Projection<D>,
    /// With the sensor's default noise.
    pub(super) innovation: Innovation<D>,
}

impl<'a, D: Dims> Detectable<'a, D>
where
    DefaultAllocator: Storage<D>,
{
    /// Prepares `component` for a sensor of sizes `dims` with default noise `noise` and
    /// gate `gate` (γ).
    pub(super) fn new(
        dims: D,
        component: &'a Gaussian,
        log_prior: f64,
        projection: Projection<D>,
        noise: &DMatrix<f64>,
        gate: f64,
    ) -> Self {
        // Factored before the component is assembled, so that it is built in one piece.
        let z_cov = |r: usize, c: usize| projection.z_cov(component, r, c);
        let innovation = Innovation::of(dims.measurement(), z_cov, noise, gate);
        Self {
            component,
            log_prior,
            dims,
            projection,
            innovation,
        }
    }

    /// True for H = [I_m 0] (then the Joseph-form covariance update applies).
    pub(super) fn is_linear(&self) -> bool {
        matches!(self.projection, Projection::Linear)
    }

    /// Size of the state.
    pub(super) fn state_dim(&self) -> D::N {
        self.dims.state(self.component)
    }

    /// Size of a measurement.
    pub(super) fn measurement_dim(&self) -> D::M {
        self.dims.measurement()
    }

    /// The unscented moments, for a nonlinear sensor.
    pub(super) fn unscented_moments(&self) -> Option<&UnscentedMoments<D>> {
        match &self.projection {
            Projection::Linear => None,
            Projection::Unscented(moments) => Some(moments),
        }
    }

    /// The predicted measurement ẑ.
    pub(super) fn predicted_z(&self) -> &[f64] {
        match &self.projection {
            Projection::Linear => &self.component.mean.as_slice()[..self.measurement_dim().value()],
            Projection::Unscented(moments) => moments.mean.as_slice(),
        }
    }

    /// Entry (r, c) of H P Hᵀ (noise not included).
    pub(super) fn z_cov(&self, r: usize, c: usize) -> f64 {
        self.projection.z_cov(self.component, r, c)
    }

    /// The state–measurement cross-covariance P Hᵀ, n × m, column-major: entry (r, c) is at
    /// r + c·n (for a linear sensor, the first m columns of P).
    pub(super) fn cross_cov(&self) -> &[f64] {
        let (n, m) = (self.state_dim().value(), self.measurement_dim().value());
        match &self.projection {
            Projection::Linear => &self.component.cov.as_slice()[..n * m],
            Projection::Unscented(moments) => moments.cross_cov.as_slice(),
        }
    }

    /// The innovation covariance H P Hᵀ + `noise`, factored, for the gate `gate`.
    pub(super) fn innovation_with(&self, noise: &DMatrix<f64>, gate: f64) -> Innovation<D> {
        Innovation::of(self.measurement_dim(), |r, c| self.z_cov(r, c), noise, gate)
    }
}

impl<D: Dims> Innovation<D>
where
    DefaultAllocator: Storage<D>,
{
    /// The innovation covariance `z_cov` + `noise` (m × m), factored, for the gate `gate`.
    fn of(
        m_dim: D::M,
        z_cov: impl Fn(usize, usize) -> f64,
        noise: &DMatrix<f64>,
        gate: f64,
    ) -> Self {
        let m = m_dim.value();
        let s = |r: usize, c: usize| z_cov(r, c) + noise[(r, c)];
        let mut lower = OMatrix::<f64, D::M, D::M>::zeros_generic(m_dim, m_dim);
        if !lower_cholesky(m, s, lower.as_mut_slice()) {
            // Not numerically positive definite (a tiny innovation against round-off):
            // the repaired factor, as everywhere else in the filter.
            let repaired = robust_cholesky(&DMatrix::from_fn(m, m, s)).unpack();
            lower.as_mut_slice().copy_from_slice(repaired.as_slice());
        }
        let log_det: f64 = (0..m).map(|i| 2.0 * lower[(i, i)].ln()).sum();
        let half_width =
            OVector::<f64, D::M>::from_fn_generic(m_dim, U1, |i, _| (gate * s(i, i)).sqrt());
        Innovation {
            lower,
            half_width,
            log_peak_inverse: 0.5 * (m as f64 * LN_TAU + log_det),
        }
    }
}

/// The innovation covariance S = H P Hᵀ + R of one component and noise, factored.
pub(super) struct Innovation<D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    /// The lower Cholesky factor L of S.
    lower: OMatrix<f64, D::M, D::M>,
    /// √(γ S_ii) for each i: a residual entry beyond it puts the pair outside the gate γ,
    /// since rᵀ S⁻¹ r ≥ r_i² / S_ii (+∞ without a gate).
    half_width: OVector<f64, D::M>,
    /// ½ (m ln 2π + ln det S): −log of the density's peak.
    log_peak_inverse: f64,
}

impl<D: Dims> Innovation<D>
where
    DefaultAllocator: Storage<D>,
{
    /// The lower factor L, column-major, and its size m.
    fn lower(&self) -> (&[f64], usize) {
        (self.lower.as_slice(), self.lower.nrows())
    }

    /// √(γ S_ii): the gate's extent along measurement dimension `i` (+∞ without a gate).
    pub(super) fn half_width(&self, i: usize) -> f64 {
        self.half_width[i]
    }

    /// True when some entry of `residual` alone puts the pair outside the gate.
    pub(super) fn outside_box(&self, residual: &[f64]) -> bool {
        residual
            .iter()
            .zip(self.half_width.as_slice())
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
        let (l, m) = self.lower();
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
        let (l, m) = self.lower();
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
