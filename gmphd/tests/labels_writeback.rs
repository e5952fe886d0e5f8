//! Deriving inherited label sets from a pre-reduction mixture and writing chosen
//! labels back onto components.

use gmphd::extract::{Estimate, Grouping, StateExtractor, WeightThresholdExtractor};
use gmphd::labels::{
    apply_relabelling, associate_labels, inherited_label_sets, LabelError, LabelOrigin,
    PreviousEstimate, Relabelling,
};
use gmphd::{Gaussian, GaussianMixture, Label, LabelSource};
use nalgebra::{DMatrix, DVector};

fn component(weight: f64, x: f64, y: f64, label: u64) -> Gaussian {
    Gaussian::new(
        weight,
        DVector::from_vec(vec![x, y]),
        DMatrix::identity(2, 2),
        Label(label),
    )
}

fn labels_of(mixture: &GaussianMixture) -> Vec<u64> {
    mixture.iter().map(|c| c.label.0).collect()
}

#[test]
fn inherited_sets_collect_labels_within_the_merge_gate() {
    // Before reduction: labels 1 and 2 close together (they will merge), 3 far off.
    let pre = GaussianMixture::from_components(vec![
        component(0.6, 0.0, 0.0, 1),
        component(0.4, 1.0, 0.0, 2),
        component(0.9, 30.0, 0.0, 3),
    ]);
    // After reduction the merged component carries label 1 only.
    let post = GaussianMixture::from_components(vec![
        component(1.0, 0.4, 0.0, 1),
        component(0.9, 30.0, 0.0, 3),
    ]);
    let estimates = WeightThresholdExtractor::default().extract(&post).unwrap();
    let sets = inherited_label_sets(&pre, &estimates, 4.0).unwrap();
    assert!(sets[0].contains(Label(1)) && sets[0].contains(Label(2)));
    assert!(!sets[0].contains(Label(3)));
    assert_eq!(sets[1].len(), 1);
    assert!(sets[1].contains(Label(3)));

    let singular = GaussianMixture::from_components(vec![Gaussian::new(
        1.0,
        DVector::zeros(2),
        DMatrix::zeros(2, 2),
        Label(8),
    )]);
    assert_eq!(
        inherited_label_sets(&singular, &estimates, 4.0),
        Err(LabelError::SingularCovariance(8))
    );
}

/// The full cycle on a swap: two objects merged under label 1, separate again;
/// the merged label's component is matched to previous object 2 and a component
/// labelled 2 to object 1, so labels swap on the mixture, including on the light
/// components that follow each group.
#[test]
fn relabelling_swaps_groups_on_the_mixture() {
    let mut mixture = GaussianMixture::from_components(vec![
        component(0.9, 10.0, 0.0, 1),
        component(0.05, 10.5, 0.0, 1),
        component(0.9, 0.0, 0.0, 2),
    ]);
    let estimates = WeightThresholdExtractor::default()
        .extract(&mixture)
        .unwrap();
    let relabelling = Relabelling {
        labels: vec![Label(2), Label(1)],
        origins: vec![
            LabelOrigin::Matched { previous: 1 },
            LabelOrigin::Matched { previous: 0 },
        ],
    };
    let mut source = LabelSource::starting_at(50);
    apply_relabelling(&mut mixture, &estimates, &relabelling, &mut source).unwrap();
    assert_eq!(labels_of(&mixture), vec![2, 2, 1]);
    assert_eq!(source.peek(), 50);
}

/// A weight-2 component yields two Vo & Ma estimates; the extra copy gets a fresh label,
/// and the component is split so that each identity owns half of it.
#[test]
fn a_component_with_two_objects_is_split_between_their_labels() {
    let mut mixture = GaussianMixture::from_components(vec![component(1.9, 5.0, 5.0, 4)]);
    let vo_ma = WeightThresholdExtractor {
        grouping: Grouping::PerComponent,
        ..WeightThresholdExtractor::default()
    };
    let estimates = vo_ma.extract(&mixture).unwrap();
    assert_eq!(estimates.len(), 2);
    assert!(estimates[1].is_extra_copy());
    let previous = vec![PreviousEstimate {
        label: Label(4),
        predicted: DVector::from_vec(vec![5.0, 5.0]),
        established: true,
        reach: 0.0,
    }];
    let current = estimates
        .iter()
        .map(|e| gmphd::labels::CurrentEstimate {
            mean: e.mean.clone(),
            weight: e.weight,
            inherited: gmphd::labels::LabelSet::single(e.label, e.weight),
        })
        .collect::<Vec<_>>();
    let mut source = LabelSource::starting_at(30);
    let relabelling = associate_labels(&previous, &current, &mut source).unwrap();
    assert_eq!(relabelling.labels, vec![Label(4), Label(30)]);
    apply_relabelling(&mut mixture, &estimates, &relabelling, &mut source).unwrap();
    assert_eq!(labels_of(&mixture), vec![4, 30]);
    assert!(mixture.iter().all(|c| (c.weight - 0.95).abs() < 1e-12));
}

/// A light component whose label was given to another group gets a fresh label,
/// so a label never names two groups.
#[test]
fn displaced_light_components_get_a_fresh_label() {
    let mut mixture = GaussianMixture::from_components(vec![
        component(0.95, 0.0, 0.0, 5),
        component(0.2, 40.0, 0.0, 6),
    ]);
    let extractor = WeightThresholdExtractor {
        grouping: Grouping::ByLabel,
        ..WeightThresholdExtractor::default()
    };
    let estimates = extractor.extract(&mixture).unwrap();
    assert_eq!(estimates.len(), 1);
    let relabelling = Relabelling {
        labels: vec![Label(6)],
        origins: vec![LabelOrigin::Matched { previous: 0 }],
    };
    let mut source = LabelSource::starting_at(70);
    apply_relabelling(&mut mixture, &estimates, &relabelling, &mut source).unwrap();
    assert_eq!(labels_of(&mixture), vec![6, 70]);
}

#[test]
fn writeback_rejects_mismatched_input() {
    let mut mixture = GaussianMixture::from_components(vec![component(0.9, 0.0, 0.0, 1)]);
    let estimate = Estimate {
        label: Label(1),
        copy_index: 0,
        source: 3,
        weight: 0.9,
        mean: DVector::zeros(2),
        cov: DMatrix::identity(2, 2),
    };
    let relabelling = Relabelling {
        labels: vec![Label(1)],
        origins: vec![LabelOrigin::Inherited],
    };
    let mut source = LabelSource::default();
    assert_eq!(
        apply_relabelling(
            &mut mixture,
            std::slice::from_ref(&estimate),
            &relabelling,
            &mut source
        ),
        Err(LabelError::SourceOutOfRange { index: 3, len: 1 })
    );
    assert_eq!(
        apply_relabelling(
            &mut mixture,
            &[estimate.clone(), estimate],
            &relabelling,
            &mut source
        ),
        Err(LabelError::LengthMismatch {
            estimates: 2,
            labels: 1
        })
    );
}
