//! Weighted, labelled Gaussian components and the mixture that is the PHD intensity.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// A track label (Pham ch. 4): the identity a component carries from birth on.
///
/// Labels are unique within one filter; `Label(0)` is never handed out so it can
/// mean "no label yet" in serialized state of older versions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Label(pub u64);

/// Hands out fresh labels in increasing order. Part of the filter state, so that
/// labels continue across a checkpoint and restart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct LabelSource {
    next: u64,
}

impl Default for LabelSource {
    fn default() -> Self {
        Self { next: 1 }
    }
}

impl LabelSource {
    /// A source whose first label is `next` (used when restoring a checkpoint).
    pub fn starting_at(next: u64) -> Self {
        Self { next: next.max(1) }
    }

    /// The label the next call to [`LabelSource::fresh`] returns.
    pub fn peek(&self) -> u64 {
        self.next
    }

    /// A label never handed out before by this source.
    pub fn fresh(&mut self) -> Label {
        let label = Label(self.next);
        self.next += 1;
        label
    }
}

/// One weighted Gaussian component of the intensity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gaussian {
    /// Weight: the expected number of objects this component stands for.
    pub weight: f64,
    /// Mean state.
    pub mean: DVector<f64>,
    /// State covariance (symmetric positive definite).
    pub cov: DMatrix<f64>,
    /// The label the component inherited from its birth component.
    pub label: Label,
    /// Probability that the object is *active* — in the state that sensors which detect only
    /// active objects need, such as a talker talking for a microphone pair (see
    /// [`crate::activity`]). 1 unless the filter models activity.
    #[serde(default = "always_active")]
    pub activity: f64,
}

/// The activity of a component of a filter that does not model it (and of older checkpoints).
fn always_active() -> f64 {
    1.0
}

impl Gaussian {
    /// A component from its parts.
    pub fn new(weight: f64, mean: DVector<f64>, cov: DMatrix<f64>, label: Label) -> Self {
        Self {
            weight,
            mean,
            cov,
            label,
            activity: always_active(),
        }
    }

    /// State dimension.
    pub fn dim(&self) -> usize {
        self.mean.len()
    }
}

/// A Gaussian mixture: the GM-PHD intensity (or a birth intensity).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GaussianMixture {
    /// The components, in no particular order unless a reducer sorted them.
    pub components: Vec<Gaussian>,
}

impl GaussianMixture {
    /// An empty mixture (zero intensity).
    pub fn new() -> Self {
        Self::default()
    }

    /// A mixture of the given components.
    pub fn from_components(components: Vec<Gaussian>) -> Self {
        Self { components }
    }

    /// Number of components.
    pub fn len(&self) -> usize {
        self.components.len()
    }

    /// True when the mixture has no component.
    pub fn is_empty(&self) -> bool {
        self.components.is_empty()
    }

    /// Total mass: the PHD's expected number of objects.
    pub fn total_weight(&self) -> f64 {
        self.components.iter().map(|c| c.weight).sum()
    }

    /// Iterates over the components.
    pub fn iter(&self) -> std::slice::Iter<'_, Gaussian> {
        self.components.iter()
    }

    /// The first component whose weight is not a finite number ≥ 0, if any.
    pub fn first_invalid_weight(&self) -> Option<&Gaussian> {
        self.iter()
            .find(|c| !c.weight.is_finite() || c.weight < 0.0)
    }

    /// (label, index) of every component, ascending: each label's components form one run
    /// (group them with `chunk_by`), in input order. One sort rather than a map of
    /// per-label lists.
    pub fn indices_by_label(&self) -> Vec<(Label, usize)> {
        // Packed as one integer, label then index: the order of the pairs, compared at once.
        let mut packed: Vec<u128> = self
            .iter()
            .enumerate()
            .map(|(index, component)| u128::from(component.label.0) << 64 | index as u128)
            .collect();
        // Distinct keys: the unstable sort orders them as a stable one would.
        packed.sort_unstable();
        packed
            .into_iter()
            .map(|key| (Label((key >> 64) as u64), key as u64 as usize))
            .collect()
    }
}
