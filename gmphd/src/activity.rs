//! Objects that some sensors detect only while they are *active*: a talker is heard by a
//! microphone pair while talking, not in the pauses between talk spurts.
//!
//! Without a model of it, every set of such a sensor in which a silent talker is not heard
//! counts as a miss: four pairs at 256 ms multiply the talker's weight by `1 − p_D` sixteen
//! times a second, and a one-second pause wipes the talker out. The misses of a pause are not
//! independent: they all have one cause. So each component carries the probability
//! `a = P(active)` of a two-state Markov chain (talking ⇄ silent), as in the jump-Markov
//! GM-PHD filter of Pasha, Vo, Tuan & Ma (2009), collapsed to one probability per component:
//!
//! * **prediction** over `dt` relaxes `a` toward the chain's stationary share
//!   `π = μ / (λ + μ)` (`λ = 1 / mean_active_s`, `μ = 1 / mean_inactive_s`):
//!   `a' = π + (a − π) e^{−(λ + μ) dt}`;
//! * an update by a sensor that detects only active objects uses `p_D · a`: a miss keeps
//!   `w (1 − p_D a)` and `a' = a (1 − p_D) / (1 − p_D a)` (Bayes: the miss is evidence of
//!   silence); a detection child is active (`a' = 1`);
//! * other sensors (cameras, LIDAR) see the object either way and leave `a` as it is;
//! * a birth starts at `π`, and components whose `a` differ by more than
//!   [`MERGE_ACTIVITY_GAP`] are not merged (Pasha et al. merge within a mode only): a silent
//!   talker's widening component would otherwise merge into a talking neighbour's.
//!
//! The default means are the talk spurt and pause of conversational speech in ITU-T P.59
//! (1.004 s and 1.587 s).

use serde::{Deserialize, Serialize};

use crate::error::{invalid, FilterError};
use crate::gaussian::GaussianMixture;

/// Components whose activities differ by more than this are not merged.
pub const MERGE_ACTIVITY_GAP: f64 = 0.5;

/// The two-state activity chain: mean durations of the active and inactive spells.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ActivityModel {
    /// Mean length of an active spell (a talk spurt), s. Default 1.004 (ITU-T P.59).
    pub mean_active_s: f64,
    /// Mean length of an inactive spell (a pause), s. Default 1.587 (ITU-T P.59).
    pub mean_inactive_s: f64,
}

impl Default for ActivityModel {
    fn default() -> Self {
        Self {
            mean_active_s: 1.004,
            mean_inactive_s: 1.587,
        }
    }
}

impl ActivityModel {
    /// Checks that both means are positive and finite.
    pub fn validate(&self) -> Result<(), FilterError> {
        for (what, value) in [
            ("mean active spell", self.mean_active_s),
            ("mean inactive spell", self.mean_inactive_s),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(what, format!("{value} s is not a positive number")));
            }
        }
        Ok(())
    }

    /// The stationary probability of being active, `π = μ / (λ + μ)`.
    pub fn stationary(&self) -> f64 {
        self.mean_active_s / (self.mean_active_s + self.mean_inactive_s)
    }

    /// `a` predicted over `dt` seconds.
    pub fn predict(&self, activity: f64, dt: f64) -> f64 {
        let rate = 1.0 / self.mean_active_s + 1.0 / self.mean_inactive_s;
        let pi = self.stationary();
        pi + (activity - pi) * (-rate * dt).exp()
    }

    /// Predicts the activity of every component over `dt`.
    pub fn predict_mixture(&self, mixture: &mut GaussianMixture, dt: f64) {
        for component in &mut mixture.components {
            component.activity = self.predict(component.activity, dt);
        }
    }
}

/// `a` after a sensor that detects only active objects, with detection probability `p_d`
/// where the component is, did not detect it: `a (1 − p_D) / (1 − p_D a)`.
pub fn after_miss(activity: f64, p_d: f64) -> f64 {
    let missed = 1.0 - p_d * activity;
    if missed <= 0.0 {
        return 0.0;
    }
    (activity * (1.0 - p_d) / missed).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prediction_relaxes_to_the_stationary_share() {
        let model = ActivityModel::default();
        let pi = model.stationary();
        assert!((pi - 1.004 / 2.591).abs() < 1e-12);
        assert_eq!(model.predict(0.3, 0.0), 0.3);
        assert!((model.predict(1.0, 100.0) - pi).abs() < 1e-12);
        assert!((model.predict(0.0, 100.0) - pi).abs() < 1e-12);
        // The chain's transition over dt from "active": stay active with
        // π + (1 − π) e^{−(λ+μ) dt}; for a small dt about 1 − λ dt.
        let dt = 1e-4;
        assert!((model.predict(1.0, dt) - (1.0 - dt / 1.004)).abs() < 1e-8);
        assert!((model.predict(0.0, dt) - dt / 1.587).abs() < 1e-8);
    }

    #[test]
    fn a_miss_is_evidence_of_inactivity() {
        // Bayes over the two states: P(active | miss) = a (1 − p_D) / (a (1 − p_D) + (1 − a)).
        let (a, p_d) = (0.6, 0.8);
        let expected = a * (1.0 - p_d) / (a * (1.0 - p_d) + (1.0 - a));
        assert!((after_miss(a, p_d) - expected).abs() < 1e-12);
        assert_eq!(after_miss(1.0, 1.0), 0.0);
        assert_eq!(after_miss(0.0, 0.9), 0.0);
        assert_eq!(after_miss(0.7, 0.0), 0.7);
    }

    #[test]
    fn nonpositive_means_are_rejected() {
        let bad = ActivityModel {
            mean_active_s: 0.0,
            ..ActivityModel::default()
        };
        assert!(bad.validate().is_err());
        assert!(ActivityModel::default().validate().is_ok());
    }
}
