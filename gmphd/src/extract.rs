//! State extraction: turning the PHD intensity into a set of labelled estimates.
//!
//! Vo & Ma (2006, Table III) report the mean of every component whose weight
//! exceeds 0.5, repeated `round(w)` times, because a component of weight 2 stands
//! for two objects at the same place. With labelled components and several sensors
//! updating one intensity (Pham ch. 7.4), one object's mass is spread over several
//! components sharing its label (one per measurement hypothesis plus the
//! missed-detection term); Pham takes, per label, the component of largest weight.
//!
//! [`WeightThresholdExtractor`] does both, selected by [`Grouping`]:
//!
//! * [`Grouping::ByLabel`] (default): components are grouped by label; the group's
//!   mass `W` (the **sum** of its weights — the expected number of objects carrying
//!   that label) is compared with the threshold. A group yields `max(1, round(W))`
//!   estimates; each is placed at the component with the most mass not yet used
//!   (take the heaviest, subtract 1, repeat), so a label split across measurement
//!   hypotheses yields one estimate at its heaviest component, and a birth label
//!   that caught two objects yields two estimates at its two heaviest components.
//!   Summing rather than taking the maximum keeps an object whose mass is split
//!   between two nearby measurements (e.g. 0.45 + 0.45) from vanishing.
//! * [`Grouping::PerComponent`]: Vo & Ma verbatim, component by component.
//!
//! Copies: the first estimate of a group (or component) has `copy_index` 0 and owns
//! the label; further copies (`copy_index` ≥ 1) stand for other objects that only
//! *descend* from that label. They carry it as ancestry, and label association
//! ([`crate::labels`]) gives them a label of their own.

use crate::gaussian::{GaussianMixture, Label};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use thiserror::Error;

/// Why extraction failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ExtractError {
    /// A component weight was NaN, infinite or negative.
    #[error("component with label {label} has invalid weight {weight}")]
    InvalidWeight {
        /// Label of the offending component.
        label: u64,
        /// Its weight.
        weight: f64,
    },
}

/// One extracted object estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Label of the component the estimate comes from (its identity when
    /// `copy_index == 0`, its ancestry otherwise).
    pub label: Label,
    /// 0 for the estimate that owns `label`; 1, 2, … for extra copies that stand
    /// for further objects of the same label group (or component).
    pub copy_index: u32,
    /// Index, in the extracted mixture, of the component the estimate was read
    /// from (so labels can be written back, see [`crate::labels::apply_relabelling`]).
    pub source: usize,
    /// Mass this estimate stands for: its group's (or component's) weight shared
    /// equally among the group's estimates.
    pub weight: f64,
    /// Mean state of the source component.
    pub mean: DVector<f64>,
    /// Covariance of the source component.
    pub cov: DMatrix<f64>,
}

impl Estimate {
    /// True for an extra copy that must not keep `label` as its identity.
    pub fn is_extra_copy(&self) -> bool {
        self.copy_index > 0
    }
}

/// Turns an intensity into estimates.
pub trait StateExtractor {
    /// Estimates in the intensity, sorted by `(label, copy_index)`.
    fn extract(&self, intensity: &GaussianMixture) -> Result<Vec<Estimate>, ExtractError>;
}

/// How components are grouped before thresholding; see the module docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Grouping {
    /// Sum weights per label, place `round(sum)` estimates at the heaviest members.
    #[default]
    ByLabel,
    /// Vo & Ma: each component on its own, `round(w)` copies of its mean.
    PerComponent,
}

/// Weight-threshold extraction (Vo & Ma 2006; Pham ch. 7.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WeightThresholdExtractor {
    /// A group (or component) yields estimates when its weight is strictly greater
    /// than this. Default 0.5.
    pub threshold: f64,
    /// Grouping of components. Default [`Grouping::ByLabel`].
    pub grouping: Grouping,
    /// Upper bound on estimates from one group (or component), so that a corrupt
    /// weight cannot allocate without bound. Default 100.
    pub max_copies: u32,
}

impl Default for WeightThresholdExtractor {
    fn default() -> Self {
        Self {
            threshold: 0.5,
            grouping: Grouping::ByLabel,
            max_copies: 100,
        }
    }
}

impl WeightThresholdExtractor {
    /// Number of estimates a mass `weight` above the threshold stands for.
    fn copies(&self, weight: f64) -> u32 {
        let rounded = weight.round().clamp(1.0, f64::from(self.max_copies.max(1)));
        rounded as u32
    }
}

impl StateExtractor for WeightThresholdExtractor {
    fn extract(&self, intensity: &GaussianMixture) -> Result<Vec<Estimate>, ExtractError> {
        if let Some(bad) = intensity
            .iter()
            .find(|c| !c.weight.is_finite() || c.weight < 0.0)
        {
            return Err(ExtractError::InvalidWeight {
                label: bad.label.0,
                weight: bad.weight,
            });
        }
        let mut estimates = Vec::new();
        match self.grouping {
            Grouping::PerComponent => {
                let above = intensity
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.weight > self.threshold);
                for (index, component) in above {
                    let copies = self.copies(component.weight);
                    for copy_index in 0..copies {
                        estimates.push(Estimate {
                            label: component.label,
                            copy_index,
                            source: index,
                            weight: component.weight / f64::from(copies),
                            mean: component.mean.clone(),
                            cov: component.cov.clone(),
                        });
                    }
                }
            }
            Grouping::ByLabel => {
                let mut groups: BTreeMap<Label, Vec<usize>> = BTreeMap::new();
                for (index, component) in intensity.iter().enumerate() {
                    groups.entry(component.label).or_default().push(index);
                }
                for (label, members) in groups {
                    let mass: f64 = members
                        .iter()
                        .map(|&i| intensity.components[i].weight)
                        .sum();
                    if mass <= self.threshold {
                        continue;
                    }
                    let copies = self.copies(mass);
                    // Remaining mass per member; each estimate goes to the member with
                    // the most left, which then gives up one object's worth.
                    let mut remaining: Vec<f64> = members
                        .iter()
                        .map(|&i| intensity.components[i].weight)
                        .collect();
                    for copy_index in 0..copies {
                        let best = (0..members.len())
                            .max_by(|&a, &b| remaining[a].total_cmp(&remaining[b]))
                            .unwrap_or(0);
                        remaining[best] -= 1.0;
                        let component = &intensity.components[members[best]];
                        estimates.push(Estimate {
                            label,
                            copy_index,
                            source: members[best],
                            weight: mass / f64::from(copies),
                            mean: component.mean.clone(),
                            cov: component.cov.clone(),
                        });
                    }
                }
            }
        }
        estimates.sort_by_key(|e| (e.label, e.copy_index));
        Ok(estimates)
    }
}
