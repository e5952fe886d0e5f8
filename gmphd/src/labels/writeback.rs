//! Bridges between label association and the mixture: deriving the labels an
//! estimate inherited, and writing the chosen labels back onto components.

use super::{label_position, LabelError, LabelSet, Relabelling};
use crate::extract::Estimate;
use crate::gaussian::{Gaussian, GaussianMixture, Label, LabelSource};
use crate::linalg::MahalanobisGate;
use crate::sweep::IntervalHits;
use nalgebra::DMatrix;
use std::collections::BTreeMap;

/// The inherited label set of each estimate, derived from the mixture *before*
/// reduction (Pham's `l̃ᴱ`).
///
/// Merging replaces a cluster of components by one, losing the members' labels.
/// This recovers them with the merge criterion itself (Vo & Ma, Table II): a
/// pre-reduction component `c` counts as an ancestor of estimate `x̂` when
/// `(m_c − x̂)ᵀ P_c⁻¹ (m_c − x̂) ≤ merge_threshold`, and contributes its weight to
/// its label. The estimate's own label is always in its set (with weight 0 unless
/// a contributing component carries it). Using the estimate's
/// mean in place of the (unknown) heaviest member's mean makes this approximate at
/// the cluster's edge; [`crate::reduce::PruneMergeCap`] records its clusters
/// ([`crate::reduce::Reducer::reduce_recording`]), and the tracker uses those exact sets;
/// this is the fallback for reducers that do not.
///
/// A covariance that is not positive definite is an error when it has a non-positive
/// variance, or when its component is close enough to an estimate to be tested.
pub fn inherited_label_sets(
    pre_reduction: &GaussianMixture,
    estimates: &[Estimate],
    merge_threshold: f64,
) -> Result<Vec<LabelSet>, LabelError> {
    super::check_states(
        pre_reduction
            .iter()
            .map(|c| &c.mean)
            .chain(estimates.iter().map(|e| &e.mean)),
    )?;
    // A non-positive variance rules out a positive definite covariance wherever the
    // component lies; other defects are found when a component is close enough to an
    // estimate to need its factor.
    if let Some(bad) = pre_reduction
        .iter()
        .find(|c| c.cov.diagonal().iter().any(|v| *v <= 0.0 || v.is_nan()))
    {
        return Err(LabelError::SingularCovariance(bad.label.0));
    }
    let mut gates = vec![MahalanobisGate::default(); pre_reduction.len()];
    let mut scratch = Vec::new();
    // The gate fails when the first coordinate alone is farther than √(U P₀₀): only the
    // components within that of an estimate are tested (in component order, as a full
    // scan would visit them).
    let queries: Vec<Option<f64>> = estimates.iter().map(|e| e.mean.get(0).copied()).collect();
    let near = IntervalHits::build(
        &queries,
        pre_reduction.iter().map(|c| {
            let centre = c.mean.get(0).copied().unwrap_or(f64::NAN);
            let variance = c.cov.get((0, 0)).copied().unwrap_or(f64::NAN);
            (centre, (merge_threshold * variance).sqrt())
        }),
    );
    estimates
        .iter()
        .enumerate()
        .map(|(e, estimate)| {
            // Weights come from the contributing components only, so that the
            // fallback label (the heaviest in the set) is Pham's "largest weight
            // Gaussian contributing to this component".
            let mut set = LabelSet::single(estimate.label, 0.0);
            for c in near.hits(e).iter().map(|&c| c as usize) {
                let (component, gate) = (&pre_reduction.components[c], &mut gates[c]);
                // No repair: a singular covariance is an error here.
                let strict = |_: &DMatrix<f64>| None;
                let close = gate.contains(
                    &component.cov,
                    &component.mean,
                    &estimate.mean,
                    merge_threshold,
                    &mut scratch,
                    strict,
                );
                match close {
                    None => return Err(LabelError::SingularCovariance(component.label.0)),
                    Some(true) => set.insert(component.label, component.weight),
                    Some(false) => {}
                }
            }
            Ok(set)
        })
        .collect()
}

/// Writes the labels chosen by [`super::associate_labels`] back onto the mixture
/// the `estimates` were extracted from.
///
/// * Each estimate's source component takes the estimate's new label. A component
///   that is the source of `k > 1` estimates (a weight-2 component yields two
///   copies) is split into `k` equal-weight copies, one per new label, so that
///   every identity owns a component of its own.
/// * Every other component whose old label was the label of an owning estimate
///   (`copy_index == 0`) follows that estimate's new label (the heaviest such
///   estimate's, if several components shared the old label).
/// * A remaining component whose old label is now used by a different group gets a
///   fresh label from `source`, so that labels keep naming one group each; all
///   other components keep their labels.
pub fn apply_relabelling(
    mixture: &mut GaussianMixture,
    estimates: &[Estimate],
    relabelling: &Relabelling,
    source: &mut LabelSource,
) -> Result<(), LabelError> {
    if estimates.len() != relabelling.labels.len() {
        return Err(LabelError::LengthMismatch {
            estimates: estimates.len(),
            labels: relabelling.labels.len(),
        });
    }
    let len = mixture.len();
    if let Some(bad) = estimates.iter().find(|e| e.source >= len) {
        return Err(LabelError::SourceOutOfRange {
            index: bad.source,
            len,
        });
    }

    // (source component, new label) in source order, each source's labels in estimate
    // order: walked alongside the mixture instead of looked up per component.
    let mut labels_by_source: Vec<(usize, Label)> = estimates
        .iter()
        .map(|e| e.source)
        .zip(relabelling.labels.iter().copied())
        .collect();
    labels_by_source.sort_by_key(|&(source, _)| source);
    let group_rename = group_renames(estimates, relabelling);
    let renamed = |label: Label| label_position(&group_rename, label).map(|k| group_rename[k].1);
    let mut claimed: Vec<Label> = relabelling.labels.clone();
    claimed.sort_unstable();
    let is_claimed = |label: Label| claimed.binary_search(&label).is_ok();

    let old = std::mem::take(&mut mixture.components);
    // A split source adds a component per extra copy.
    mixture.components.reserve(old.len() + estimates.len());
    let mut fresh_for: BTreeMap<Label, Label> = BTreeMap::new();
    let mut sources = labels_by_source.as_slice();
    for (index, component) in old.into_iter().enumerate() {
        let count = sources
            .iter()
            .take_while(|(source, _)| *source == index)
            .count();
        if count > 0 {
            let (new_labels, rest) = sources.split_at(count);
            sources = rest;
            let share = component.weight / count as f64;
            let (&(_, last_label), copies) = new_labels.split_last().expect("count > 0");
            for &(_, label) in copies {
                mixture.components.push(Gaussian {
                    weight: share,
                    label,
                    ..component.clone()
                });
            }
            // The last (usually the only) estimate of the source takes the component itself.
            mixture.components.push(Gaussian {
                weight: share,
                label: last_label,
                ..component
            });
            continue;
        }
        let label = match renamed(component.label) {
            Some(renamed) => renamed,
            None if is_claimed(component.label) => *fresh_for
                .entry(component.label)
                .or_insert_with(|| super::fresh_unused(source, is_claimed)),
            None => component.label,
        };
        mixture.components.push(Gaussian { label, ..component });
    }
    Ok(())
}

/// Each owning estimate's old label → its new one (the heaviest owner's, the first of
/// equal weights), sorted by old label (looked up by binary search).
fn group_renames(estimates: &[Estimate], relabelling: &Relabelling) -> Vec<(Label, Label)> {
    let mut owners: Vec<(Label, f64, Label)> = estimates
        .iter()
        .zip(&relabelling.labels)
        .filter(|(estimate, _)| !estimate.is_extra_copy())
        .map(|(estimate, &new_label)| (estimate.label, estimate.weight, new_label))
        .collect();
    // (Stable: owners of one label stay in estimate order.)
    owners.sort_by_key(|&(label, _, _)| label);
    owners
        .chunk_by(|a, b| a.0 == b.0)
        .map(|run| {
            // The first of the heaviest: a later owner replaces it only when strictly heavier.
            let heaviest = run
                .iter()
                .copied()
                .reduce(|best, owner| if owner.1 > best.1 { owner } else { best })
                .expect("a run is not empty");
            (heaviest.0, heaviest.2)
        })
        .collect()
}
