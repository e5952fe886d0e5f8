//! Unscented transform (Julier & Uhlmann), used for nonlinear motion and measurements.
//!
//! Parameterisation: the scaled form with (alpha, beta, kappa), λ = α²(n + κ) − n,
//! sigma points m and m ± columns of √((n + λ) P), mean weights λ/(n+λ) and
//! 1/(2(n+λ)), covariance weights the same plus (1 − α² + β) on the centre point.
//!
//! Default α = 1, β = 2, κ = 2 — the values of Vo & Ma's own unscented GM-PHD
//! implementation. With them every weight is positive for any state size, so the
//! transformed covariance is a positive combination of outer products and stays
//! positive semi-definite; the plain "κ = 3 − n" rule would make the centre weight
//! negative for n > 3 (our states have 4 to 6 entries). β = 2 is the optimal
//! choice for a Gaussian prior. The parameters are configurable.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::error::{invalid, FilterError};
use crate::linalg::robust_cholesky;

/// The (alpha, beta, kappa) parameters of the scaled unscented transform.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UnscentedParams {
    /// Spread of the sigma points around the mean (> 0).
    pub alpha: f64,
    /// Prior knowledge of the distribution; 2 is optimal for a Gaussian.
    pub beta: f64,
    /// Secondary scaling; n + κ must stay > 0.
    pub kappa: f64,
}

impl Default for UnscentedParams {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            kappa: 2.0,
        }
    }
}

impl UnscentedParams {
    /// Checked constructor (the state size is checked again when the points are drawn).
    pub fn new(alpha: f64, beta: f64, kappa: f64) -> Result<Self, FilterError> {
        if !(alpha > 0.0 && alpha.is_finite()) {
            return Err(invalid("unscented alpha", format!("{alpha} is not > 0")));
        }
        if !beta.is_finite() || !kappa.is_finite() {
            return Err(invalid("unscented beta/kappa", "must be finite"));
        }
        Ok(Self { alpha, beta, kappa })
    }

    /// λ = α²(n + κ) − n for a state of size n.
    pub fn lambda(&self, n: usize) -> f64 {
        let n = n as f64;
        self.alpha * self.alpha * (n + self.kappa) - n
    }
}

/// The scalars of the scaled transform for one state size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct UnscentedWeights {
    /// n + λ: the sigma points are m ± the columns of √((n + λ) P).
    pub(crate) spread: f64,
    /// Mean weight of the centre point, λ / (n + λ).
    pub(crate) centre_mean: f64,
    /// Covariance weight of the centre point, λ / (n + λ) + 1 − α² + β.
    pub(crate) centre_cov: f64,
    /// Mean and covariance weight of each other point, 1 / (2(n + λ)).
    pub(crate) outer: f64,
}

impl UnscentedParams {
    /// The weights for a state of size `n`; an error when n + λ ≤ 0.
    pub(crate) fn weights(&self, n: usize) -> Result<UnscentedWeights, FilterError> {
        let lambda = self.lambda(n);
        let spread = n as f64 + lambda;
        if spread.is_nan() || spread <= 0.0 {
            return Err(invalid(
                "unscented parameters",
                format!("n + lambda = {spread} must be > 0 for a state of size {n}"),
            ));
        }
        let centre_mean = lambda / spread;
        Ok(UnscentedWeights {
            spread,
            centre_mean,
            centre_cov: centre_mean + 1.0 - self.alpha * self.alpha + self.beta,
            outer: 1.0 / (2.0 * spread),
        })
    }
}

/// Sigma points of a Gaussian with their mean and covariance weights.
#[derive(Debug, Clone, PartialEq)]
pub struct SigmaPoints {
    /// 2n + 1 points; the first one is the mean.
    pub points: Vec<DVector<f64>>,
    /// Weights for the mean (sum to 1).
    pub mean_weights: Vec<f64>,
    /// Weights for the covariance.
    pub cov_weights: Vec<f64>,
}

impl SigmaPoints {
    /// Sigma points of N(mean, cov). A covariance made slightly indefinite by
    /// round-off is repaired before taking its square root.
    pub fn new(
        mean: &DVector<f64>,
        cov: &DMatrix<f64>,
        params: &UnscentedParams,
    ) -> Result<Self, FilterError> {
        let n = mean.len();
        if cov.nrows() != n || cov.ncols() != n {
            return Err(FilterError::DimensionMismatch {
                what: "covariance for sigma points",
                expected: n,
                found: cov.nrows(),
            });
        }
        let weights = params.weights(n)?;
        let spread = weights.spread;
        let root = robust_cholesky(&(cov * spread)).unpack();
        let mut points = Vec::with_capacity(2 * n + 1);
        points.push(mean.clone());
        for i in 0..n {
            points.push(mean + root.column(i));
        }
        for i in 0..n {
            points.push(mean - root.column(i));
        }
        let mut mean_weights = vec![weights.outer; 2 * n + 1];
        mean_weights[0] = weights.centre_mean;
        let mut cov_weights = mean_weights.clone();
        cov_weights[0] = weights.centre_cov;
        Ok(Self {
            points,
            mean_weights,
            cov_weights,
        })
    }

    /// Pushes the points through `f` and returns the transformed mean, covariance
    /// and cross-covariance with the input.
    ///
    /// `residual(a, b)` is the difference a − b in the output space (angles wrapped).
    /// The mean is taken relative to the first transformed point,
    /// ȳ = y₀ + Σ wᵢ residual(yᵢ, y₀), so that angular outputs near ±π average
    /// correctly without a separate circular-mean function.
    pub fn transform<F, R>(&self, f: F, residual: R) -> UnscentedResult
    where
        F: Fn(&DVector<f64>) -> DVector<f64>,
        R: Fn(&DVector<f64>, &DVector<f64>) -> DVector<f64>,
    {
        self.accumulate(f, |a, b, out| out.copy_from(&residual(a, b)))
    }

    /// [`SigmaPoints::transform`] with a residual that writes a − b into its third
    /// argument (all of the output's length): apart from the 2n + 1 outputs of `f`, nothing
    /// is allocated per sigma point.
    pub fn transform_into<F, R>(&self, f: F, residual_into: R) -> UnscentedResult
    where
        F: Fn(&DVector<f64>) -> DVector<f64>,
        R: Fn(&[f64], &[f64], &mut [f64]),
    {
        self.accumulate(f, |a, b, out| {
            residual_into(a.as_slice(), b.as_slice(), out.as_mut_slice())
        })
    }

    /// The weighted sums of both transforms, with rank-one updates into the results.
    fn accumulate<F, R>(&self, f: F, residual: R) -> UnscentedResult
    where
        F: Fn(&DVector<f64>) -> DVector<f64>,
        R: Fn(&DVector<f64>, &DVector<f64>, &mut DVector<f64>),
    {
        let outputs: Vec<DVector<f64>> = self.points.iter().map(&f).collect();
        let anchor = &outputs[0];
        let mut mean = anchor.clone();
        let mut dy = DVector::zeros(mean.len());
        for (y, w) in outputs.iter().zip(&self.mean_weights).skip(1) {
            residual(y, anchor, &mut dy);
            mean.axpy(*w, &dy, 1.0);
        }
        let x_mean = &self.points[0];
        let (nx, ny) = (x_mean.len(), mean.len());
        let mut cov = DMatrix::zeros(ny, ny);
        let mut cross_cov = DMatrix::zeros(nx, ny);
        let mut dx = DVector::zeros(nx);
        for ((x, y), w) in self.points.iter().zip(&outputs).zip(&self.cov_weights) {
            residual(y, &mean, &mut dy);
            dx.copy_from(x);
            dx -= x_mean;
            cov.ger(*w, &dy, &dy, 1.0);
            cross_cov.ger(*w, &dx, &dy, 1.0);
        }
        UnscentedResult {
            mean,
            cov: (&cov + cov.transpose()) * 0.5,
            cross_cov,
        }
    }
}

/// Output of an unscented transform.
#[derive(Debug, Clone, PartialEq)]
pub struct UnscentedResult {
    /// Transformed mean.
    pub mean: DVector<f64>,
    /// Transformed covariance (symmetric; no additive noise included).
    pub cov: DMatrix<f64>,
    /// Cross-covariance between the input and the output (n_x × n_y).
    pub cross_cov: DMatrix<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::wrap_angle;

    fn gaussian() -> (DVector<f64>, DMatrix<f64>) {
        let mean = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let cov = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.2, 1.0, 3.0, -0.5, 0.2, -0.5, 2.0]);
        (mean, cov)
    }

    #[test]
    fn linear_map_is_exact() {
        let (mean, cov) = gaussian();
        let a = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 0.0, -1.0, 0.5, 3.0]);
        let sp = SigmaPoints::new(&mean, &cov, &UnscentedParams::default()).unwrap();
        let out = sp.transform(|x| &a * x, |a, b| a - b);
        assert!((out.mean - &a * &mean).amax() < 1e-12);
        assert!((out.cov - &a * &cov * a.transpose()).amax() < 1e-10);
        assert!((out.cross_cov - &cov * a.transpose()).amax() < 1e-10);
    }

    #[test]
    fn angular_mean_straddling_pi_is_near_pi() {
        let mean = DVector::from_vec(vec![std::f64::consts::PI - 0.01]);
        let cov = DMatrix::from_element(1, 1, 0.05 * 0.05);
        let sp = SigmaPoints::new(&mean, &cov, &UnscentedParams::default()).unwrap();
        let out = sp.transform(
            |x| DVector::from_element(1, wrap_angle(x[0])),
            |a, b| DVector::from_element(1, wrap_angle(a[0] - b[0])),
        );
        assert!(wrap_angle(out.mean[0] - mean[0]).abs() < 1e-12);
        assert!((out.cov[(0, 0)] - 0.05 * 0.05).abs() < 1e-12);
    }

    #[test]
    fn rejects_a_degenerate_spread() {
        let (mean, cov) = gaussian();
        let params = UnscentedParams::new(1.0, 2.0, -3.0).unwrap();
        assert!(SigmaPoints::new(&mean, &cov, &params).is_err());
        assert!(UnscentedParams::new(0.0, 2.0, 0.0).is_err());
    }
}
