//! State extraction: turning the PHD intensity into a set of labelled estimates.
//!
//! Vo & Ma (2006, Table III) report the mean of every component whose weight
//! exceeds 0.5, repeated `round(w)` times, because a component of weight 2 stands
//! for two objects at the same place. With labelled components and several sensors
//! updating one intensity (Pham ch. 7.4), one object's mass is spread over several
//! components sharing its label (one per measurement hypothesis plus the
//! missed-detection term); Pham takes, per label, the component of largest weight.
//!
//! [`WeightThresholdExtractor`] does either, selected by [`Grouping`]:
//!
//! * [`Grouping::ByLabel`] (default, Pham 7.4): components are grouped by label. A
//!   label is reported when its mass — the **sum** of its weights, the expected
//!   number of objects carrying it — exceeds the threshold (summing rather than
//!   taking the maximum keeps an object whose mass is split between two nearby
//!   measurements, 0.45 + 0.45, from vanishing). Its estimate is the heaviest
//!   member. A further member is reported as an extra estimate only when its own
//!   weight exceeds the threshold *and* it lies farther than `separation_gate`
//!   (squared Mahalanobis distance under the sum of both covariances) from every
//!   member already reported — two objects born from one birth component.
//!   Nearby heavy members are not reported: a clutter return within a few σ of an
//!   object gives the object's label a second component of weight ≈ 1 for a scan,
//!   and reporting it (as `round(W)` would) gives the clutter an identity of its
//!   own, to which the object's identity moves whenever the clutter happened to be
//!   the heavier. In the crossing-objects experiment of Pham ch. 4.4
//!   (`tests/labels_pham_example2.rs`) that raised the mean number of labels per
//!   true track from ≈ 1.05 to ≈ 1.5. The price: two objects merged into one
//!   component (weight ≈ 2) are reported once until they separate.
//! * [`Grouping::PerComponent`]: Vo & Ma verbatim, component by component, with
//!   `round(w)` copies; labels may repeat.
//!
//! Copies: the first estimate of a group (or component) has `copy_index` 0 and owns
//! the label; further estimates (`copy_index` ≥ 1) stand for other objects that
//! only *descend* from that label. They carry it as ancestry, and label
//! association ([`crate::labels`]) gives them a label of their own.

use crate::gaussian::{Gaussian, GaussianMixture, Label};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
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
    /// Mass this estimate stands for. [`Grouping::ByLabel`]: an extra estimate its
    /// own component's weight, the owner the rest of the label's mass.
    /// [`Grouping::PerComponent`]: the component's weight shared among its copies.
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
    /// Pham 7.4: per label, the heaviest component, plus well-separated heavy members.
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
    /// [`Grouping::ByLabel`]: squared Mahalanobis distance (full state, sum of the
    /// two covariances) beyond which a second heavy member of a label counts as a
    /// separate object. Default 25 (5 σ).
    pub separation_gate: f64,
}

impl Default for WeightThresholdExtractor {
    fn default() -> Self {
        Self {
            threshold: 0.5,
            grouping: Grouping::ByLabel,
            max_copies: 100,
            separation_gate: 25.0,
        }
    }
}

impl WeightThresholdExtractor {
    /// True when two components of one label are too far apart to be one object.
    /// A singular covariance sum counts as separated only for distinct means.
    fn separated(&self, a: &Gaussian, b: &Gaussian) -> bool {
        let diff = &a.mean - &b.mean;
        match (&a.cov + &b.cov).cholesky() {
            Some(factor) => diff.dot(&factor.solve(&diff)) > self.separation_gate,
            None => diff.norm() > 0.0,
        }
    }

    /// Number of estimates a mass `weight` above the threshold stands for.
    fn copies(&self, weight: f64) -> u32 {
        let rounded = weight.round().clamp(1.0, f64::from(self.max_copies.max(1)));
        rounded as u32
    }
}

impl StateExtractor for WeightThresholdExtractor {
    fn extract(&self, intensity: &GaussianMixture) -> Result<Vec<Estimate>, ExtractError> {
        if let Some(bad) = intensity.first_invalid_weight() {
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
                let weight = |i: usize| intensity.components[i].weight;
                let by_label = intensity.indices_by_label();
                for group in by_label.chunk_by(|a, b| a.0 == b.0) {
                    let label = group[0].0;
                    let mass: f64 = group.iter().map(|&(_, i)| weight(i)).sum();
                    if mass <= self.threshold {
                        continue;
                    }
                    let mut members: Vec<usize> = group.iter().map(|&(_, i)| i).collect();
                    members.sort_by(|&a, &b| weight(b).total_cmp(&weight(a)));
                    let mut reported = vec![members[0]];
                    for &candidate in &members[1..] {
                        if reported.len() >= self.max_copies.max(1) as usize
                            || weight(candidate) <= self.threshold
                        {
                            break;
                        }
                        let separate = reported.iter().all(|&r| {
                            self.separated(
                                &intensity.components[r],
                                &intensity.components[candidate],
                            )
                        });
                        if separate {
                            reported.push(candidate);
                        }
                    }
                    let extras: f64 = reported[1..].iter().map(|&i| weight(i)).sum();
                    for (copy_index, &index) in (0u32..).zip(&reported) {
                        let component = &intensity.components[index];
                        estimates.push(Estimate {
                            label,
                            copy_index,
                            source: index,
                            // The owner stands for the label's mass not claimed by extras.
                            weight: if copy_index == 0 {
                                mass - extras
                            } else {
                                component.weight
                            },
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
