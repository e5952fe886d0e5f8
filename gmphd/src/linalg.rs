//! Small linear-algebra routines shared by the prediction, update and reduction steps.

use std::f64::consts::{PI, TAU};

use nalgebra::allocator::Allocator;
use nalgebra::storage::StorageMut;
use nalgebra::{Cholesky, DMatrix, DVector, DefaultAllocator, Dim, Dyn, Matrix, OMatrix, SMatrix};

use crate::error::FilterError;

/// Relative tolerance for accepting a user-supplied matrix as symmetric.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// Entries of the largest square matrix [`check_spd`] factors on the stack (8 × 8).
const SMALL_SQUARE: usize = 64;

/// Smallest eigenvalue kept by [`nearest_spd`], relative to the largest one.
///
/// 1e-12 keeps the condition number well inside what a Cholesky factorisation
/// in f64 handles, while barely changing a healthy covariance.
const EIGENVALUE_FLOOR: f64 = 1e-12;

/// Wraps an angle to [-pi, pi).
pub fn wrap_angle(angle: f64) -> f64 {
    let shifted = angle + PI;
    // `rem_euclid` returns a value already in [0, 2π) unchanged, so the common case (a
    // residual of two angles that is already small) skips its floating-point remainder.
    let wrapped = if (0.0..TAU).contains(&shifted) {
        shifted
    } else {
        shifted.rem_euclid(TAU)
    } - PI;
    // `rem_euclid` can round up to exactly TAU for inputs just below a multiple of 2 pi.
    if wrapped >= PI {
        wrapped - TAU
    } else {
        wrapped
    }
}

/// The symmetric part (P + Pᵀ)/2 of a square matrix.
pub fn symmetrize(matrix: &DMatrix<f64>) -> DMatrix<f64> {
    // Entry by entry, in one allocation (`(P + Pᵀ) * 0.5` would take three).
    DMatrix::from_fn(matrix.nrows(), matrix.ncols(), |r, c| {
        (matrix[(r, c)] + matrix[(c, r)]) * 0.5
    })
}

/// Replaces a square matrix by its symmetric part (P + Pᵀ)/2, in place (of any storage:
/// the update's fixed-size matrices too).
#[inline]
pub fn symmetrize_in_place<R: Dim, C: Dim, S: StorageMut<f64, R, C>>(
    matrix: &mut Matrix<f64, R, C, S>,
) {
    let n = matrix.nrows().min(matrix.ncols());
    for c in 0..n {
        for r in c + 1..n {
            let mean = (matrix[(r, c)] + matrix[(c, r)]) * 0.5;
            matrix[(r, c)] = mean;
            matrix[(c, r)] = mean;
        }
    }
}

/// Makes `target` a copy of `source`, reusing `target`'s buffer when the shapes agree
/// (nalgebra's `clone_from` is the derived one, which allocates a new buffer every time).
/// Both are contiguous, so the copy is one block (nalgebra's `copy_from` walks entry by
/// entry, as for any strided view).
pub(crate) fn copy_into<R: Dim, C: Dim>(
    target: &mut OMatrix<f64, R, C>,
    source: &OMatrix<f64, R, C>,
) where
    DefaultAllocator: Allocator<R, C>,
{
    if target.shape() == source.shape() {
        target.as_mut_slice().copy_from_slice(source.as_slice());
    } else {
        *target = source.clone();
    }
}

/// Checks that every entry of a vector is finite.
pub fn check_finite_vector(vector: &DVector<f64>, what: &'static str) -> Result<(), FilterError> {
    if vector.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(FilterError::NonFinite { what })
    }
}

/// Checks that a matrix is `dim`×`dim`, finite, symmetric and positive definite.
pub fn check_spd(matrix: &DMatrix<f64>, dim: usize, what: &'static str) -> Result<(), FilterError> {
    if matrix.nrows() != dim || matrix.ncols() != dim {
        return Err(FilterError::DimensionMismatch {
            what,
            expected: dim,
            found: if matrix.nrows() != dim {
                matrix.nrows()
            } else {
                matrix.ncols()
            },
        });
    }
    if !matrix.iter().all(|x| x.is_finite()) {
        return Err(FilterError::NonFinite { what });
    }
    let scale = matrix.amax().max(f64::MIN_POSITIVE);
    // Without allocating: the filter validates every component it is handed (births, a
    // restored checkpoint), many per set.
    let mut asymmetry = 0.0_f64;
    for c in 0..dim {
        for r in c + 1..dim {
            asymmetry = asymmetry.max((matrix[(r, c)] - matrix[(c, r)]).abs());
        }
    }
    if asymmetry > SYMMETRY_TOLERANCE * scale {
        return Err(FilterError::NotPositiveDefinite { what });
    }
    let mut stack = [0.0; SMALL_SQUARE];
    let mut heap = Vec::new();
    let lower = if dim * dim <= SMALL_SQUARE {
        &mut stack[..dim * dim]
    } else {
        heap.resize(dim * dim, 0.0);
        &mut heap[..]
    };
    let symmetric = |r: usize, c: usize| (matrix[(r, c)] + matrix[(c, r)]) * 0.5;
    if !lower_cholesky(dim, symmetric, lower) {
        return Err(FilterError::NotPositiveDefinite { what });
    }
    Ok(())
}

/// The symmetric positive definite matrix closest to `matrix` in the sense used here:
/// symmetrize, and if the Cholesky factorisation still fails, clamp the eigenvalues
/// from below at a small fraction of the largest one.
///
/// Round-off in `P - K S Kᵀ` can make a covariance slightly indefinite when a
/// measurement is far more precise than the prior (a TDOA of 6e-5 s against a
/// metre-scale position); this repairs it without visibly changing a healthy matrix.
///
/// A matrix with non-finite entries is only symmetrized: an eigen-decomposition of
/// it would not converge, and there is nothing meaningful to repair.
pub fn nearest_spd(matrix: &DMatrix<f64>) -> DMatrix<f64> {
    let symmetric = symmetrize(matrix);
    if !symmetric.iter().all(|x| x.is_finite()) || cholesky_succeeds(&symmetric) {
        return symmetric;
    }
    let eigen = symmetric.symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    let floor = if largest.is_finite() && largest > 0.0 {
        largest * EIGENVALUE_FLOOR
    } else {
        EIGENVALUE_FLOOR
    };
    let clamped = eigen.eigenvalues.map(|value| value.max(floor));
    let rebuilt =
        &eigen.eigenvectors * DMatrix::from_diagonal(&clamped) * eigen.eigenvectors.transpose();
    symmetrize(&rebuilt)
}

/// Whether nalgebra's Cholesky factorisation of the square `matrix` succeeds: for the state
/// sizes of the motion models, on a fixed-size copy (the same algorithm, so the same
/// outcome, without the heap).
fn cholesky_succeeds(matrix: &DMatrix<f64>) -> bool {
    fn fixed<const N: usize>(matrix: &DMatrix<f64>) -> bool {
        Cholesky::new(SMatrix::<f64, N, N>::from_column_slice(matrix.as_slice())).is_some()
    }
    match matrix.shape() {
        (2, 2) => fixed::<2>(matrix),
        (3, 3) => fixed::<3>(matrix),
        (4, 4) => fixed::<4>(matrix),
        (5, 5) => fixed::<5>(matrix),
        (6, 6) => fixed::<6>(matrix),
        _ => Cholesky::new(matrix.clone()).is_some(),
    }
}

/// How many times [`robust_cholesky`] grows its diagonal jitter (by 10× each time,
/// from 1e-12 of the diagonal up to far beyond the matrix's own scale).
const MAX_JITTER_ROUNDS: usize = 30;

/// Cholesky factorisation of the m × m matrix with entries `a(r, c)` (its lower triangle is
/// read) into `lower`, column-major with zeros above the diagonal; false when the matrix is
/// not numerically positive definite.
///
/// Inlined so that each fixed size of the update gets its own unrolled copy.
#[inline]
pub(crate) fn lower_cholesky(m: usize, a: impl Fn(usize, usize) -> f64, lower: &mut [f64]) -> bool {
    lower_cholesky_columns(m, m, a, lower)
}

/// The first `columns` columns of [`lower_cholesky`]'s factor (the rest of `lower` is not
/// written), which depend on the first `columns` columns of the matrix only; false when one
/// of their pivots is not positive.
#[inline]
pub(crate) fn lower_cholesky_columns(
    m: usize,
    columns: usize,
    a: impl Fn(usize, usize) -> f64,
    lower: &mut [f64],
) -> bool {
    for j in 0..columns.min(m) {
        let mut diagonal = a(j, j);
        for k in 0..j {
            diagonal -= lower[j + k * m] * lower[j + k * m];
        }
        if diagonal <= 0.0 || diagonal.is_nan() {
            return false;
        }
        let l_jj = diagonal.sqrt();
        lower[j + j * m] = l_jj;
        for i in j + 1..m {
            let mut v = a(i, j);
            for k in 0..j {
                v -= lower[i + k * m] * lower[j + k * m];
            }
            lower[i + j * m] = v / l_jj;
        }
        for i in 0..j {
            lower[i + j * m] = 0.0;
        }
    }
    true
}

/// Cholesky factor of a covariance, repairing it with [`nearest_spd`] when needed.
///
/// Never fails and never loops forever: a matrix that cannot be repaired (only
/// possible with non-finite entries, which validated inputs never produce) is
/// replaced by the identity.
pub fn robust_cholesky(matrix: &DMatrix<f64>) -> Cholesky<f64, Dyn> {
    if let Some(chol) = Cholesky::new(symmetrize(matrix)) {
        return chol;
    }
    let n = matrix.nrows();
    let mut repaired = nearest_spd(matrix);
    // Clamping leaves a positive spectrum, but rounding in the rebuild can still defeat
    // Cholesky for a wildly scaled matrix; grow a diagonal jitter until it succeeds.
    let mut jitter = repaired.diagonal().amax().max(f64::MIN_POSITIVE) * EIGENVALUE_FLOOR;
    for _ in 0..MAX_JITTER_ROUNDS {
        if let Some(chol) = Cholesky::new(repaired.clone()) {
            return chol;
        }
        for i in 0..n {
            repaired[(i, i)] += jitter;
        }
        jitter *= 10.0;
    }
    Cholesky::new(DMatrix::identity(n, n)).expect("the identity is positive definite")
}

/// log det of the matrix factored by `chol`.
pub fn log_determinant(chol: &Cholesky<f64, Dyn>) -> f64 {
    2.0 * chol
        .l_dirty()
        .diagonal()
        .iter()
        .map(|d| d.ln())
        .sum::<f64>()
}

/// log N(residual; 0, S) given the Cholesky factor of S.
pub fn gaussian_log_density(residual: &DVector<f64>, chol: &Cholesky<f64, Dyn>) -> f64 {
    let dim = residual.len() as f64;
    let whitened = chol
        .l_dirty()
        .solve_lower_triangular(residual)
        .unwrap_or_else(|| DVector::from_element(residual.len(), f64::INFINITY));
    -0.5 * (whitened.norm_squared() + dim * TAU.ln() + log_determinant(chol))
}

/// Whether points lie within a squared Mahalanobis distance of a centre, under one fixed
/// covariance P, for many point–centre pairs (the merge test of Vo & Ma's reduction and
/// the ancestor test of label inheritance), without allocating per pair.
///
/// Each entry alone bounds the distance, dᵀ P⁻¹ d ≥ d_k² / P_kk, so a pair with some
/// d_k² > threshold · P_kk is rejected at once; only the others need the Cholesky factor
/// of P, and a forward substitution that stops as soon as the partial sum exceeds the
/// threshold. Row i of the substitution needs rows 0..=i of the factor only, and most
/// tests stop within the position's rows, so the factor is computed row by row as the
/// substitutions first reach each row (the same arithmetic as [`lower_cholesky`], in the
/// same order: the same factor).
#[derive(Debug, Clone, Default)]
pub(crate) struct MahalanobisGate {
    /// The lower Cholesky factor of P, column-major, valid in its first `rows` rows.
    lower: Vec<f64>,
    /// Rows of `lower` computed so far.
    rows: usize,
}

impl MahalanobisGate {
    /// (point − centre)ᵀ P⁻¹ (point − centre) ≤ `threshold` for P = `cov`. When a pivot of
    /// P's Cholesky factor is not positive, `fallback` gives the factor to use instead (all
    /// of it), or `None`, which is then returned. `scratch` is resized to the dimension.
    pub(crate) fn contains(
        &mut self,
        cov: &DMatrix<f64>,
        point: &DVector<f64>,
        centre: &DVector<f64>,
        threshold: f64,
        scratch: &mut Vec<f64>,
        fallback: impl FnOnce(&DMatrix<f64>) -> Option<DMatrix<f64>>,
    ) -> Option<bool> {
        let n = cov.nrows();
        scratch.resize(n, 0.0);
        for (k, d) in scratch.iter_mut().enumerate() {
            *d = point[k] - centre[k];
            if *d * *d > threshold * cov[(k, k)] {
                return Some(false);
            }
        }
        if self.lower.len() != n * n {
            self.lower = vec![0.0; n * n];
            self.rows = 0;
        }
        let mut fallback = Some(fallback);
        let mut sum = 0.0;
        for i in 0..n {
            if self.rows <= i && !self.factor_row(cov, i) {
                let repaired = fallback.take().and_then(|fallback| fallback(cov))?;
                self.lower.copy_from_slice(repaired.as_slice());
                self.rows = n;
            }
            let l = &self.lower;
            let mut v = scratch[i];
            for k in 0..i {
                v -= l[i + k * n] * scratch[k];
            }
            v /= l[i + i * n];
            scratch[i] = v;
            sum += v * v;
            if sum > threshold || sum.is_nan() {
                return Some(false);
            }
        }
        Some(true)
    }

    /// Computes row `i` of the factor of `cov` (rows before it are done): false when its
    /// pivot is not positive.
    fn factor_row(&mut self, cov: &DMatrix<f64>, i: usize) -> bool {
        let n = cov.nrows();
        // Both column-major n × n with i < n, stated up front so that the indexing below
        // needs no checks of its own.
        let (cov, l) = (&cov.as_slice()[..n * n], &mut self.lower[..n * n]);
        assert!(i < n);
        for j in 0..i {
            let mut v = cov[i + j * n];
            for k in 0..j {
                v -= l[i + k * n] * l[j + k * n];
            }
            l[i + j * n] = v / l[j + j * n];
        }
        let mut diagonal = cov[i + i * n];
        for k in 0..i {
            diagonal -= l[i + k * n] * l[i + k * n];
        }
        if diagonal <= 0.0 || diagonal.is_nan() {
            return false;
        }
        l[i + i * n] = diagonal.sqrt();
        self.rows = i + 1;
        true
    }
}

/// log(sum(exp(terms))) without overflow; -inf for an empty or all -inf input.
pub fn log_sum_exp(terms: &[f64]) -> f64 {
    let max = terms.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if max == f64::NEG_INFINITY {
        return f64::NEG_INFINITY;
    }
    max + terms.iter().map(|t| (t - max).exp()).sum::<f64>().ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fixed_size_cholesky_decides_as_the_dynamic_one() {
        // Positive definite, rank-deficient (round-off decides) and indefinite matrices.
        for n in 1..=7_usize {
            for (seed, rank) in [(1, n), (2, n.saturating_sub(1)), (3, 1), (4, n)] {
                let a = DMatrix::from_fn(n, rank, |r, c| {
                    ((r * 7 + c * 3 + seed * 5) % 13) as f64 * 0.37 - 2.1
                });
                let mut m = &a * a.transpose();
                if seed == 4 {
                    m[(n - 1, n - 1)] = -0.5;
                }
                let dynamic = Cholesky::new(m.clone()).is_some();
                assert_eq!(cholesky_succeeds(&m), dynamic, "{m}");
            }
        }
    }

    #[test]
    fn the_gate_factors_row_by_row_as_lower_cholesky_does() {
        let root = DMatrix::from_fn(6, 6, |r, c| ((r * 5 + c * 7) % 11) as f64 * 0.21 - 0.9);
        let cov = &root * root.transpose() + DMatrix::identity(6, 6) * 0.3;
        let mut full = vec![0.0; 36];
        assert!(lower_cholesky(6, |r, c| cov[(r, c)], &mut full));
        let centre = DVector::zeros(6);
        let mut scratch = Vec::new();
        let mut gate = MahalanobisGate::default();
        let never =
            |_: &DMatrix<f64>| -> Option<DMatrix<f64>> { unreachable!("positive definite") };
        for step in 0..40 {
            let point = DVector::from_fn(6, |i, _| ((step * 3 + i * 5) % 9) as f64 * 0.25 - 1.0);
            // The exact distance, through the full factor.
            let mut whitened = point.as_slice().to_vec();
            for i in 0..6 {
                for k in 0..i {
                    whitened[i] -= full[i + k * 6] * whitened[k];
                }
                whitened[i] /= full[i + i * 6];
            }
            let distance: f64 = whitened.iter().map(|w| w * w).sum();
            let inside = gate.contains(&cov, &point, &centre, 4.0, &mut scratch, never);
            assert_eq!(inside, Some(distance <= 4.0), "{point}");
            assert!(gate.lower[..gate.rows].iter().all(|x| x.is_finite()));
        }
        assert_eq!(gate.rows, 6, "some point went through every row");
        assert_eq!(gate.lower, full, "bit for bit");
        // An indefinite covariance: the fallback's factor, or its `None`.
        let mut bad = cov.clone();
        bad[(4, 4)] = 1e-6;
        // (Zero in entry 4, so that the entry-wise test does not settle it first.)
        let point = DVector::from_fn(6, |i, _| if i == 4 { 0.0 } else { 0.01 });
        let mut gate = MahalanobisGate::default();
        assert_eq!(
            gate.contains(&bad, &point, &centre, 4.0, &mut scratch, |_| None),
            None
        );
        let identity = |_: &DMatrix<f64>| Some(DMatrix::identity(6, 6));
        let mut gate = MahalanobisGate::default();
        assert_eq!(
            gate.contains(&bad, &point, &centre, 4.0, &mut scratch, identity),
            Some(true)
        );
    }

    #[test]
    fn wrap_angle_skips_the_remainder_without_changing_a_bit() {
        let by_remainder = |angle: f64| {
            let wrapped = (angle + PI).rem_euclid(TAU) - PI;
            if wrapped >= PI {
                wrapped - TAU
            } else {
                wrapped
            }
        };
        let edges = [-PI, PI, -TAU, TAU, 0.0, -0.0, 3.0 * PI];
        let near = edges
            .iter()
            .flat_map(|&e| [e.next_down(), e, e.next_up()].into_iter());
        let spread = (-2000..=2000).map(|i| f64::from(i) * 0.00731);
        for angle in near.chain(spread) {
            assert_eq!(
                wrap_angle(angle).to_bits(),
                by_remainder(angle).to_bits(),
                "{angle}"
            );
        }
    }

    #[test]
    fn wrap_angle_lands_in_half_open_interval() {
        for angle in [-7.0, -PI, -0.5, 0.0, 0.5, PI, 3.0 * PI, 7.0, -TAU] {
            let wrapped = wrap_angle(angle);
            assert!((-PI..PI).contains(&wrapped), "{angle} -> {wrapped}");
            assert!(((wrapped - angle) / TAU - ((wrapped - angle) / TAU).round()).abs() < 1e-12);
        }
        assert_eq!(wrap_angle(PI), -PI);
    }

    #[test]
    fn nearest_spd_repairs_an_indefinite_matrix() {
        let bad = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        let fixed = nearest_spd(&bad);
        assert!(Cholesky::new(fixed).is_some());
    }

    #[test]
    fn non_finite_matrices_do_not_hang_the_repair() {
        let bad = DMatrix::from_row_slice(2, 2, &[f64::NAN, 0.0, 0.0, 1.0]);
        assert!(nearest_spd(&bad)[(0, 0)].is_nan());
        assert_eq!(robust_cholesky(&bad).l(), DMatrix::identity(2, 2));
    }

    #[test]
    fn log_density_matches_closed_form() {
        let cov = DMatrix::from_diagonal(&DVector::from_vec(vec![4.0, 9.0]));
        let chol = Cholesky::new(cov).unwrap();
        let r = DVector::from_vec(vec![2.0, 3.0]);
        let expected = -0.5 * (1.0 + 1.0) - (TAU * 6.0).ln();
        assert!((gaussian_log_density(&r, &chol) - expected).abs() < 1e-12);
    }

    #[test]
    fn log_sum_exp_handles_huge_and_empty_inputs() {
        assert_eq!(log_sum_exp(&[]), f64::NEG_INFINITY);
        let v = log_sum_exp(&[1000.0, 1000.0]);
        assert!((v - (1000.0 + 2f64.ln())).abs() < 1e-12);
        assert_eq!(log_sum_exp(&[f64::NEG_INFINITY, 0.0]), 0.0);
    }
}
