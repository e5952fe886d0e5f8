//! Mixture reduction: pruning, merging and capping (Vo & Ma 2006, Table II).

use std::cmp::Ordering;
use std::fmt::Debug;

use nalgebra::{DMatrix, DVector};

use crate::error::{invalid, FilterError};
use crate::gaussian::{Gaussian, GaussianMixture, Label};
use crate::labels::LabelSet;
use clusters::Clusters;
use merge::merge;

mod clusters;
mod merge;

/// Where the labels that merging replaced can be found (Pham's inherited label sets).
#[derive(Debug, Clone, PartialEq)]
pub enum Ancestry {
    /// Per component of the reduced mixture, the labels of the components merged into it,
    /// each with their summed weight.
    Recorded(Vec<LabelSet>),
    /// The mixture before reduction, for [`crate::labels::inherited_label_sets`] to
    /// derive them from (a reducer that does not record its merges).
    PreReduction(GaussianMixture),
}

/// A reduced mixture and its [`Ancestry`].
#[derive(Debug, Clone, PartialEq)]
pub struct Reduction {
    /// The reduced mixture.
    pub mixture: GaussianMixture,
    /// What each of its components descends from.
    pub ancestry: Ancestry,
}

/// Keeps the number of Gaussian components bounded between updates.
pub trait Reducer: Send + Sync + Debug {
    /// The reduced mixture.
    fn reduce(&self, mixture: &GaussianMixture) -> GaussianMixture;

    /// Reduces `mixture`, which the caller no longer needs, and says what each output
    /// component descends from. The default keeps the input as [`Ancestry::PreReduction`].
    fn reduce_recording(&self, mixture: GaussianMixture) -> Reduction {
        Reduction {
            mixture: self.reduce(&mixture),
            ancestry: Ancestry::PreReduction(mixture),
        }
    }

    /// Components of at most this weight never survive [`Reducer::reduce`] (0 unless the
    /// reducer prunes), so an update reduced at once need not emit them.
    fn prune_threshold(&self) -> f64 {
        0.0
    }
}

/// Vo & Ma's reduction: drop components with weight ≤ T, merge every component
/// within squared Mahalanobis distance U of the heaviest remaining one, keep at
/// most J_max of the heaviest.
///
/// Deterministic: components are visited by weight (descending), ties broken by
/// label then position in the input. A merged component takes the label of its
/// heaviest member, so a track's identity survives merging.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PruneMergeCap {
    prune_threshold: f64,
    merge_threshold: f64,
    max_components: usize,
}

impl PruneMergeCap {
    /// `prune_threshold` T ≥ 0, `merge_threshold` U ≥ 0 (squared Mahalanobis
    /// distance), `max_components` J_max ≥ 1.
    pub fn new(
        prune_threshold: f64,
        merge_threshold: f64,
        max_components: usize,
    ) -> Result<Self, FilterError> {
        if !(prune_threshold >= 0.0 && prune_threshold.is_finite()) {
            return Err(invalid(
                "prune threshold",
                format!("{prune_threshold} is not >= 0"),
            ));
        }
        if !(merge_threshold >= 0.0 && merge_threshold.is_finite()) {
            return Err(invalid(
                "merge threshold",
                format!("{merge_threshold} is not >= 0"),
            ));
        }
        if max_components == 0 {
            return Err(invalid("max components", "must be at least 1"));
        }
        Ok(Self {
            prune_threshold,
            merge_threshold,
            max_components,
        })
    }
}

/// What orders components: weight, label and position in the input, copied out of the
/// component so that sorting thousands of them does not chase a pointer per comparison.
/// The weight is held as [`descending_key`], so that comparing two ranks compares three
/// integers.
type Rank = (u64, Label, usize);

/// The [`Rank`] of component `g` at position `index`.
fn rank(index: usize, g: &Gaussian) -> Rank {
    (descending_key(g.weight), g.label, index)
}

/// An integer whose ascending order is the descending order of `f64::total_cmp`.
fn descending_key(weight: f64) -> u64 {
    let bits = weight.to_bits();
    // total_cmp's own key: a negative number's bits all flipped (larger magnitudes come
    // first), a positive number's sign bit set (above every negative one).
    let ascending = if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    };
    !ascending
}

/// Heaviest first, then smaller label, then earlier position.
fn heaviest_first(a: &Rank, b: &Rank) -> Ordering {
    a.cmp(b)
}

/// The clusters to build, in the reduced mixture's order: heaviest merged weight first
/// (then smaller label, then earlier cluster), at most `max_components` of them.
///
/// A cluster's weight and label are computed as [`merge`] computes them (the members'
/// weights summed in cluster order; the first member's label), so the order is known
/// before any component is built: each kept component is then built (or moved) once,
/// straight into place, and the clusters the cap drops are never merged. Ranks are
/// distinct (they end with the cluster's position), so the unstable sort gives the
/// order a stable one would.
fn heaviest_kept(
    mixture: &GaussianMixture,
    clusters: &Clusters,
    max_components: usize,
) -> Vec<usize> {
    let mut ranks: Vec<Rank> = clusters
        .iter()
        .enumerate()
        .map(|(c, cluster)| {
            let member = |i: &usize| &mixture.components[*i];
            let weight: f64 = cluster.iter().map(member).map(|g| g.weight).sum();
            (descending_key(weight), member(&cluster[0]).label, c)
        })
        .collect();
    ranks.sort_unstable_by(heaviest_first);
    ranks.truncate(max_components);
    ranks.into_iter().map(|(_, _, c)| c).collect()
}

/// What is left in a component's place once it is moved out: empty, so it allocates nothing.
fn moved_out() -> Gaussian {
    Gaussian::new(0.0, DVector::zeros(0), DMatrix::zeros(0, 0), Label(0))
}

impl Reducer for PruneMergeCap {
    fn reduce(&self, mixture: &GaussianMixture) -> GaussianMixture {
        let clusters = self.clusters(mixture);
        let components = heaviest_kept(mixture, &clusters, self.max_components)
            .into_iter()
            .map(|c| match clusters.get(c) {
                // Nothing to match: the component itself (moments would only add rounding).
                [only] => mixture.components[*only].clone(),
                members => merge(members.iter().map(|&i| &mixture.components[i])),
            })
            .collect();
        GaussianMixture::from_components(components)
    }

    /// As [`Reducer::reduce`], recording each cluster's labels; unmerged components are
    /// moved rather than copied.
    fn reduce_recording(&self, mixture: GaussianMixture) -> Reduction {
        let clusters = self.clusters(&mixture);
        let order = heaviest_kept(&mixture, &clusters, self.max_components);
        let mut input = mixture.components;
        let mut components = Vec::with_capacity(order.len());
        let mut ancestry = Vec::with_capacity(order.len());
        for c in order {
            let cluster = clusters.get(c);
            let labels: LabelSet = cluster
                .iter()
                .map(|&i| (input[i].label, input[i].weight))
                .collect();
            components.push(match cluster {
                // Each component is in one cluster at most: a singleton's can be moved out
                // (an empty placeholder, which allocates nothing, stays behind).
                [only] => std::mem::replace(&mut input[*only], moved_out()),
                members => merge(members.iter().map(|&i| &input[i])),
            });
            ancestry.push(labels);
        }
        Reduction {
            mixture: GaussianMixture::from_components(components),
            ancestry: Ancestry::Recorded(ancestry),
        }
    }

    fn prune_threshold(&self) -> f64 {
        self.prune_threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;
    use nalgebra::{DMatrix, DVector};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn component(weight: f64, x: f64, label: u64) -> Gaussian {
        Gaussian::new(
            weight,
            DVector::from_vec(vec![x, 0.0]),
            DMatrix::identity(2, 2),
            Label(label),
        )
    }

    /// Labels 5 and 7 merge (1 apart, U = 4), 1 is pruned (T = 1e-3), 2 stays alone and 3
    /// goes with a cap of 2.
    fn two_clusters_a_pruned_and_a_capped() -> GaussianMixture {
        GaussianMixture::from_components(vec![
            component(0.3, 0.0, 5),
            component(0.6, 1.0, 7),
            component(1e-4, 0.5, 1),
            component(0.2, 10.0, 2),
            component(0.1, 20.0, 3),
        ])
    }

    #[test]
    fn descending_keys_order_weights_as_total_cmp_reversed() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut weights = vec![
            0.0,
            -0.0,
            1e-300,
            f64::MIN_POSITIVE,
            1.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            f64::MAX,
        ];
        weights.extend(
            (0..200).map(|_| rng.gen_range(-1.0..1.0) * 10f64.powi(rng.gen_range(-20..20))),
        );
        for a in &weights {
            for b in &weights {
                assert_eq!(
                    descending_key(*a).cmp(&descending_key(*b)),
                    b.total_cmp(a),
                    "{a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn prunes_merges_and_caps_deterministically() {
        let reducer = PruneMergeCap::new(1e-3, 4.0, 2).unwrap();
        let mixture = two_clusters_a_pruned_and_a_capped();
        let reduced = reducer.reduce(&mixture);
        assert_eq!(reduced.len(), 2);
        let first = &reduced.components[0];
        assert!((first.weight - 0.9).abs() < 1e-12);
        assert_eq!(first.label, Label(7));
        assert!((first.mean[0] - 2.0 / 3.0).abs() < 1e-12);
        // Spread of the merged means adds to the covariance: 1 + (0.3·(2/3)² + 0.6·(1/3)²)/0.9.
        assert!((first.cov[(0, 0)] - (1.0 + 2.0 / 9.0)).abs() < 1e-12);
        assert_eq!(reduced.components[1].label, Label(2));
    }

    #[test]
    fn recording_reduces_alike_and_names_each_clusters_labels() {
        let reducer = PruneMergeCap::new(1e-3, 4.0, 2).unwrap();
        let mixture = two_clusters_a_pruned_and_a_capped();
        let reduction = reducer.reduce_recording(mixture.clone());
        assert_eq!(reduction.mixture, reducer.reduce(&mixture));
        let Ancestry::Recorded(sets) = reduction.ancestry else {
            panic!("PruneMergeCap records its merges");
        };
        let labels: Vec<Vec<(Label, f64)>> = sets.iter().map(LabelSet::heaviest_first).collect();
        assert_eq!(
            labels,
            vec![
                vec![(Label(7), 0.6), (Label(5), 0.3)],
                vec![(Label(2), 0.2)]
            ]
        );
    }

    #[test]
    fn equal_weights_are_ordered_by_label() {
        let reducer = PruneMergeCap::new(0.0, 0.0, 10).unwrap();
        let mixture =
            GaussianMixture::from_components(vec![component(0.5, 0.0, 9), component(0.5, 50.0, 4)]);
        let labels: Vec<_> = reducer.reduce(&mixture).iter().map(|g| g.label).collect();
        assert_eq!(labels, vec![Label(4), Label(9)]);
        assert!(PruneMergeCap::new(-1.0, 4.0, 10).is_err());
        assert!(PruneMergeCap::new(1e-5, 4.0, 0).is_err());
    }
}
