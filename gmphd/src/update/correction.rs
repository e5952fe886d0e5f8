//! Gain and posterior covariance of one component for one noise covariance. Neither
//! depends on the measurement, so the update computes them once per component that has a
//! kept pair and every child of the component shares them.
//!
//! The matrices are small (n ≤ 6 or so states, m ≤ 3 measurement entries), so the products
//! are written out as loops over their entries: a correction allocates only its gain, its
//! covariance and one scratch buffer.

use nalgebra::{DMatrix, DVectorView};

use super::component::{Detectable, Innovation};
use crate::gaussian::Gaussian;
use crate::linalg::{lower_cholesky, nearest_spd, symmetrize_in_place};

/// Gain and posterior covariance of one component and noise (independent of z).
pub(super) struct Correction {
    gain: DMatrix<f64>,
    posterior_cov: DMatrix<f64>,
}

impl Correction {
    /// K = C S⁻¹ and the posterior covariance, in Joseph form for a linear sensor, for the
    /// component `d` whose innovation with `noise` is `innovation`.
    pub(super) fn new(d: &Detectable<'_>, innovation: &Innovation, noise: &DMatrix<f64>) -> Self {
        let (n, m) = (d.state_dim(), d.measurement_dim());
        // Row i of K is S⁻¹ (row i of C), S being symmetric.
        let cross = d.cross_cov();
        let mut gain = DMatrix::zeros(n, m);
        let mut row = vec![0.0; m.max(n * m)];
        for i in 0..n {
            for (k, x) in row.iter_mut().enumerate().take(m) {
                *x = cross[i + k * n];
            }
            innovation.solve_in_place(&mut row[..m]);
            for k in 0..m {
                gain[(i, k)] = row[k];
            }
        }
        let prior = &d.component.cov;
        // P − K Cᵀ; for a linear sensor this is B = (I − K H) P, as H P = Cᵀ.
        let mut posterior = prior.clone();
        let k_entries = gain.as_slice();
        for (j, column) in posterior.as_mut_slice().chunks_exact_mut(n).enumerate() {
            for (i, entry) in column.iter_mut().enumerate() {
                let kc: f64 = (0..m)
                    .map(|k| k_entries[i + k * n] * cross[j + k * n])
                    .sum();
                *entry -= kc;
            }
        }
        if d.is_linear() {
            // Joseph form (I − K H) P (I − K H)ᵀ + K R Kᵀ = B − B Hᵀ Kᵀ + K R Kᵀ: stays
            // symmetric positive definite under round-off. B Hᵀ is B's first m columns.
            let b_columns = &mut row[..n * m];
            for k in 0..m {
                for i in 0..n {
                    b_columns[i + k * n] = posterior[(i, k)];
                }
            }
            for j in 0..n {
                for i in 0..n {
                    let mut v = 0.0;
                    for k in 0..m {
                        v -= b_columns[i + k * n] * gain[(j, k)];
                        for l in 0..m {
                            v += gain[(i, k)] * noise[(k, l)] * gain[(j, l)];
                        }
                    }
                    posterior[(i, j)] += v;
                }
            }
        }
        // (K S Kᵀ = K Cᵀ for the unscented form, because K S = C.)
        symmetrize_in_place(&mut posterior);
        let mut factor = vec![0.0; n * n];
        if !lower_cholesky(n, |r, c| posterior[(r, c)], &mut factor) {
            // Round-off made it indefinite (a measurement far more precise than the prior).
            posterior = nearest_spd(&posterior);
        }
        Self {
            gain,
            posterior_cov: posterior,
        }
    }

    /// The child of `component` for residual `r`: m + K r, the shared posterior covariance.
    pub(super) fn child(&self, component: &Gaussian, weight: f64, residual: &[f64]) -> Gaussian {
        let mut mean = component.mean.clone();
        let r = DVectorView::from_slice(residual, residual.len());
        mean.gemv(1.0, &self.gain, &r, 1.0);
        Gaussian::new(weight, mean, self.posterior_cov.clone(), component.label)
    }
}
