//! One identity per object a birth component gives rise to.
//!
//! Components keep their parent's label through an update (Pham ch. 4), which is right for
//! a surviving object: its children under different measurements are rival hypotheses
//! about *one* object. A birth component is different: it stands for any number of new
//! objects near its mean (a PHD, not a single-object density), so its children under two
//! measurements may be two objects born together — Vo & Ma's demo births two targets from
//! one birth component at k = 20. Sharing the birth label, the two would be extracted as
//! one estimate until they drift apart beyond the extractor's separation gate, and the
//! second one would only then start collecting the hits that confirm a track. So in the
//! first update after its birth, each child of a newborn component under a further
//! measurement gets a label of its own; the first descendant (its missed-detection term,
//! or its first measurement's child) keeps the birth label. Where both children are the
//! same object, label association and the reducer's merge bring them back together as one
//! estimate that inherited both labels.
//!
//! Children lighter than [`SEPARATION_MIN_WEIGHT`] keep the birth label: a wide birth prior
//! (the server's grid over a room) has a child under almost every measurement, nearly all of
//! them negligible next to the objects already tracked, and a label each made the dense
//! scenario's step about a tenth slower for nothing.

use std::ops::Range;

use crate::gaussian::{GaussianMixture, LabelSource};

/// Weight below which a newborn component's child keeps the birth label: far below any
/// confirmation or extraction threshold, so it cannot be reported as an object of its own
/// before further detections have merged it with, or separated it from, its siblings.
pub(crate) const SEPARATION_MIN_WEIGHT: f64 = 0.01;

/// Gives every descendant of a newborn component (label in `newborn`) after the first, of
/// weight at least [`SEPARATION_MIN_WEIGHT`], a fresh label from `labels`. Descendants are recognised by label, in mixture order (an
/// update emits missed-detection terms first, then children measurement by measurement,
/// so two descendants sharing a birth label come from different measurements).
pub(crate) fn separate_newborn_children(
    mixture: &mut GaussianMixture,
    newborn: &Range<u64>,
    labels: &mut LabelSource,
) {
    if newborn.is_empty() {
        return;
    }
    // Newborn labels are consecutive (the births of one prediction, each of which was a
    // component): one flag each, by offset from the first.
    let mut seen = vec![false; (newborn.end - newborn.start) as usize];
    for component in &mut mixture.components {
        if !newborn.contains(&component.label.0) {
            continue;
        }
        let offset = (component.label.0 - newborn.start) as usize;
        let first = !std::mem::replace(&mut seen[offset], true);
        if !first && component.weight >= SEPARATION_MIN_WEIGHT {
            component.label = labels.fresh();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::{Gaussian, Label};
    use nalgebra::{DMatrix, DVector};

    fn component(label: u64) -> Gaussian {
        Gaussian::new(
            0.5,
            DVector::zeros(2),
            DMatrix::identity(2, 2),
            Label(label),
        )
    }

    #[test]
    fn later_children_of_a_newborn_label_get_fresh_labels() {
        let mut mixture = GaussianMixture::from_components(
            [3, 7, 3, 7, 3, 5, 7].into_iter().map(component).collect(),
        );
        mixture.components[6].weight = SEPARATION_MIN_WEIGHT / 2.0;
        let mut labels = LabelSource::starting_at(10);
        separate_newborn_children(&mut mixture, &(5..8), &mut labels);
        let got: Vec<u64> = mixture.iter().map(|c| c.label.0).collect();
        // 3 is not newborn; 7 and 5 keep their first component; the light child of 7 too.
        assert_eq!(got, vec![3, 7, 3, 10, 3, 5, 7]);
        assert_eq!(labels.peek(), 11);
    }

    #[test]
    fn nothing_changes_without_newborn_labels() {
        let mut mixture =
            GaussianMixture::from_components([1, 1, 2].into_iter().map(component).collect());
        let before = mixture.clone();
        let mut labels = LabelSource::starting_at(10);
        separate_newborn_children(&mut mixture, &(10..10), &mut labels);
        assert_eq!(mixture, before);
        assert_eq!(labels.peek(), 10);
    }
}
