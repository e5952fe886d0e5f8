//! State extraction (Vo & Ma; Pham ch. 7.4): threshold, round(w) copies, grouping
//! by label with separated heavy members.

use gmphd::extract::{ExtractError, Grouping, StateExtractor, WeightThresholdExtractor};
use gmphd::{Gaussian, GaussianMixture, Label};
use nalgebra::{DMatrix, DVector};

fn component(weight: f64, x: f64, label: u64) -> Gaussian {
    Gaussian::new(
        weight,
        DVector::from_vec(vec![x, 0.0]),
        DMatrix::identity(2, 2),
        Label(label),
    )
}

fn per_component() -> WeightThresholdExtractor {
    WeightThresholdExtractor {
        grouping: Grouping::PerComponent,
        ..WeightThresholdExtractor::default()
    }
}

#[test]
fn vo_ma_extraction_thresholds_and_repeats_round_w_times() {
    let mixture = GaussianMixture::from_components(vec![
        component(0.49, 0.0, 1),
        component(0.51, 1.0, 2),
        component(2.4, 2.0, 3),
        component(1.6, 3.0, 4),
    ]);
    let estimates = per_component().extract(&mixture).unwrap();
    let summary: Vec<(u64, u32)> = estimates
        .iter()
        .map(|e| (e.label.0, e.copy_index))
        .collect();
    assert_eq!(summary, vec![(2, 0), (3, 0), (3, 1), (4, 0), (4, 1)]);
    // Copies share the component's mass equally and sit at its mean.
    assert!((estimates[1].weight - 1.2).abs() < 1e-12);
    assert_eq!(estimates[1].mean, estimates[2].mean);
    assert_eq!(estimates[2].source, 2);
}

/// Pham 7.4: after a multi-sensor update one label's mass is spread over several
/// components; per label, the heaviest component gives the estimate, and the
/// label's *summed* mass decides whether it is reported.
#[test]
fn by_label_reports_the_heaviest_component_of_each_label() {
    let mixture = GaussianMixture::from_components(vec![
        component(0.45, 0.0, 1),
        component(0.40, 0.3, 1),
        component(0.10, 5.0, 1),
        component(0.30, 9.0, 2),
    ]);
    let estimates = WeightThresholdExtractor::default()
        .extract(&mixture)
        .unwrap();
    assert_eq!(
        estimates.len(),
        1,
        "label 1 (0.95) is reported, label 2 (0.3) not"
    );
    assert_eq!(estimates[0].label, Label(1));
    assert_eq!(estimates[0].mean[0], 0.0);
    assert!((estimates[0].weight - 0.95).abs() < 1e-12);
    // Per component, no single member of label 1 exceeds 0.5: the object vanishes.
    assert!(per_component().extract(&mixture).unwrap().is_empty());
}

/// A birth label that caught two objects far apart: both heavy members are
/// reported, the second flagged as an extra estimate.
#[test]
fn by_label_reports_well_separated_heavy_members_separately() {
    let mixture = GaussianMixture::from_components(vec![
        component(0.9, 0.0, 7),
        component(0.95, 20.0, 7),
        component(0.1, 40.0, 7),
    ]);
    let estimates = WeightThresholdExtractor::default()
        .extract(&mixture)
        .unwrap();
    assert_eq!(estimates.len(), 2);
    assert_eq!((estimates[0].copy_index, estimates[0].mean[0]), (0, 20.0));
    assert_eq!((estimates[1].copy_index, estimates[1].mean[0]), (1, 0.0));
    assert!(estimates[1].is_extra_copy());
    // The owner carries the label's mass not claimed by the extra estimate.
    assert!((estimates[0].weight - 1.05).abs() < 1e-12);
    assert!((estimates[1].weight - 0.9).abs() < 1e-12);
}

/// A clutter return next to an object gives its label a second heavy component
/// close by (squared Mahalanobis 4.5 < 25): one object, one estimate. A merged
/// component of weight 2 is likewise reported once per label.
#[test]
fn by_label_does_not_report_nearby_heavy_members_or_round_w_copies() {
    let duplicate =
        GaussianMixture::from_components(vec![component(1.0, 0.0, 3), component(0.98, 3.0, 3)]);
    let estimates = WeightThresholdExtractor::default()
        .extract(&duplicate)
        .unwrap();
    assert_eq!(estimates.len(), 1);
    assert_eq!(estimates[0].mean[0], 0.0);
    let merged = GaussianMixture::from_components(vec![component(2.0, 0.0, 4)]);
    assert_eq!(
        WeightThresholdExtractor::default()
            .extract(&merged)
            .unwrap()
            .len(),
        1
    );
    assert_eq!(per_component().extract(&merged).unwrap().len(), 2);
}

#[test]
fn copies_are_capped_and_bad_weights_rejected() {
    let capped = WeightThresholdExtractor {
        max_copies: 3,
        ..per_component()
    };
    let heavy = GaussianMixture::from_components(vec![component(1e6, 0.0, 1)]);
    assert_eq!(capped.extract(&heavy).unwrap().len(), 3);
    let bad = GaussianMixture::from_components(vec![component(f64::NAN, 0.0, 9)]);
    assert!(matches!(
        capped.extract(&bad),
        Err(ExtractError::InvalidWeight { label: 9, .. })
    ));
    assert!(capped.extract(&GaussianMixture::new()).unwrap().is_empty());
}
