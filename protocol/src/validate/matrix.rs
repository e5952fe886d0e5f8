//! Covariance checks: square of the right size, finite, symmetric, positive definite.

use super::checks::check_finite;
use super::SYMMETRY_RELATIVE_TOLERANCE;
use crate::error::ProtocolError;

/// Checks that `matrix` (rows) is a `dim`×`dim` symmetric positive definite matrix of finite numbers.
///
/// `field` names the matrix in errors (e.g. `covariances[2]`). Symmetry is judged to
/// [`SYMMETRY_RELATIVE_TOLERANCE`] of the largest absolute entry; definiteness by a Cholesky factorisation
/// whose every pivot must be > 0.
pub fn check_covariance<R: AsRef<[f64]>>(
    matrix: &[R],
    dim: usize,
    field: &str,
) -> Result<(), ProtocolError> {
    check_shape(matrix, dim, field)?;
    for (i, row) in matrix.iter().enumerate() {
        for (j, &value) in row.as_ref().iter().enumerate() {
            check_finite(value, || format!("{field}[{i}][{j}]"))?;
        }
    }
    check_symmetric(matrix, field)?;
    check_positive_definite(matrix, field)
}

fn check_shape<R: AsRef<[f64]>>(
    matrix: &[R],
    dim: usize,
    field: &str,
) -> Result<(), ProtocolError> {
    let shape_error = |found: String| ProtocolError::MatrixShape {
        field: field.to_owned(),
        expected: dim,
        found,
    };
    if matrix.len() != dim {
        return Err(shape_error(format!("{} rows", matrix.len())));
    }
    match matrix.iter().position(|row| row.as_ref().len() != dim) {
        Some(i) => Err(shape_error(format!(
            "row {i} with {} values",
            matrix[i].as_ref().len()
        ))),
        None => Ok(()),
    }
}

fn check_symmetric<R: AsRef<[f64]>>(matrix: &[R], field: &str) -> Result<(), ProtocolError> {
    let scale = matrix
        .iter()
        .flat_map(|row| row.as_ref().iter())
        .fold(0.0_f64, |acc, v| acc.max(v.abs()));
    let tolerance = SYMMETRY_RELATIVE_TOLERANCE * scale;
    for row in 0..matrix.len() {
        for col in row + 1..matrix.len() {
            let upper = matrix[row].as_ref()[col];
            let lower = matrix[col].as_ref()[row];
            if (upper - lower).abs() > tolerance {
                return Err(ProtocolError::NotSymmetric {
                    field: field.to_owned(),
                    row,
                    col,
                    upper,
                    lower,
                });
            }
        }
    }
    Ok(())
}

/// Cholesky–Banachiewicz on the lower triangle: A = L·Lᵀ exists with a positive diagonal iff A is SPD.
fn check_positive_definite<R: AsRef<[f64]>>(
    matrix: &[R],
    field: &str,
) -> Result<(), ProtocolError> {
    let n = matrix.len();
    let mut lower = vec![0.0_f64; n * n];
    for i in 0..n {
        for j in 0..=i {
            let dot: f64 = (0..j).map(|k| lower[i * n + k] * lower[j * n + k]).sum();
            let residual = matrix[i].as_ref()[j] - dot;
            if i == j {
                // The NaN test catches an overflow of the finite inputs.
                if residual.is_nan() || residual <= 0.0 {
                    return Err(ProtocolError::NotPositiveDefinite {
                        field: field.to_owned(),
                        pivot: i,
                        value: residual,
                    });
                }
                lower[i * n + i] = residual.sqrt();
            } else {
                lower[i * n + j] = residual / lower[j * n + j];
            }
        }
    }
    Ok(())
}
