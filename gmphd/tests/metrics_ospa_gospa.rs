//! OSPA and GOSPA against hand-computed cases, brute force and their metric
//! properties.

use gmphd::metrics::{gospa, ospa, MetricError, MetricParams};
use nalgebra::DVector;
use proptest::prelude::*;

fn points(coords: &[(f64, f64)]) -> Vec<DVector<f64>> {
    coords
        .iter()
        .map(|&(x, y)| DVector::from_vec(vec![x, y]))
        .collect()
}

fn params(cutoff: f64, order: f64) -> MetricParams {
    MetricParams::new(cutoff, order).expect("valid metric parameters")
}

const TOL: f64 = 1e-9;

#[test]
fn empty_sets_are_at_distance_zero() {
    let o = ospa(&[], &[], params(5.0, 2.0)).unwrap();
    assert_eq!((o.distance, o.localisation, o.cardinality), (0.0, 0.0, 0.0));
    let g = gospa(&[], &[], params(5.0, 2.0)).unwrap();
    assert_eq!(g.distance, 0.0);
    assert_eq!((g.missed_count, g.false_count, g.assigned), (0, 0, 0));
}

#[test]
fn one_empty_set_gives_the_cutoff() {
    let x = points(&[(0.0, 0.0), (3.0, 4.0), (-7.0, 1.0)]);
    let o = ospa(&x, &[], params(5.0, 2.0)).unwrap();
    assert!((o.distance - 5.0).abs() < TOL);
    assert!((o.cardinality - 5.0).abs() < TOL);
    assert_eq!(o.localisation, 0.0);
    // GOSPA: three misses at c^p/2 each: (3 · 25 / 2)^(1/2).
    let g = gospa(&x, &[], params(5.0, 2.0)).unwrap();
    assert!((g.distance - 37.5_f64.sqrt()).abs() < TOL);
    assert_eq!(g.missed_count, 3);
    assert!((g.missed - 37.5).abs() < TOL);
}

/// X = {(0,0), (10,0)}, Y = {(1,0), (10,2), (50,50)}, c = 5, p = 2.
/// Optimal pairs: (0,0)–(1,0) at 1 and (10,0)–(10,2) at 2; (50,50) is left over.
/// OSPA: n = 3, Σ d^p = 1 + 4 = 5, cardinality term c^p (n − m) = 25.
///   distance = √((5 + 25)/3) = √10, localisation = √(5/3), cardinality = √(25/3).
/// GOSPA: localisation 5, missed 0, false 25/2 = 12.5, distance = √17.5.
#[test]
fn two_versus_three_by_hand() {
    let x = points(&[(0.0, 0.0), (10.0, 0.0)]);
    let y = points(&[(1.0, 0.0), (10.0, 2.0), (50.0, 50.0)]);
    let o = ospa(&x, &y, params(5.0, 2.0)).unwrap();
    assert!((o.distance - 10.0_f64.sqrt()).abs() < TOL, "{o:?}");
    assert!((o.localisation - (5.0_f64 / 3.0).sqrt()).abs() < TOL);
    assert!((o.cardinality - (25.0_f64 / 3.0).sqrt()).abs() < TOL);

    let g = gospa(&x, &y, params(5.0, 2.0)).unwrap();
    assert!((g.localisation - 5.0).abs() < TOL, "{g:?}");
    assert_eq!(g.missed, 0.0);
    assert!((g.false_targets - 12.5).abs() < TOL);
    assert!((g.distance - 17.5_f64.sqrt()).abs() < TOL);
    assert_eq!((g.assigned, g.missed_count, g.false_count), (2, 0, 1));
}

/// A pair beyond the cut-off is one miss plus one false target in GOSPA and a
/// cut-off error in OSPA. X = {(0,0), (1,0)}, Y = {(0,1), (20,0)}, c = 4, p = 1:
/// (0,0)–(0,1) at 1 is assigned; (1,0)–(20,0) at 19 ≥ c is not.
/// OSPA = (1 + 4)/2 = 2.5 with no cardinality part; GOSPA = 1 + 2 + 2 = 5.
#[test]
fn pair_beyond_cutoff_splits_into_miss_and_false() {
    let x = points(&[(0.0, 0.0), (1.0, 0.0)]);
    let y = points(&[(0.0, 1.0), (20.0, 0.0)]);
    let o = ospa(&x, &y, params(4.0, 1.0)).unwrap();
    assert!((o.distance - 2.5).abs() < TOL, "{o:?}");
    assert_eq!(o.cardinality, 0.0);
    let g = gospa(&x, &y, params(4.0, 1.0)).unwrap();
    assert!((g.distance - 5.0).abs() < TOL, "{g:?}");
    assert_eq!((g.assigned, g.missed_count, g.false_count), (1, 1, 1));
    assert!((g.localisation - 1.0).abs() < TOL);
}

#[test]
fn gospa_power_is_the_sum_of_its_parts() {
    let x = points(&[(0.0, 0.0), (4.0, 4.0), (9.0, -2.0), (30.0, 0.0)]);
    let y = points(&[(0.5, 0.2), (4.5, 3.0), (-9.0, -2.0)]);
    for order in [1.0, 2.0, 3.0] {
        let g = gospa(&x, &y, params(6.0, order)).unwrap();
        let sum = g.localisation + g.missed + g.false_targets;
        assert!(
            (g.distance.powf(order) - sum).abs() < 1e-9 * sum.max(1.0),
            "{g:?}"
        );
    }
}

#[test]
fn gospa_swaps_missed_and_false_when_arguments_swap() {
    let x = points(&[(0.0, 0.0), (4.0, 4.0), (30.0, 0.0)]);
    let y = points(&[(0.5, 0.2)]);
    let forward = gospa(&x, &y, params(5.0, 2.0)).unwrap();
    let backward = gospa(&y, &x, params(5.0, 2.0)).unwrap();
    assert!((forward.distance - backward.distance).abs() < TOL);
    assert_eq!(forward.missed_count, backward.false_count);
    assert_eq!(forward.false_count, backward.missed_count);
}

#[test]
fn bad_input_is_a_typed_error() {
    let x = points(&[(0.0, 0.0)]);
    let three_d = vec![DVector::from_vec(vec![0.0, 0.0, 0.0])];
    assert!(matches!(
        ospa(&x, &three_d, params(5.0, 2.0)),
        Err(MetricError::DimensionMismatch {
            expected: 2,
            found: 3
        })
    ));
    assert!(matches!(
        MetricParams::new(0.0, 2.0),
        Err(MetricError::InvalidCutoff(_))
    ));
    assert!(matches!(
        MetricParams::new(1.0, 0.5),
        Err(MetricError::InvalidOrder(_))
    ));
    let nan = points(&[(f64::NAN, 0.0)]);
    assert!(matches!(
        gospa(&x, &nan, params(5.0, 2.0)),
        Err(MetricError::NonFinitePoint)
    ));
}

/// OSPA by enumerating every injective map from the smaller set into the larger.
fn brute_force_ospa(x: &[DVector<f64>], y: &[DVector<f64>], c: f64, p: f64) -> f64 {
    let (small, large) = if x.len() <= y.len() { (x, y) } else { (y, x) };
    let n = large.len();
    if n == 0 {
        return 0.0;
    }
    fn best(
        small: &[DVector<f64>],
        large: &[DVector<f64>],
        used: &mut Vec<bool>,
        c: f64,
        p: f64,
    ) -> f64 {
        let Some((first, rest)) = small.split_first() else {
            return 0.0;
        };
        let mut min = f64::INFINITY;
        for j in 0..large.len() {
            if !used[j] {
                used[j] = true;
                let cost =
                    (first - &large[j]).norm().min(c).powf(p) + best(rest, large, used, c, p);
                min = min.min(cost);
                used[j] = false;
            }
        }
        min
    }
    let loc = best(small, large, &mut vec![false; n], c, p);
    ((loc + c.powf(p) * (n - small.len()) as f64) / n as f64).powf(1.0 / p)
}

fn point_set() -> impl Strategy<Value = Vec<DVector<f64>>> {
    prop::collection::vec((-20.0..20.0f64, -20.0..20.0f64), 0..6).prop_map(|coords| points(&coords))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

    #[test]
    fn ospa_is_a_bounded_symmetric_metric(x in point_set(), y in point_set(), c in 0.5..15.0f64, p in 1.0..3.0f64) {
        let params = MetricParams::new(c, p).unwrap();
        let d = ospa(&x, &y, params).unwrap().distance;
        prop_assert!((0.0..=c + TOL).contains(&d));
        prop_assert!((d - ospa(&y, &x, params).unwrap().distance).abs() < TOL);
        prop_assert!(ospa(&x, &x, params).unwrap().distance.abs() < TOL);
        prop_assert!((d - brute_force_ospa(&x, &y, c, p)).abs() < 1e-6 * c);
    }

    #[test]
    fn gospa_is_symmetric_and_zero_on_equal_sets(x in point_set(), y in point_set(), c in 0.5..15.0f64, p in 1.0..3.0f64) {
        let params = MetricParams::new(c, p).unwrap();
        let d = gospa(&x, &y, params).unwrap().distance;
        prop_assert!(d >= 0.0);
        prop_assert!((d - gospa(&y, &x, params).unwrap().distance).abs() < TOL);
        prop_assert!(gospa(&x, &x, params).unwrap().distance.abs() < TOL);
    }
}
