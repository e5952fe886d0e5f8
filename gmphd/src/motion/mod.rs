//! Motion models: how an object state evolves over a time step.
//!
//! State layout is always positions first, then velocities, then any extra
//! components (e.g. a turn rate). The filter only needs the prediction and the
//! map from a state to a 3-D world point, which is what sensors observe.

mod constant_velocity;
mod coordinated_turn;
mod random_walk;

pub use constant_velocity::ConstantVelocity;
pub use coordinated_turn::CoordinatedTurn;
pub use random_walk::RandomWalk;

use std::fmt::Debug;

use nalgebra::{DMatrix, DVector, Vector3};

use crate::error::{invalid, FilterError};
use crate::gaussian::Gaussian;

/// A single-object Markov motion model with Gaussian process noise.
pub trait MotionModel: Send + Sync + Debug {
    /// Size of the state vector.
    fn state_dim(&self) -> usize;

    /// Number of leading state components that are world coordinates (2 or 3).
    fn position_dims(&self) -> usize;

    /// The 3-D world point of a state; a 2-D state is padded with the model's
    /// fixed height. It depends on the leading [`MotionModel::position_dims`] entries of
    /// the state only (the unscented update relies on it).
    fn position(&self, x: &DVector<f64>) -> Vector3<f64>;

    /// The 3-D world velocity of a state, if the state has one (padded with 0).
    fn velocity(&self, x: &DVector<f64>) -> Option<Vector3<f64>>;

    /// Predicted mean and covariance after `dt` seconds (`dt` ≥ 0; 0 leaves the
    /// Gaussian unchanged).
    fn predict(
        &self,
        mean: &DVector<f64>,
        cov: &DMatrix<f64>,
        dt: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), FilterError>;

    /// Predicts every one of `components` over `dt` seconds in place (weights and labels
    /// untouched), all or none: on error every component is as it was.
    ///
    /// The default predicts them all with [`MotionModel::predict`] before writing any; a
    /// model whose only failures are a bad `dt` or a wrong size can check those first and
    /// then predict without allocating (as [`ConstantVelocity`] does).
    fn predict_all_in_place(
        &self,
        components: &mut [Gaussian],
        dt: f64,
    ) -> Result<(), FilterError> {
        let predicted = components
            .iter()
            .map(|c| self.predict(&c.mean, &c.cov, dt))
            .collect::<Result<Vec<_>, _>>()?;
        for (component, (mean, cov)) in components.iter_mut().zip(predicted) {
            component.mean = mean;
            component.cov = cov;
        }
        Ok(())
    }
}

/// Rejects a negative or non-finite time step.
pub(crate) fn check_dt(dt: f64) -> Result<(), FilterError> {
    if !dt.is_finite() {
        return Err(FilterError::NonFinite { what: "time step" });
    }
    if dt < 0.0 {
        return Err(FilterError::NegativeTimeStep { dt });
    }
    Ok(())
}

/// Rejects a state dimension other than 2 or 3 for the spatial part.
pub(crate) fn check_spatial_dims(dims: usize) -> Result<(), FilterError> {
    if dims == 2 || dims == 3 {
        Ok(())
    } else {
        Err(invalid(
            "motion model dimension",
            format!("{dims} spatial dimensions, expected 2 or 3"),
        ))
    }
}

/// Rejects a negative or non-finite noise level (0 is allowed: deterministic motion).
pub(crate) fn check_noise(std: f64, name: &'static str) -> Result<f64, FilterError> {
    if std >= 0.0 && std.is_finite() {
        Ok(std)
    } else {
        Err(invalid(name, format!("{std} is not a finite number >= 0")))
    }
}

/// Checks that a mean and covariance fit a state of size `n`.
pub(crate) fn check_gaussian_dims(
    mean: &DVector<f64>,
    cov: &DMatrix<f64>,
    n: usize,
) -> Result<(), FilterError> {
    if mean.len() != n {
        return Err(FilterError::DimensionMismatch {
            what: "state mean",
            expected: n,
            found: mean.len(),
        });
    }
    if cov.nrows() != n || cov.ncols() != n {
        return Err(FilterError::DimensionMismatch {
            what: "state covariance",
            expected: n,
            found: cov.nrows(),
        });
    }
    Ok(())
}

/// The `dims` components of `x` starting at `offset` as a 3-D vector, padded with
/// `pad` (missing entries of a malformed state read as `pad` rather than panicking).
pub(crate) fn padded(x: &DVector<f64>, offset: usize, dims: usize, pad: f64) -> Vector3<f64> {
    let get = |i: usize| {
        if i < dims {
            x.get(offset + i).copied().unwrap_or(pad)
        } else {
            pad
        }
    };
    Vector3::new(get(0), get(1), get(2))
}
