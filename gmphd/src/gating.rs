//! Gating of component–measurement pairs in the update.
//!
//! The exact GM-PHD update (Vo & Ma 2006, Prop. 2) gives every predicted component a
//! child for every measurement: J × |Z| components, nearly all of them with a weight
//! that underflows any use (a component 30 standard deviations from a measurement gets
//! e^{−450} of it). They cost time twice — once to emit, once more in the reducer, which
//! prunes them. Gating skips them, by two rules:
//!
//! * **Distance gate.** A pair is skipped when the squared Mahalanobis distance
//!   d² = (z − ẑ)ᵀ S⁻¹ (z − ẑ) of the measurement from the component's predicted
//!   measurement exceeds γ, the `probability` quantile of the χ² distribution with as many
//!   degrees of freedom as the measurement has entries (Bar-Shalom's validation gate). A
//!   measurement of the object the component stands for lies outside it with probability
//!   1 − `probability` (1e-4 by default). A skipped pair takes no part in the
//!   normaliser κ(z) + Σ p_D w q(z) either: its term there is at most e^{−γ/2} of the
//!   component's peak term p_D w q_max (e^{−γ/2} ≈ 1e-4 for a 2-D measurement, 2.7e-5
//!   for 3-D), and the kept weights of z grow by the skipped terms' share of the
//!   normaliser — in `tests/gating.rs`, 100 camera components × 60 measurements, by at
//!   most 0.13 % and the total weight by 1e-5 relative. One
//!   exception: when the sensor has no clutter (κ = 0) and no component has the
//!   measurement in its gate, the model says it still comes from some object, so its
//!   pairs are weighed without the gate rather than dropping the measurement.
//! * **Weight floor.** Of the pairs inside the gate, one whose posterior weight is below
//!   `min_weight` is not emitted (its share still counts in the normaliser, so the other
//!   weights are exact). The weight of a component is the expected number of objects it
//!   stands for, so the floor is absolute: an update drops at most `min_weight` expected
//!   objects per pair it evaluates. The default 1e-9 is four orders of magnitude below
//!   the pruning thresholds used with Vo & Ma's reduction (T = 1e-5), so the reducer would
//!   have pruned the pair anyway unless a later update of the same time stamp (another
//!   sensor, before the reduction) raised its weight 10 000-fold, which needs that pair to
//!   be the only explanation of that sensor's measurement and a clutter intensity below
//!   1e-4 of its density.
//!
//! Both are on by default in [`GmPhdFilter`](crate::GmPhdFilter); [`Gating::OFF`] gives the
//! exact update (every pair of non-zero weight is emitted).

use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::error::{invalid, FilterError};

/// Which component–measurement pairs the update evaluates and keeps (see the module
/// documentation for the rules and their effect).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gating {
    /// Probability mass of the innovation's Gaussian inside the distance gate, in (0, 1);
    /// `None` switches the distance gate off.
    pub probability: Option<f64>,
    /// Pairs whose posterior weight is below this are not emitted (≥ 0; 0 keeps every
    /// pair of non-zero weight).
    pub min_weight: f64,
}

impl Default for Gating {
    /// A 99.99 % distance gate and a weight floor of 1e-9.
    fn default() -> Self {
        Self {
            probability: Some(0.9999),
            min_weight: 1e-9,
        }
    }
}

impl Gating {
    /// No gating: the exact update, every pair of non-zero weight emitted.
    pub const OFF: Self = Self {
        probability: None,
        min_weight: 0.0,
    };

    /// Checks that the probability lies in (0, 1) and the floor is a finite number ≥ 0.
    pub fn validate(&self) -> Result<(), FilterError> {
        if let Some(p) = self.probability {
            if !(p > 0.0 && p < 1.0) {
                return Err(invalid("gate probability", format!("{p} is not in (0, 1)")));
            }
        }
        if !(self.min_weight >= 0.0 && self.min_weight.is_finite()) {
            return Err(invalid(
                "gating weight floor",
                format!("{} is not a finite number >= 0", self.min_weight),
            ));
        }
        Ok(())
    }

    /// γ: the largest squared Mahalanobis distance inside the gate for a measurement of
    /// `dim` entries (+∞ without a distance gate or for `dim` = 0).
    pub fn distance_threshold(&self, dim: usize) -> f64 {
        match self.probability {
            Some(p) if dim > 0 && p > 0.0 && p < 1.0 => chi_square_quantile(p, dim),
            _ => f64::INFINITY,
        }
    }
}

/// The `p` quantile of the χ² distribution with `dof` ≥ 1 degrees of freedom, p ∈ (0, 1)
/// (NaN outside those).
pub fn chi_square_quantile(p: f64, dof: usize) -> f64 {
    match ChiSquared::new(dof as f64) {
        Ok(distribution) if p > 0.0 && p < 1.0 => distribution.inverse_cdf(p),
        _ => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_tables_and_closed_forms() {
        // 2 degrees of freedom: the tail is e^(−x/2), so x = −2 ln(1 − p).
        for p in [0.5f64, 0.9, 0.99, 0.9999] {
            let exact = -2.0 * (1.0 - p).ln();
            assert!((chi_square_quantile(p, 2) - exact).abs() < 1e-9 * exact);
        }
        // Tabulated values (Abramowitz & Stegun 26.4; 1 dof is the squared normal).
        let table = [
            (0.95, 1, 3.841_458_820_694_124),
            (0.99, 3, 11.344_866_730_144_37),
            (0.9999, 1, 15.136_705_226_623_4),
            (0.9999, 3, 21.107_513_466_160_21),
            (0.999, 6, 22.457_744_484_825_3),
        ];
        for (p, dof, expected) in table {
            let x = chi_square_quantile(p, dof);
            assert!((x - expected).abs() < 1e-8 * expected, "{p} {dof}: {x}");
        }
    }

    #[test]
    fn default_gate_and_validation() {
        let gating = Gating::default();
        assert!(gating.validate().is_ok());
        assert!((gating.distance_threshold(2) + 2.0 * 1e-4f64.ln()).abs() < 1e-9);
        assert_eq!(Gating::OFF.distance_threshold(3), f64::INFINITY);
        let bad_probability = Gating {
            probability: Some(1.0),
            ..Gating::default()
        };
        assert!(bad_probability.validate().is_err());
        let bad_floor = Gating {
            min_weight: -1.0,
            ..Gating::default()
        };
        assert!(bad_floor.validate().is_err());
    }
}
