//! Label continuity (Pham ch. 4): the part of the labelled tracker that carries identities
//! from one step's estimates to the next.
//!
//! Per step, after the update and reduction:
//! 1. **extract** the estimates, plus any cluster that descends from an identity no
//!    estimate carries any more ([`report_lost_identities`]: objects that crossed or were
//!    born together), each with its *inherited* labels (the labels merged into it);
//! 2. **associate** them with the previous step's estimates, predicted to now, and with the
//!    confirmed tracks that are coasting, by a minimum-total-distance assignment restricted
//!    to the inherited labels ([`associate_labels`]), and write the chosen labels back onto
//!    the components.

use std::collections::BTreeSet;

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3};
use serde::{Deserialize, Serialize};

use crate::extract::{Estimate, StateExtractor, WeightThresholdExtractor};
use crate::filter::GmPhdFilter;
use crate::gating::chi_square_quantile;
use crate::gaussian::{GaussianMixture, Label, LabelSource};
use crate::labels::{
    apply_relabelling, associate_labels, inherited_label_sets, report_lost_identities,
    CurrentEstimate, LabelSet, PreviousEstimate,
};
use crate::motion::MotionModel;
use crate::reduce::Ancestry;
use crate::tracker::{TrackerConfig, TrackerError};
use crate::tracks::TrackManager;

/// Probability mass of a coasting track's predicted position within its reach: a birth
/// inside that gate continues the track's identity ([`PreviousEstimate::reach`]).
const COASTING_REACH_PROBABILITY: f64 = 0.99;

/// A labelled estimate of the previous step, kept to carry identities to the next one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct LabelledEstimate {
    label: Label,
    mean: DVector<f64>,
    cov: DMatrix<f64>,
}

/// One step's estimates and the labels each inherited.
pub(crate) struct Extracted {
    estimates: Vec<Estimate>,
    inherited: Vec<LabelSet>,
}

/// What label continuity remembers between steps; see the module documentation.
#[derive(Debug)]
pub(crate) struct LabelContinuity {
    extractor: WeightThresholdExtractor,
    /// Mahalanobis distance within which a pre-reduction component is an estimate's ancestor.
    merge_threshold: f64,
    /// γ of a coasting track's reach, for the motion model's position size.
    coasting_gate: f64,
    /// The previous step's estimates, and their time.
    pub(crate) previous: Vec<LabelledEstimate>,
    pub(crate) previous_time: f64,
    /// Tracked labels that a current estimate took while descending from another, confirmed
    /// track's label too: a clutter return beside an object, or one of two objects that
    /// were merged. They are never confirmed on one set's weight alone
    /// ([`TrackManager::update_scoped`]).
    pub(crate) split_offs: BTreeSet<Label>,
}

impl LabelContinuity {
    /// Continuity for a filter whose motion model has `position_dims` position entries.
    pub(crate) fn new(config: &TrackerConfig, position_dims: usize) -> Self {
        Self {
            extractor: WeightThresholdExtractor {
                threshold: config.extraction_threshold,
                separation_gate: config.separation_gate,
                ..WeightThresholdExtractor::default()
            },
            merge_threshold: config.merge_threshold,
            coasting_gate: chi_square_quantile(COASTING_REACH_PROBABILITY, position_dims),
            previous: Vec::new(),
            previous_time: 0.0,
            split_offs: BTreeSet::new(),
        }
    }

    /// Step 1: the estimates of `intensity` (reduced with `ancestry`), with the lost
    /// identities of `tracks`' confirmed labels and the previous estimates', and what each
    /// inherited.
    pub(crate) fn extract(
        &self,
        intensity: &GaussianMixture,
        ancestry: &Ancestry,
        tracks: &TrackManager,
    ) -> Result<Extracted, TrackerError> {
        let mut estimates = self.extractor.extract(intensity)?;
        let inherited = match ancestry {
            Ancestry::Recorded(sets) => {
                let identities = self
                    .previous
                    .iter()
                    .map(|e| e.label)
                    .chain(tracks.confirmed_tracks().map(|track| track.label))
                    .collect();
                let threshold = self.extractor.threshold;
                report_lost_identities(intensity, sets, &identities, threshold, &mut estimates);
                // Pham's l̃ᴱ: the labels merged into the estimate's component, and its own.
                let inherit = |estimate: &Estimate| {
                    let mut set = sets.get(estimate.source).cloned().unwrap_or_default();
                    set.insert(estimate.label, 0.0);
                    set
                };
                estimates.iter().map(inherit).collect()
            }
            Ancestry::PreReduction(before_reduction) => {
                inherited_label_sets(before_reduction, &estimates, self.merge_threshold)?
            }
        };
        Ok(Extracted {
            estimates,
            inherited,
        })
    }

    /// Step 2: labels the `extracted` estimates of time `t` to continue the previous ones
    /// and `tracks`' coasting identities, writes them onto the filter's components and
    /// remembers the estimates for the next step.
    pub(crate) fn associate(
        &mut self,
        t: f64,
        extracted: Extracted,
        filter: &mut GmPhdFilter,
        tracks: &TrackManager,
    ) -> Result<(), TrackerError> {
        let Extracted {
            estimates,
            inherited,
        } = extracted;
        let motion = filter.motion();
        let previous = self.predicted(t, motion, tracks)?;
        let descends_from_confirmed: Vec<bool> = inherited
            .iter()
            .map(|set| {
                set.heaviest()
                    .is_some_and(|label| tracks.is_confirmed(label))
            })
            .collect();
        let current: Vec<CurrentEstimate> = estimates
            .iter()
            .zip(inherited)
            .map(|(estimate, inherited)| CurrentEstimate {
                mean: position(motion, &estimate.mean),
                weight: estimate.weight,
                inherited,
            })
            .collect();
        let mut source = LabelSource::starting_at(filter.next_label());
        let relabelling = associate_labels(&previous, &current, &mut source)?;
        // `apply_relabelling` checks its input before it changes anything, so on error the
        // intensity is untouched.
        filter.relabel_intensity(|mixture| {
            apply_relabelling(mixture, &estimates, &relabelling, &mut source)
        })?;
        for (&label, descends) in relabelling.labels.iter().zip(descends_from_confirmed) {
            if descends && !tracks.is_confirmed(label) {
                self.split_offs.insert(label);
            }
        }
        self.previous = estimates
            .into_iter()
            .zip(&relabelling.labels)
            .map(|(estimate, &label)| LabelledEstimate {
                label,
                mean: estimate.mean,
                cov: estimate.cov,
            })
            .collect();
        self.previous_time = t;
        Ok(())
    }

    /// Forgets the split-offs whose track is gone.
    pub(crate) fn forget_split_offs(&mut self, tracks: &TrackManager) {
        self.split_offs
            .retain(|&label| tracks.tracks().any(|track| track.label == label));
    }

    /// The identities a current estimate may continue, predicted to `t`: the previous
    /// estimates, then the confirmed tracks that gave no estimate last time (coasting
    /// through misses or a pause in the data). Those compete too: otherwise the birth that
    /// explains the object's next detection better than the weakened track would take it
    /// over under a new label. They are predicted from their anchor (the label's heaviest
    /// component in the last set in which it had weight enough not to be a clutter return's
    /// child) and reach as far as their predicted position's validation gate
    /// ([`PreviousEstimate::reach`]).
    fn predicted(
        &self,
        t: f64,
        motion: &dyn MotionModel,
        tracks: &TrackManager,
    ) -> Result<Vec<PreviousEstimate>, TrackerError> {
        let dt = (t - self.previous_time).max(0.0);
        let mut previous = Vec::with_capacity(self.previous.len());
        for estimate in &self.previous {
            let (predicted, _) = motion.predict(&estimate.mean, &estimate.cov, dt)?;
            previous.push(PreviousEstimate {
                label: estimate.label,
                predicted: position(motion, &predicted),
                established: tracks.is_confirmed(estimate.label),
                reach: 0.0,
            });
        }
        let dims = motion.position_dims();
        for track in tracks.confirmed_tracks() {
            if self.previous.iter().any(|e| e.label == track.label) {
                continue;
            }
            let (mean, cov, since) = match tracks.anchor(track.label) {
                Some(anchor) => (&anchor.mean, &anchor.cov, anchor.time_s),
                None => (&track.mean, &track.cov, self.previous_time),
            };
            let (predicted, cov) = motion.predict(mean, cov, (t - since).max(0.0))?;
            let spread = largest_eigenvalue(&cov, dims);
            previous.push(PreviousEstimate {
                label: track.label,
                predicted: position(motion, &predicted),
                established: true,
                reach: (self.coasting_gate * spread.max(0.0)).sqrt(),
            });
        }
        Ok(previous)
    }
}

/// The world position of state `x`, as the vector label association compares.
fn position(motion: &dyn MotionModel, x: &DVector<f64>) -> DVector<f64> {
    DVector::from_column_slice(motion.position(x).as_slice())
}

/// The largest eigenvalue of the leading `dims` × `dims` block of the symmetric `cov`: for the
/// usual 2 or 3 position dimensions, of a fixed-size copy (nalgebra's algorithm either way,
/// so the same value, without the heap).
fn largest_eigenvalue(cov: &DMatrix<f64>, dims: usize) -> f64 {
    let block = cov.view((0, 0), (dims, dims));
    match dims {
        2 => Matrix2::from_fn(|r, c| block[(r, c)])
            .symmetric_eigenvalues()
            .max(),
        3 => Matrix3::from_fn(|r, c| block[(r, c)])
            .symmetric_eigenvalues()
            .max(),
        _ => block.clone_owned().symmetric_eigenvalues().max(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_eigenvalue_is_nalgebras_on_any_size() {
        for dims in 1..=4 {
            for seed in 0..5 {
                let a = DMatrix::from_fn(6, 6, |r, c| ((r * 5 + c * 11 + seed) % 17) as f64 * 0.3);
                let cov = &a * a.transpose();
                let dynamic = cov
                    .view((0, 0), (dims, dims))
                    .clone_owned()
                    .symmetric_eigenvalues()
                    .max();
                assert_eq!(largest_eigenvalue(&cov, dims).to_bits(), dynamic.to_bits());
            }
        }
    }
}
