//! Estimates for identities that merging would otherwise lose.
//!
//! The reducer gives a merged cluster the label of its heaviest member. When two objects
//! come close (objects crossing, or two born from one birth component), both their
//! labels' children fall into the same clusters, and every cluster may end up with the
//! *same* label even after the objects separate again. Extraction by label
//! ([`crate::extract::Grouping::ByLabel`]) then reports one estimate until the two
//! clusters lie beyond its separation gate, which is wide on purpose: a clutter return near
//! an object also gives the object's label a second heavy component for a scan, and that
//! must not become an object. What tells the two cases apart is the clusters' ancestry: a
//! cluster that descends from an identity the previous step reported, which no current
//! estimate carries any more, is that object — clutter next to an object descends from the
//! object's own identity only. Such a cluster is reported as a further estimate, and label
//! association ([`super::associate_labels`]) can hand it the identity back.

use super::{label_position, LabelSet};
use crate::extract::Estimate;
use crate::gaussian::{GaussianMixture, Label};
use std::collections::BTreeSet;

/// Adds to `estimates` (sorted by `(label, copy_index)`, as extracted from `mixture`) one
/// estimate for each heavy component (weight above `threshold`) that is no estimate's
/// source, belongs to a label that gave an estimate, and whose `inherited` labels (by
/// component index) include one of `identities` that no estimate carries as its own
/// label. Heaviest components are considered first; each lost identity is used up by the
/// first component that carries it. The new estimate is an extra copy of its label and its
/// weight is moved from the label's owning estimate. Returns how many were added.
pub fn report_lost_identities(
    mixture: &GaussianMixture,
    inherited: &[LabelSet],
    identities: &BTreeSet<Label>,
    threshold: f64,
    estimates: &mut Vec<Estimate>,
) -> usize {
    // Sorted lists and flags rather than trees: a few dozen labels, every set.
    let mut given: Vec<(Label, u32)> = estimates.iter().map(|e| (e.label, e.copy_index)).collect();
    given.sort_unstable();
    let gave = |label: &Label| label_position(&given, *label).is_some();
    let mut lost: Vec<Label> = identities.iter().copied().filter(|l| !gave(l)).collect();
    if lost.is_empty() {
        return 0;
    }
    // Next copy index per label that gave an estimate (one past its largest).
    let mut next_copy: Vec<(Label, u32)> = given
        .chunk_by(|a, b| a.0 == b.0)
        .map(|run| {
            (
                run[0].0,
                run.iter().map(|&(_, copy)| copy + 1).max().unwrap_or(0),
            )
        })
        .collect();
    let mut reported = vec![false; mixture.len()];
    for estimate in estimates.iter() {
        if let Some(flag) = reported.get_mut(estimate.source) {
            *flag = true;
        }
    }
    let mut candidates: Vec<usize> = (0..mixture.len())
        .filter(|&i| {
            let component = &mixture.components[i];
            component.weight > threshold && !reported[i] && gave(&component.label)
        })
        .collect();
    candidates.sort_by(|&a, &b| {
        let weight = |i: usize| mixture.components[i].weight;
        weight(b).total_cmp(&weight(a)).then(a.cmp(&b))
    });
    let mut added = 0;
    for index in candidates {
        let Some(set) = inherited.get(index) else {
            continue;
        };
        let before = lost.len();
        lost.retain(|&l| !set.contains(l));
        if lost.len() == before {
            continue;
        }
        let component = &mixture.components[index];
        let copy_index = label_position(&next_copy, component.label).map(|k| {
            let next = &mut next_copy[k].1;
            *next += 1;
            *next - 1
        });
        if let Some(owner) = estimates
            .iter_mut()
            .find(|e| e.label == component.label && e.copy_index == 0)
        {
            owner.weight = (owner.weight - component.weight).max(0.0);
        }
        estimates.push(Estimate {
            label: component.label,
            copy_index: copy_index.unwrap_or(1),
            source: index,
            weight: component.weight,
            mean: component.mean.clone(),
            cov: component.cov.clone(),
        });
        added += 1;
        if lost.is_empty() {
            break;
        }
    }
    estimates.sort_by_key(|e| (e.label, e.copy_index));
    added
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::{StateExtractor, WeightThresholdExtractor};
    use crate::gaussian::Gaussian;
    use nalgebra::{DMatrix, DVector};

    /// Two heavy components of label 1, 3 m apart (inside the extractor's separation gate).
    fn two_close_members() -> GaussianMixture {
        let member = |x: f64, weight: f64| {
            Gaussian::new(
                weight,
                DVector::from_vec(vec![x, 0.0]),
                DMatrix::identity(2, 2),
                Label(1),
            )
        };
        GaussianMixture::from_components(vec![member(0.0, 0.95), member(3.0, 0.9)])
    }

    fn extracted(mixture: &GaussianMixture) -> Vec<Estimate> {
        let estimates = WeightThresholdExtractor::default()
            .extract(mixture)
            .unwrap();
        assert_eq!(
            estimates.len(),
            1,
            "one estimate inside the separation gate"
        );
        estimates
    }

    #[test]
    fn a_cluster_descending_from_a_lost_identity_is_reported() {
        let mixture = two_close_members();
        let mut estimates = extracted(&mixture);
        // The second cluster also descends from label 2, which the previous step reported.
        let inherited = vec![
            LabelSet::single(Label(1), 0.9),
            [(Label(1), 0.5), (Label(2), 0.4)].into_iter().collect(),
        ];
        let identities = BTreeSet::from([Label(1), Label(2)]);
        let added = report_lost_identities(&mixture, &inherited, &identities, 0.5, &mut estimates);
        assert_eq!(added, 1);
        assert_eq!(estimates.len(), 2);
        let extra = &estimates[1];
        assert_eq!(
            (extra.label, extra.copy_index, extra.source),
            (Label(1), 1, 1)
        );
        assert!((extra.weight - 0.9).abs() < 1e-12);
        // The owner keeps the rest of the label's mass.
        assert!((estimates[0].weight - 0.95).abs() < 1e-12);
    }

    #[test]
    fn clutter_beside_an_object_descends_from_no_lost_identity() {
        let mixture = two_close_members();
        let mut estimates = extracted(&mixture);
        let inherited = vec![
            LabelSet::single(Label(1), 0.9),
            LabelSet::single(Label(1), 0.9),
        ];
        // Label 3 was reported before but nothing here descends from it.
        let identities = BTreeSet::from([Label(1), Label(3)]);
        let added = report_lost_identities(&mixture, &inherited, &identities, 0.5, &mut estimates);
        assert_eq!(added, 0);
        assert_eq!(estimates.len(), 1);
    }

    #[test]
    fn light_components_are_never_reported() {
        let mut mixture = two_close_members();
        mixture.components[1].weight = 0.3;
        let mut estimates = extracted(&mixture);
        let inherited = vec![
            LabelSet::single(Label(1), 0.9),
            [(Label(1), 0.1), (Label(2), 0.2)].into_iter().collect(),
        ];
        let identities = BTreeSet::from([Label(1), Label(2)]);
        let added = report_lost_identities(&mixture, &inherited, &identities, 0.5, &mut estimates);
        assert_eq!(added, 0);
    }
}
