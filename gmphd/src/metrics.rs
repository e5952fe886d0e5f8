//! Multi-object accuracy metrics: OSPA, GOSPA and label continuity.
//!
//! * OSPA — Schuhmacher, Vo & Vo, "A consistent metric for performance evaluation
//!   of multi-object filters", IEEE TSP 56(8), 2008.
//! * GOSPA (α = 2) — Rahmathullah, García-Fernández & Svensson, "Generalized
//!   optimal sub-pattern assignment metric", FUSION 2017.
//! * Mean number of labels per true track — Pham's thesis, ch. 4.4.
//!
//! Point sets are `&[DVector<f64>]`; the caller chooses which state entries to
//! compare (usually the positions: `mean.rows(0, 2).into_owned()`). Distances are
//! Euclidean. Optimal assignments come from [`crate::assignment`], whose integer
//! scaling makes the assignment optimal to about 10^-9 relative for sets of up to
//! a few hundred points; reported values are recomputed from the float distances.

mod continuity;

pub use continuity::LabelContinuity;

use crate::assignment::{min_cost_matching, AssignmentError, CostMatrix};
use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why a metric could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MetricError {
    /// The cut-off `c` must be finite and > 0.
    #[error("metric cut-off must be finite and > 0, got {0}")]
    InvalidCutoff(f64),
    /// The order `p` must be finite and >= 1.
    #[error("metric order must be finite and >= 1, got {0}")]
    InvalidOrder(f64),
    /// Two points had different dimensions.
    #[error("points have different dimensions: {expected} and {found}")]
    DimensionMismatch {
        /// Dimension of the first point seen.
        expected: usize,
        /// Dimension of the offending point.
        found: usize,
    },
    /// A coordinate was NaN or infinite.
    #[error("a point has a non-finite coordinate")]
    NonFinitePoint,
    /// The optimal assignment rejected its cost matrix.
    #[error(transparent)]
    Assignment(#[from] AssignmentError),
}

/// Cut-off `c` and order `p` shared by OSPA and GOSPA.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MetricParams {
    /// Cut-off `c` (same unit as the points): a larger error counts as `c`.
    pub cutoff: f64,
    /// Order `p` >= 1: how strongly large errors are emphasised.
    pub order: f64,
}

impl MetricParams {
    /// Checked constructor.
    pub fn new(cutoff: f64, order: f64) -> Result<Self, MetricError> {
        let params = Self { cutoff, order };
        params.validate()?;
        Ok(params)
    }

    fn validate(&self) -> Result<(), MetricError> {
        if !(self.cutoff.is_finite() && self.cutoff > 0.0) {
            return Err(MetricError::InvalidCutoff(self.cutoff));
        }
        if !(self.order.is_finite() && self.order >= 1.0) {
            return Err(MetricError::InvalidOrder(self.order));
        }
        Ok(())
    }
}

/// OSPA distance and its two components.
///
/// `distance^p = localisation^p + cardinality^p`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ospa {
    /// The OSPA distance, in `[0, c]`.
    pub distance: f64,
    /// Localisation component `((1/n) Σ min(d, c)^p)^(1/p)` over the optimal pairs.
    pub localisation: f64,
    /// Cardinality component `(c^p (n − m) / n)^(1/p)`, `m <= n` the set sizes.
    pub cardinality: f64,
}

/// GOSPA (α = 2) and its parts, each given as its contribution to `distance^p`.
///
/// `distance^p = localisation + missed + false_targets`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gospa {
    /// The GOSPA distance.
    pub distance: f64,
    /// `Σ d^p` over assigned pairs (those closer than `c`).
    pub localisation: f64,
    /// `(c^p / 2) ·` number of missed truths (truths left unassigned).
    pub missed: f64,
    /// `(c^p / 2) ·` number of false estimates (estimates left unassigned).
    pub false_targets: f64,
    /// Number of assigned pairs.
    pub assigned: usize,
    /// Number of missed truths.
    pub missed_count: usize,
    /// Number of false estimates.
    pub false_count: usize,
}

/// OSPA between two point sets (symmetric in its arguments).
pub fn ospa(
    x: &[DVector<f64>],
    y: &[DVector<f64>],
    params: MetricParams,
) -> Result<Ospa, MetricError> {
    params.validate()?;
    check_points(x.iter().chain(y))?;
    let (m, n) = (x.len().min(y.len()), x.len().max(y.len()));
    if n == 0 {
        return Ok(Ospa {
            distance: 0.0,
            localisation: 0.0,
            cardinality: 0.0,
        });
    }
    let (c, p) = (params.cutoff, params.order);
    let pairs = cut_off_matching(x, y, params)?;
    let loc_sum: f64 = pairs.iter().map(|pair| pair.cost).sum();
    let card_sum = c.powf(p) * (n - m) as f64;
    let nf = n as f64;
    Ok(Ospa {
        distance: ((loc_sum + card_sum) / nf).powf(1.0 / p).min(c),
        localisation: (loc_sum / nf).powf(1.0 / p),
        cardinality: (card_sum / nf).powf(1.0 / p),
    })
}

/// GOSPA (α = 2) between `truth` and `estimates`.
///
/// The distance is symmetric; the split into missed and false parts is not.
pub fn gospa(
    truth: &[DVector<f64>],
    estimates: &[DVector<f64>],
    params: MetricParams,
) -> Result<Gospa, MetricError> {
    params.validate()?;
    check_points(truth.iter().chain(estimates))?;
    let (c, p) = (params.cutoff, params.order);
    let c_p = c.powf(p);
    // With α = 2, pairing two points costs min(d, c)^p, and a pair at d >= c costs
    // exactly one miss plus one false target (c^p/2 each): the optimal assignment
    // over min(d, c)^p is the GOSPA assignment once such pairs are split up.
    let pairs = cut_off_matching(truth, estimates, params)?;
    let close: Vec<f64> = pairs
        .iter()
        .map(|pair| pair.cost)
        .filter(|&cost| cost < c_p)
        .collect();
    let assigned = close.len();
    let localisation: f64 = close.iter().sum();
    let missed_count = truth.len() - assigned;
    let false_count = estimates.len() - assigned;
    let missed = c_p / 2.0 * missed_count as f64;
    let false_targets = c_p / 2.0 * false_count as f64;
    Ok(Gospa {
        distance: (localisation + missed + false_targets).powf(1.0 / p),
        localisation,
        missed,
        false_targets,
        assigned,
        missed_count,
        false_count,
    })
}

/// Optimal assignment of `x` to `y` under cost `min(d, c)^p`; pair costs are that.
fn cut_off_matching(
    x: &[DVector<f64>],
    y: &[DVector<f64>],
    params: MetricParams,
) -> Result<Vec<crate::assignment::MatchedPair>, MetricError> {
    let (c, p) = (params.cutoff, params.order);
    let costs = CostMatrix::from_fn(x.len(), y.len(), |i, j| {
        Some((&x[i] - &y[j]).norm().min(c).powf(p))
    })?;
    Ok(min_cost_matching(&costs))
}

/// Checks that all points share one dimension and are finite.
fn check_points<'a>(points: impl Iterator<Item = &'a DVector<f64>>) -> Result<(), MetricError> {
    let mut expected = None;
    for point in points {
        let dim = *expected.get_or_insert(point.len());
        if point.len() != dim {
            return Err(MetricError::DimensionMismatch {
                expected: dim,
                found: point.len(),
            });
        }
        if point.iter().any(|v| !v.is_finite()) {
            return Err(MetricError::NonFinitePoint);
        }
    }
    Ok(())
}
