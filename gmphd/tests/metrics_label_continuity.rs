//! The label-continuity accumulator: distinct labels per true track and switches.

use gmphd::metrics::{LabelContinuity, MetricError};
use gmphd::Label;
use nalgebra::DVector;

fn at(x: f64, y: f64) -> DVector<f64> {
    DVector::from_vec(vec![x, y])
}

#[test]
fn counts_distinct_labels_and_switches() {
    let mut continuity = LabelContinuity::new();
    assert_eq!(continuity.mean_labels_per_track(), None);
    // Truth 1 keeps label 10 throughout; truth 2 goes 20 → 21 → 20 (two switches,
    // two distinct labels).
    for label_of_two in [20, 20, 21, 20] {
        continuity.record(1, Label(10));
        continuity.record(2, Label(label_of_two));
    }
    assert_eq!(continuity.label_switches(), 2);
    assert_eq!(continuity.tracks_seen(), 2);
    assert_eq!(continuity.total_labels(), 3);
    assert_eq!(continuity.mean_labels_per_track(), Some(1.5));
}

#[test]
fn a_gap_without_a_change_is_not_a_switch() {
    let mut continuity = LabelContinuity::new();
    continuity.record(7, Label(3));
    // Step with no association for truth 7, then the same label again.
    continuity.record(7, Label(3));
    assert_eq!(continuity.label_switches(), 0);
    assert_eq!(continuity.mean_labels_per_track(), Some(1.0));
}

#[test]
fn associate_step_uses_optimal_assignment_within_cutoff() {
    let mut continuity = LabelContinuity::new();
    let truths = vec![(1, at(0.0, 0.0)), (2, at(2.0, 0.0)), (3, at(100.0, 0.0))];
    // Greedy nearest-neighbour would give label 5 (at 1.1, distance 0.9 from truth 2)
    // to truth 2 and leave truth 1 with label 6 at distance 3.5; the optimal
    // assignment pairs 1–5 (1.1) and 2–6 (1.5). Truth 3 has nothing within 5.
    let estimates = vec![(Label(5), at(1.1, 0.0)), (Label(6), at(3.5, 0.0))];
    let pairs = continuity.associate_step(&truths, &estimates, 5.0).unwrap();
    assert_eq!(pairs, vec![(1, Label(5)), (2, Label(6))]);
    assert_eq!(continuity.tracks_seen(), 2);

    let far = vec![(Label(9), at(50.0, 50.0))];
    assert!(continuity
        .associate_step(&truths, &far, 5.0)
        .unwrap()
        .is_empty());
    assert!(matches!(
        continuity.associate_step(&truths, &estimates, f64::NAN),
        Err(MetricError::InvalidCutoff(_))
    ));
}
