//! The one error type of the filter crate.

use thiserror::Error;

/// Everything that can go wrong when configuring or running the GM-PHD filter.
///
/// Bad input (a malformed model, a measurement of the wrong size, time running
/// backwards) is reported here instead of panicking, so that a long-running
/// service can reject one bad message and carry on.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FilterError {
    /// A configuration parameter is outside its valid range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// Why it is rejected.
        reason: String,
    },
    /// A vector or matrix does not have the size the model expects.
    #[error("{what} has dimension {found}, expected {expected}")]
    DimensionMismatch {
        /// What was being checked.
        what: &'static str,
        /// The size the model needs.
        expected: usize,
        /// The size that was given.
        found: usize,
    },
    /// A value that must be finite is NaN or infinite.
    #[error("{what} contains a non-finite value")]
    NonFinite {
        /// What was being checked.
        what: &'static str,
    },
    /// A covariance is not symmetric positive definite.
    #[error("{what} is not a symmetric positive definite matrix")]
    NotPositiveDefinite {
        /// What was being checked.
        what: &'static str,
    },
    /// A prediction was asked for a time before the filter's last time stamp.
    #[error("time went backwards: filter is at t = {last}, asked to predict to t = {requested}")]
    TimeWentBackwards {
        /// The filter's current time stamp.
        last: f64,
        /// The requested time stamp.
        requested: f64,
    },
    /// A motion model was asked to predict over a negative time step.
    #[error("negative time step dt = {dt}")]
    NegativeTimeStep {
        /// The offending time step.
        dt: f64,
    },
}

/// Shorthand for an [`FilterError::InvalidParameter`].
pub(crate) fn invalid(name: &'static str, reason: impl Into<String>) -> FilterError {
    FilterError::InvalidParameter {
        name,
        reason: reason.into(),
    }
}
