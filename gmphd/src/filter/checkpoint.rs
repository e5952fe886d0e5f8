//! The filter's checkpoint: what it holds and how the filter resumes from it.

use std::ops::Range;

use serde::{Deserialize, Serialize};

use super::GmPhdFilter;
use crate::adaptive_birth::BirthCandidate;
use crate::error::{invalid, FilterError};
use crate::gaussian::{GaussianMixture, LabelSource};
use crate::linalg::{check_finite_vector, check_spd};

/// What a checkpoint holds: enough to resume the filter exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilterState {
    /// The current intensity.
    pub intensity: GaussianMixture,
    /// Time stamp (s) the intensity refers to.
    pub time: f64,
    /// The next label the filter will hand out.
    pub next_label: u64,
    /// Measurement-driven births waiting for the next prediction (empty without
    /// adaptive birth; absent in checkpoints of older versions).
    #[serde(default)]
    pub pending_births: Vec<BirthCandidate>,
    /// Seconds of static birth not yet added (see [`GmPhdFilter::with_birth_interval`];
    /// absent in checkpoints of older versions).
    #[serde(default)]
    pub birth_owed_s: f64,
    /// Labels handed out by the latest prediction, whose children a further update at the
    /// same time stamp separates (module `newborn`; absent in older checkpoints).
    #[serde(default)]
    pub newborn_labels: Range<u64>,
}

impl GmPhdFilter {
    /// A checkpoint of the filter.
    pub fn state(&self) -> FilterState {
        FilterState {
            intensity: self.intensity.clone(),
            time: self.time,
            next_label: self.labels.peek(),
            pending_births: self
                .adaptive_birth
                .as_ref()
                .map(|adaptive| adaptive.pending().to_vec())
                .unwrap_or_default(),
            birth_owed_s: self.birth_owed_s,
            newborn_labels: self.newborn.clone(),
        }
    }

    /// Resumes from a checkpoint taken with [`GmPhdFilter::state`] (models and
    /// configuration are not part of it). The label source continues after both
    /// the saved next label and every label in the intensity. Pending births are
    /// restored when adaptive birth is enabled and ignored otherwise.
    pub fn restore(&mut self, state: FilterState) -> Result<(), FilterError> {
        if !state.time.is_finite() {
            return Err(FilterError::NonFinite {
                what: "checkpoint time",
            });
        }
        self.validate_mixture(&state.intensity)?;
        if let Some(adaptive) = &mut self.adaptive_birth {
            adaptive.restore(state.pending_births, self.motion.state_dim())?;
        }
        self.labels = LabelSource::starting_at(state.next_label);
        self.skip_used_labels(&state.intensity);
        self.intensity = state.intensity;
        self.time = state.time;
        self.newborn = state.newborn_labels;
        self.birth_owed_s = if state.birth_owed_s.is_finite() {
            state.birth_owed_s.max(0.0)
        } else {
            0.0
        };
        Ok(())
    }

    /// Refuses a mixture whose weights, means or covariances this filter cannot take.
    pub(super) fn validate_mixture(&self, mixture: &GaussianMixture) -> Result<(), FilterError> {
        let n = self.motion.state_dim();
        for component in mixture.iter() {
            if !(component.weight >= 0.0 && component.weight.is_finite()) {
                return Err(invalid(
                    "component weight",
                    format!("{} is not a finite number >= 0", component.weight),
                ));
            }
            if component.dim() != n {
                return Err(FilterError::DimensionMismatch {
                    what: "component mean",
                    expected: n,
                    found: component.dim(),
                });
            }
            check_finite_vector(&component.mean, "component mean")?;
            check_spd(&component.cov, n, "component covariance")?;
        }
        Ok(())
    }

    /// Moves the label source past every label `mixture` uses.
    pub(super) fn skip_used_labels(&mut self, mixture: &GaussianMixture) {
        let highest = mixture.iter().map(|c| c.label.0).max().unwrap_or(0);
        if highest >= self.labels.peek() {
            self.labels = LabelSource::starting_at(highest + 1);
        }
    }
}
