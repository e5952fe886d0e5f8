//! The track manager's thresholds and errors.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why the track manager rejected a configuration or an update.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TrackError {
    /// A configuration value is out of range.
    #[error("invalid track manager configuration: {0}")]
    InvalidConfig(&'static str),
    /// The time stamp is NaN or infinite.
    #[error("time stamp {0} is not finite")]
    NonFiniteTime(f64),
    /// Sets must be processed in time order.
    #[error("time stamp {now} s is earlier than the previous set's {previous} s")]
    TimeWentBackwards {
        /// The previous set's time.
        previous: f64,
        /// The offending time.
        now: f64,
    },
    /// A component weight was NaN, infinite or negative.
    #[error("component with label {label} has invalid weight {weight}")]
    InvalidWeight {
        /// Label of the offending component.
        label: u64,
        /// Its weight.
        weight: f64,
    },
}

/// Thresholds of the track manager.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrackManagerConfig {
    /// A set "hits" a label when the label's total weight exceeds this. Default
    /// 0.5, the usual extraction threshold.
    pub confirm_threshold: f64,
    /// `N`: the number of recent sets looked at for confirmation. Default 4.
    pub confirm_window: usize,
    /// `M`: hits among the last `N` sets that confirm a track. Default 2, so two
    /// sensors seeing the object, or one seeing it twice, confirm it.
    pub confirm_hits: usize,
    /// A single set whose weight for the label exceeds this confirms its track at once,
    /// without waiting for `M` hits (MATLAB `trackerPHD` confirms on one such weight, its
    /// `ConfirmationThreshold`, default 0.8). Only a sensor that sees the track counts.
    /// Default: `None` (off), confirmation by `M` of `N` only.
    #[serde(default)]
    pub confirm_at_once_threshold: Option<f64>,
    /// A label's weight below this counts toward deletion. Default 0.15: above one
    /// miss at `p_D = 0.8` (weight 0.2), below two consecutive misses (0.04).
    pub delete_threshold: f64,
    /// `K`: consecutive sets below `delete_threshold` that delete a track.
    /// Default 6.
    pub delete_after_sets: usize,
    /// Seconds below `delete_threshold` that delete a track even if fewer than `K`
    /// sets arrived (slow sensors). An interval between two sets longer than half of this
    /// is a pause in the data and does not count. Default 2.0 s.
    pub max_coast_s: f64,
}

impl Default for TrackManagerConfig {
    fn default() -> Self {
        Self {
            confirm_threshold: 0.5,
            confirm_window: 4,
            confirm_hits: 2,
            confirm_at_once_threshold: None,
            delete_threshold: 0.15,
            delete_after_sets: 6,
            max_coast_s: 2.0,
        }
    }
}

impl TrackManagerConfig {
    /// Checks that the thresholds are consistent.
    pub fn validate(&self) -> Result<(), TrackError> {
        let invalid = |reason| Err(TrackError::InvalidConfig(reason));
        if !(self.confirm_threshold.is_finite() && self.confirm_threshold > 0.0) {
            return invalid("confirm_threshold must be finite and > 0");
        }
        if !(self.delete_threshold.is_finite() && self.delete_threshold >= 0.0) {
            return invalid("delete_threshold must be finite and >= 0");
        }
        if self.delete_threshold > self.confirm_threshold {
            return invalid("delete_threshold must not exceed confirm_threshold");
        }
        if let Some(at_once) = self.confirm_at_once_threshold {
            if !(at_once.is_finite() && at_once >= self.confirm_threshold) {
                return invalid(
                    "confirm_at_once_threshold must be finite and >= confirm_threshold",
                );
            }
        }
        if self.confirm_hits == 0 || self.confirm_hits > self.confirm_window {
            return invalid("confirm_hits must be in 1..=confirm_window");
        }
        if self.delete_after_sets == 0 {
            return invalid("delete_after_sets must be >= 1");
        }
        if self.max_coast_s.is_nan() || self.max_coast_s <= 0.0 {
            return invalid("max_coast_s must be > 0 (may be infinite)");
        }
        Ok(())
    }
}
