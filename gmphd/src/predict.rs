//! The GM-PHD prediction (Pham eq. 3.17; Vo & Ma 2006, Prop. 2):
//! surviving components, spawned components and births.

use serde::{Deserialize, Serialize};

use crate::error::{invalid, FilterError};
use crate::gaussian::{Gaussian, GaussianMixture, LabelSource};
use crate::motion::MotionModel;
use crate::spawn::SpawnModel;

/// Probability that an object survives a prediction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Survival {
    /// p_S per prediction, whatever its length (fixed-period filters).
    PerStep(f64),
    /// p_S over one second; over dt seconds the object survives with p_S^dt, so
    /// irregular sensor intervals give a consistent death rate.
    PerSecond(f64),
}

impl Survival {
    /// Checks that the probability lies in [0, 1].
    pub fn validate(&self) -> Result<(), FilterError> {
        let p = match self {
            Self::PerStep(p) | Self::PerSecond(p) => *p,
        };
        if (0.0..=1.0).contains(&p) {
            Ok(())
        } else {
            Err(invalid(
                "survival probability",
                format!("{p} is not in [0, 1]"),
            ))
        }
    }

    /// Survival probability over a prediction of `dt` seconds.
    pub fn probability(&self, dt: f64) -> f64 {
        match self {
            Self::PerStep(p) => *p,
            Self::PerSecond(p) => p.powf(dt),
        }
    }
}

/// Everything a prediction needs besides the posterior itself.
#[derive(Debug, Clone, Copy)]
pub struct PredictionStep<'a> {
    /// Single-object motion.
    pub motion: &'a dyn MotionModel,
    /// Survival probability over this step.
    pub survival_probability: f64,
    /// Spawn model, if objects spawn others.
    pub spawn: Option<&'a SpawnModel>,
    /// Length of the step in seconds (≥ 0).
    pub dt: f64,
    /// Predicted components whose position leaves this box die (see [`SurvivalRegion`]).
    pub region: Option<&'a SurvivalRegion>,
}

/// A box of positions outside which objects do not survive (p_S = 0): the edge of the
/// surveillance volume. Without it a component that drifts out of every sensor's field of
/// view (a clutter return's child with a wrong velocity) has p_D = 0 there, so no update ever
/// lowers its weight; it lives on with its parent's label, its covariance grows, and the
/// reducer can merge the real track into it.
#[derive(Debug, Clone, PartialEq)]
pub struct SurvivalRegion {
    min: Vec<f64>,
    max: Vec<f64>,
}

impl SurvivalRegion {
    /// The box [`min`, `max`] (one bound per position dimension, `min < max`, finite).
    pub fn new(min: Vec<f64>, max: Vec<f64>) -> Result<Self, FilterError> {
        let valid = min.len() == max.len()
            && !min.is_empty()
            && min.iter().chain(&max).all(|v| v.is_finite())
            && min.iter().zip(&max).all(|(lo, hi)| lo < hi);
        if !valid {
            return Err(invalid(
                "survival region",
                format!("{min:?} .. {max:?} is not a finite box with min < max"),
            ));
        }
        Ok(Self { min, max })
    }

    /// Dimensions of the box.
    pub fn dims(&self) -> usize {
        self.min.len()
    }

    /// Whether `position` lies in the box (boundary included).
    pub fn contains(&self, position: &[f64]) -> bool {
        position
            .iter()
            .zip(self.min.iter().zip(&self.max))
            .all(|(p, (lo, hi))| (lo..=hi).contains(&p))
    }
}

/// Predicts the posterior `intensity` over one step in place and appends `births`; on
/// error the intensity is as it was.
///
/// Surviving components keep their label (the track they belong to); spawned
/// children get fresh labels from `labels`. Order of the result: survivors, then
/// spawned children (by parent), then births — deterministic for a given input.
pub fn predict_intensity(
    intensity: &mut GaussianMixture,
    step: &PredictionStep<'_>,
    births: Vec<Gaussian>,
    labels: &mut LabelSource,
) -> Result<(), FilterError> {
    let state_dim = step.motion.state_dim();
    if let Some(bad) = births.iter().find(|g| g.dim() != state_dim) {
        return Err(FilterError::DimensionMismatch {
            what: "birth component",
            expected: state_dim,
            found: bad.dim(),
        });
    }
    // Children are spawned from the components before they move.
    let spawned: Vec<Gaussian> = match step.spawn {
        Some(spawn) => intensity
            .iter()
            .flat_map(|parent| spawn.spawn(parent, labels))
            .collect(),
        None => Vec::new(),
    };
    let components = &mut intensity.components;
    if step.survival_probability > 0.0 {
        // All or none: the only fallible step comes before the intensity changes.
        step.motion.predict_all_in_place(components, step.dt)?;
        components.retain_mut(|component| {
            component.weight *= step.survival_probability;
            step.region.is_none_or(|region| {
                region.contains(step.motion.position(&component.mean).as_slice())
            })
        });
    } else {
        components.clear();
    }
    components.reserve(spawned.len() + births.len());
    components.extend(spawned);
    components.extend(births);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;
    use crate::motion::ConstantVelocity;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn survivors_keep_labels_and_births_follow() {
        let motion = ConstantVelocity::new(2, 1.0).unwrap();
        let posterior = GaussianMixture::from_components(vec![Gaussian::new(
            0.5,
            DVector::from_vec(vec![0.0, 0.0, 1.0, 2.0]),
            DMatrix::identity(4, 4),
            Label(9),
        )]);
        let birth = Gaussian::new(0.1, DVector::zeros(4), DMatrix::identity(4, 4), Label(10));
        let step = PredictionStep {
            motion: &motion,
            survival_probability: Survival::PerSecond(0.81).probability(0.5),
            spawn: None,
            dt: 0.5,
            region: None,
        };
        let mut labels = LabelSource::starting_at(11);
        let predict = |mut intensity: GaussianMixture,
                       step: &PredictionStep<'_>,
                       births: Vec<Gaussian>,
                       labels: &mut LabelSource| {
            predict_intensity(&mut intensity, step, births, labels).map(|()| intensity)
        };
        let predicted = predict(posterior.clone(), &step, vec![birth], &mut labels).unwrap();
        assert_eq!(predicted.len(), 2);
        assert!((predicted.components[0].weight - 0.45).abs() < 1e-12);
        assert_eq!(predicted.components[0].label, Label(9));
        // A region the survivor leaves (it moves to x = 0.5): only the birth is left.
        let region = SurvivalRegion::new(vec![-1.0, -1.0], vec![0.4, 1.0]).unwrap();
        let bounded = PredictionStep {
            region: Some(&region),
            ..step
        };
        let predicted_in_box = predict(
            posterior.clone(),
            &bounded,
            vec![predicted.components[1].clone()],
            &mut labels,
        )
        .unwrap();
        assert_eq!(predicted_in_box.len(), 1);
        assert_eq!(predicted_in_box.components[0].label, Label(10));
        assert!(SurvivalRegion::new(vec![0.0], vec![0.0]).is_err());
        assert!(SurvivalRegion::new(vec![0.0, f64::NAN], vec![1.0, 1.0]).is_err());
        assert_eq!(
            predicted.components[0].mean.as_slice(),
            &[0.5, 1.0, 1.0, 2.0]
        );
        assert_eq!(predicted.components[1].label, Label(10));
        let wrong = Gaussian::new(0.1, DVector::zeros(2), DMatrix::identity(2, 2), Label(12));
        assert!(predict(posterior.clone(), &step, vec![wrong], &mut labels).is_err());
        assert!(Survival::PerStep(1.5).validate().is_err());
    }

    /// A failed prediction leaves the intensity as it was, even when the bad component
    /// comes after good ones.
    #[test]
    fn a_failed_prediction_changes_nothing() {
        let motion = ConstantVelocity::new(2, 1.0).unwrap();
        let good = Gaussian::new(
            0.5,
            DVector::from_vec(vec![0.0, 0.0, 1.0, 2.0]),
            DMatrix::identity(4, 4),
            Label(1),
        );
        let wrong_size = Gaussian::new(0.5, DVector::zeros(6), DMatrix::identity(6, 6), Label(2));
        let mut intensity = GaussianMixture::from_components(vec![good, wrong_size]);
        let before = intensity.clone();
        let step = PredictionStep {
            motion: &motion,
            survival_probability: 0.9,
            spawn: None,
            dt: 0.5,
            region: None,
        };
        let mut labels = LabelSource::starting_at(3);
        assert!(predict_intensity(&mut intensity, &step, Vec::new(), &mut labels).is_err());
        assert_eq!(intensity, before);
        let backwards = PredictionStep { dt: -0.1, ..step };
        intensity.components.truncate(1);
        let before = intensity.clone();
        assert!(predict_intensity(&mut intensity, &backwards, Vec::new(), &mut labels).is_err());
        assert_eq!(intensity, before);
    }
}
