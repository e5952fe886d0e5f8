//! Which components a measurement can be gated with, found without testing every pair.
//!
//! A pair lies outside the gate as soon as one residual entry exceeds the gate's extent
//! √(γ S_ii) along that dimension (see [`super::component::Innovation::outside_box`]).
//! Along a dimension whose residual is the plain difference z_i − ẑ_i
//! ([`MeasurementModel::index_dim`](crate::measurement::MeasurementModel::index_dim)),
//! the measurements a component can reach are therefore found by interval stabbing
//! ([`crate::sweep`]) instead of a residual per pair. With objects spread over a volume
//! most pairs fall outside, so this turns the J × |Z| scan of the update into J log |Z|
//! plus the pairs that are near.
//!
//! The index only pre-selects: every candidate still goes through the full box test and
//! the Mahalanobis distance. Candidates of a measurement are listed in ascending component
//! order — the order the full scan visits them in — so the update's sums, and its output,
//! are the same bit for bit with or without the index.

use nalgebra::DefaultAllocator;

use super::component::Detectable;
use super::dims::{Dims, Storage};
use crate::measurement::Measurement;
use crate::sweep::IntervalHits;

/// For each measurement, the components whose gate can contain it.
pub(super) struct CandidateIndex {
    hits: IntervalHits,
    /// Measurements that are not indexed (own noise covariance: a wider gate) and must
    /// be tested against every component.
    unindexed: Vec<bool>,
}

impl CandidateIndex {
    /// Indexes `measurements` along dimension `dim` for the `detectable` components.
    pub(super) fn build<D: Dims>(
        detectable: &[Detectable<'_, D>],
        measurements: &[Measurement],
        dim: usize,
    ) -> Self
    where
        DefaultAllocator: Storage<D>,
    {
        let unindexed: Vec<bool> = measurements.iter().map(|m| m.cov.is_some()).collect();
        let queries: Vec<Option<f64>> = measurements
            .iter()
            .map(|m| m.cov.is_none().then(|| m.z[dim]))
            .collect();
        let intervals = detectable
            .iter()
            .map(|d| (d.predicted_z()[dim], d.innovation.half_width(dim)));
        Self {
            hits: IntervalHits::build(&queries, intervals),
            unindexed,
        }
    }

    /// The candidates of measurement `j`, ascending; `None` when every component is one.
    pub(super) fn candidates(&self, j: usize) -> Option<&[u32]> {
        (!self.unindexed[j]).then(|| self.hits.hits(j))
    }
}
