//! Gain and posterior covariance of one component for one noise covariance. Neither
//! depends on the measurement, so the update computes them once per component that has a
//! kept pair and every child of the component shares them.
//!
//! The matrices are small (n ≤ 6 or so states, m ≤ 3 measurement entries), so the products
//! are written out as loops over their entries, on the sizes of [`super::dims`]: on the
//! fixed sizes a correction allocates only the posterior covariance its children copy.

use nalgebra::{DMatrix, DefaultAllocator, Dim, OMatrix, OVector, U1};

use super::component::{Detectable, Innovation};
use super::dims::{Dims, Storage};
use crate::gaussian::Gaussian;
use crate::linalg::{lower_cholesky, nearest_spd, symmetrize_in_place};

/// Gain and posterior covariance of one component and noise (independent of z).
pub(super) struct Correction<D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    gain: OMatrix<f64, D::N, D::M>,
    /// A `DMatrix` already: every child gets a copy of it.
    posterior_cov: DMatrix<f64>,
}

impl<D: Dims> Correction<D>
where
    DefaultAllocator: Storage<D>,
{
    /// K = C S⁻¹ and the posterior covariance, in Joseph form for a linear sensor, for the
    /// component `d` whose innovation with `noise` is `innovation`.
    pub(super) fn new(
        d: &Detectable<'_, D>,
        innovation: &Innovation<D>,
        noise: &DMatrix<f64>,
    ) -> Self {
        let (n_dim, m_dim) = (d.state_dim(), d.measurement_dim());
        let (n, m) = (n_dim.value(), m_dim.value());
        // Row i of K is S⁻¹ (row i of C), S being symmetric.
        let cross = &d.cross_cov()[..n * m];
        let mut gain = OMatrix::<f64, D::N, D::M>::zeros_generic(n_dim, m_dim);
        let mut row = OVector::<f64, D::M>::zeros_generic(m_dim, U1);
        for i in 0..n {
            for (k, x) in row.as_mut_slice().iter_mut().enumerate() {
                *x = cross[i + k * n];
            }
            innovation.solve_in_place(row.as_mut_slice());
            for k in 0..m {
                gain[(i, k)] = row[k];
            }
        }
        // P − K Cᵀ; for a linear sensor this is B = (I − K H) P, as H P = Cᵀ.
        let mut posterior = OMatrix::<f64, D::N, D::N>::zeros_generic(n_dim, n_dim);
        posterior
            .as_mut_slice()
            .copy_from_slice(&d.component.cov.as_slice()[..n * n]);
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
            let b_columns =
                OMatrix::<f64, D::N, D::M>::from_fn_generic(n_dim, m_dim, |i, k| posterior[(i, k)]);
            // K_ik R_kl, the left factor of each term of K R Kᵀ (as the product associates).
            let gain_noise: Vec<OMatrix<f64, D::N, D::M>> = (0..m)
                .map(|k| {
                    OMatrix::from_fn_generic(n_dim, m_dim, |i, l| gain[(i, k)] * noise[(k, l)])
                })
                .collect();
            for j in 0..n {
                for i in 0..n {
                    let mut v = 0.0;
                    for (k, gain_noise) in gain_noise.iter().enumerate() {
                        v -= b_columns[(i, k)] * gain[(j, k)];
                        for l in 0..m {
                            v += gain_noise[(i, l)] * gain[(j, l)];
                        }
                    }
                    posterior[(i, j)] += v;
                }
            }
        }
        // (K S Kᵀ = K Cᵀ for the unscented form, because K S = C.)
        symmetrize_in_place(&mut posterior);
        let mut factor = OMatrix::<f64, D::N, D::N>::zeros_generic(n_dim, n_dim);
        let definite = lower_cholesky(n, |r, c| posterior[(r, c)], factor.as_mut_slice());
        let mut posterior_cov = DMatrix::from_column_slice(n, n, posterior.as_slice());
        if !definite {
            // Round-off made it indefinite (a measurement far more precise than the prior).
            posterior_cov = nearest_spd(&posterior_cov);
        }
        Self {
            gain,
            posterior_cov,
        }
    }

    /// The child of `component` for residual `r`: m + K r, the shared posterior covariance.
    pub(super) fn child(&self, component: &Gaussian, weight: f64, residual: &[f64]) -> Gaussian {
        Self::child_of(
            &self.gain,
            component,
            weight,
            residual,
            self.posterior_cov.clone(),
        )
    }

    /// [`Correction::child`] for the component's last child, which takes the posterior
    /// covariance instead of a copy.
    pub(super) fn last_child(
        self,
        component: &Gaussian,
        weight: f64,
        residual: &[f64],
    ) -> Gaussian {
        let Self {
            gain,
            posterior_cov,
        } = self;
        Self::child_of(&gain, component, weight, residual, posterior_cov)
    }

    /// m + K r with covariance `cov`.
    fn child_of(
        gain: &OMatrix<f64, D::N, D::M>,
        component: &Gaussian,
        weight: f64,
        residual: &[f64],
        cov: DMatrix<f64>,
    ) -> Gaussian {
        let mut mean = component.mean.clone();
        let (n, m) = gain.shape();
        let residual = &residual[..m];
        let x = &mut mean.as_mut_slice()[..n];
        for (k, r) in residual.iter().enumerate() {
            let column = &gain.as_slice()[k * n..(k + 1) * n];
            for (x, g) in x.iter_mut().zip(column) {
                *x += g * r;
            }
        }
        Gaussian {
            activity: component.activity,
            ..Gaussian::new(weight, mean, cov, component.label)
        }
    }
}
