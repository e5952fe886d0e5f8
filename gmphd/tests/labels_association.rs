//! Pham ch. 4 label association: minimum total distance, inherited-label
//! restriction, fallbacks for unmatched estimates.

use gmphd::labels::{
    associate_labels, CurrentEstimate, LabelError, LabelOrigin, LabelSet, PreviousEstimate,
    Relabelling,
};
use gmphd::{Label, LabelSource};
use nalgebra::DVector;

fn at(x: f64, y: f64) -> DVector<f64> {
    DVector::from_vec(vec![x, y])
}

fn previous(label: u64, x: f64, y: f64) -> PreviousEstimate {
    PreviousEstimate {
        label: Label(label),
        predicted: at(x, y),
        established: true,
        reach: 0.0,
    }
}

fn current(x: f64, y: f64, weight: f64, inherited: &[(u64, f64)]) -> CurrentEstimate {
    CurrentEstimate {
        mean: at(x, y),
        weight,
        inherited: inherited.iter().map(|&(l, w)| (Label(l), w)).collect(),
    }
}

/// True when every current estimate took a previous estimate's label.
fn all_matched(result: &Relabelling) -> bool {
    result
        .origins
        .iter()
        .all(|o| matches!(o, LabelOrigin::Matched { .. }))
}

/// Greedy nearest-neighbour: repeatedly take the globally closest free pair.
fn greedy_labels(previous: &[PreviousEstimate], current: &[CurrentEstimate]) -> Vec<Option<Label>> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (j, p) in previous.iter().enumerate() {
        for (i, c) in current.iter().enumerate() {
            if c.inherited.contains(p.label) {
                pairs.push(((&c.mean - &p.predicted).norm(), j, i));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut labels = vec![None; current.len()];
    let mut used = vec![false; previous.len()];
    for (_, j, i) in pairs {
        if !used[j] && labels[i].is_none() {
            used[j] = true;
            labels[i] = Some(previous[j].label);
        }
    }
    labels
}

/// Two objects crossing: A predicted at (0,0), B at (2,0). They were merged, so
/// both current estimates inherited both labels. Now at (1.1,0) and (3.5,0).
/// Greedy takes the closest pair first, B–(1.1,0) at 0.9, leaving A–(3.5,0) at
/// 3.5 (total 4.4): the identities swap. The minimum total distance pairs
/// A–(1.1,0) at 1.1 and B–(3.5,0) at 1.5 (total 2.6).
#[test]
fn crossing_targets_minimum_total_beats_nearest_neighbour() {
    let prev = vec![previous(1, 0.0, 0.0), previous(2, 2.0, 0.0)];
    let both = [(1, 0.5), (2, 0.5)];
    let cur = vec![current(1.1, 0.0, 1.0, &both), current(3.5, 0.0, 1.0, &both)];

    let greedy = greedy_labels(&prev, &cur);
    assert_eq!(
        greedy,
        vec![Some(Label(2)), Some(Label(1))],
        "greedy swaps identities"
    );

    let mut source = LabelSource::starting_at(100);
    let result = associate_labels(&prev, &cur, &mut source).unwrap();
    assert_eq!(result.labels, vec![Label(1), Label(2)]);
    assert_eq!(
        result.origins,
        vec![
            LabelOrigin::Matched { previous: 0 },
            LabelOrigin::Matched { previous: 1 }
        ]
    );
    assert_eq!(source.peek(), 100, "no fresh label needed");
}

/// Pham Fig. 4.3: choosing the cheapest edges leaves vertices unmatched; the
/// matching must be maximum before it is minimum. a, b, c at 0, 10, 20; d, e, f
/// at 9, 19, 29; each estimate inherited only its two nearest labels.
#[test]
fn matching_is_maximum_before_minimum() {
    let prev = vec![
        previous(1, 0.0, 0.0),
        previous(2, 10.0, 0.0),
        previous(3, 20.0, 0.0),
    ];
    let cur = vec![
        current(9.0, 0.0, 1.0, &[(1, 0.5), (2, 0.5)]),
        current(19.0, 0.0, 1.0, &[(2, 0.5), (3, 0.5)]),
        current(29.0, 0.0, 1.0, &[(3, 1.0)]),
    ];
    let result = associate_labels(&prev, &cur, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(1), Label(2), Label(3)]);
    assert!(all_matched(&result));
}

/// An object seen again after a pause: its confirmed track (label 1) coasted far from it,
/// a birth at its first new detection (tentative label 2) sits on it, and the two merged
/// into one estimate that inherited both labels. The established identity continues, though
/// the tentative one is nearer; among tentative labels alone the nearer still wins, and
/// the preference never costs a pair.
#[test]
fn established_labels_continue_before_tentative_ones() {
    let tentative = |label, x| PreviousEstimate {
        established: false,
        ..previous(label, x, 0.0)
    };
    let both = [(1, 0.9), (2, 1.0)];
    let merged = vec![current(0.0, 0.0, 1.9, &both)];

    let prev = vec![previous(1, 1.2, 0.0), tentative(2, 0.01)];
    let result = associate_labels(&prev, &merged, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(1)]);

    let prev = vec![tentative(1, 1.2), tentative(2, 0.01)];
    let result = associate_labels(&prev, &merged, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(2)]);

    // Two estimates: the established label goes to the one only it can continue, so both
    // are matched rather than the established label taking the contested estimate.
    let prev = vec![previous(1, 1.2, 0.0), tentative(2, 0.01)];
    let cur = vec![
        current(0.0, 0.0, 1.0, &both),
        current(3.0, 0.0, 1.0, &[(1, 1.0)]),
    ];
    let result = associate_labels(&prev, &cur, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(2), Label(1)]);
    assert!(all_matched(&result));
}

/// A coasting established identity (no estimate last time) continues into an estimate of
/// newborn descent within its reach — the object's birth after its track lost its mass —
/// but not beyond the reach, and never into an estimate that continues an established
/// identity of its own.
#[test]
fn a_coasting_identity_reaches_a_newborn_estimate() {
    let coasting = PreviousEstimate {
        reach: 1.0,
        ..previous(1, 0.0, 0.0)
    };
    let newborn = |x| current(x, 0.0, 0.9, &[(9, 0.9)]);

    let result = associate_labels(
        std::slice::from_ref(&coasting),
        &[newborn(0.5)],
        &mut LabelSource::default(),
    )
    .unwrap();
    assert_eq!(result.labels, vec![Label(1)]);
    assert_eq!(result.origins, vec![LabelOrigin::Matched { previous: 0 }]);

    let result = associate_labels(
        std::slice::from_ref(&coasting),
        &[newborn(2.0)],
        &mut LabelSource::default(),
    )
    .unwrap();
    assert_eq!(result.labels, vec![Label(9)]);
    assert_eq!(result.origins, vec![LabelOrigin::Inherited]);

    // Label 3 is another established identity: its estimate stays its own.
    let prev = vec![coasting, previous(3, 10.0, 0.0)];
    let cur = vec![current(0.5, 0.0, 0.9, &[(3, 0.9)])];
    let result = associate_labels(&prev, &cur, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(3)]);
}

/// An estimate may only take a label it inherited, even when another previous
/// estimate is much closer.
#[test]
fn labels_are_restricted_to_inherited_sets() {
    let prev = vec![previous(1, 0.0, 0.0), previous(2, 50.0, 0.0)];
    // Sits on top of A's prediction but descends only from B.
    let cur = vec![current(0.2, 0.0, 1.0, &[(2, 1.0)])];
    let result = associate_labels(&prev, &cur, &mut LabelSource::default()).unwrap();
    assert_eq!(result.labels, vec![Label(2)]);
    assert_eq!(result.origins, vec![LabelOrigin::Matched { previous: 1 }]);
}

#[test]
fn a_new_object_keeps_its_birth_label_or_gets_a_fresh_one() {
    let prev = vec![previous(1, 0.0, 0.0)];
    let cur = vec![
        current(0.1, 0.0, 0.9, &[(1, 0.9)]),
        // Born from birth component 7, never estimated before: keeps 7.
        current(40.0, 0.0, 0.8, &[(7, 0.8)]),
        // Extra copy of label 1 (a weight-2 component): 1 is taken, so fresh.
        current(0.1, 0.0, 0.6, &[(1, 0.6)]),
    ];
    let mut source = LabelSource::starting_at(20);
    let result = associate_labels(&prev, &cur, &mut source).unwrap();
    assert_eq!(result.labels, vec![Label(1), Label(7), Label(20)]);
    assert_eq!(
        result.origins,
        vec![
            LabelOrigin::Matched { previous: 0 },
            LabelOrigin::Inherited,
            LabelOrigin::Fresh
        ]
    );
}

/// Unmatched estimates pick the heaviest inherited label still free, heavier
/// estimates first.
#[test]
fn unmatched_estimates_take_their_heaviest_free_ancestor() {
    let cur = vec![
        current(0.0, 0.0, 0.7, &[(4, 0.2), (5, 0.5)]),
        current(9.0, 0.0, 1.2, &[(5, 0.9), (4, 0.3)]),
    ];
    let result = associate_labels(&[], &cur, &mut LabelSource::default()).unwrap();
    // The heavier estimate (index 1) chooses first and takes 5; index 0 gets 4.
    assert_eq!(result.labels, vec![Label(4), Label(5)]);
}

#[test]
fn label_set_merges_weights_and_orders_heaviest_first() {
    let mut set = LabelSet::single(Label(3), 0.2);
    set.insert(Label(9), 0.5);
    set.insert(Label(3), 0.4);
    assert_eq!(set.len(), 2);
    let ordered = set.heaviest_first();
    assert_eq!(
        ordered.iter().map(|m| m.0).collect::<Vec<_>>(),
        vec![Label(3), Label(9)]
    );
    assert!((ordered[0].1 - 0.6).abs() < 1e-12);
    assert!(set.contains(Label(9)) && !set.contains(Label(4)));
}

#[test]
fn bad_input_is_a_typed_error() {
    let mut source = LabelSource::default();
    let dup = vec![previous(1, 0.0, 0.0), previous(1, 5.0, 0.0)];
    assert_eq!(
        associate_labels(&dup, &[], &mut source),
        Err(LabelError::DuplicatePreviousLabel(1))
    );
    let cur3 = vec![CurrentEstimate {
        mean: DVector::from_vec(vec![0.0, 0.0, 0.0]),
        weight: 1.0,
        inherited: LabelSet::single(Label(1), 1.0),
    }];
    assert!(matches!(
        associate_labels(&[previous(1, 0.0, 0.0)], &cur3, &mut source),
        Err(LabelError::DimensionMismatch {
            expected: 2,
            found: 3
        })
    ));
    let nan = vec![current(f64::NAN, 0.0, 1.0, &[(1, 1.0)])];
    assert_eq!(
        associate_labels(&[], &nan, &mut source),
        Err(LabelError::NonFiniteState)
    );
}
