//! The GM-PHD update as Vo & Ma (2006, Prop. 2 and section IV) write it.

use std::f64::consts::TAU;

use nalgebra::{DMatrix, DVector};

use crate::error::FilterError;
use crate::gating::Gating;
use crate::gaussian::{Gaussian, GaussianMixture};
use crate::linalg::{log_determinant, log_sum_exp, robust_cholesky};
use crate::measurement::Measurement;
use crate::update::detection::detection_probability;
use crate::update::{UpdateOutcome, UpdateStep};

/// A predicted component as the sensor sees it: ẑ, H P Hᵀ (noise not included) and P Hᵀ.
struct Seen<'a> {
    component: &'a Gaussian,
    p_d: f64,
    z_hat: DVector<f64>,
    z_cov: DMatrix<f64>,
    cross_cov: DMatrix<f64>,
}

/// The posterior of `predicted` after one sensor's `measurements`, and each measurement's
/// association weight U(z), under `gating` ([`Gating::OFF`]: the exact update).
///
/// The posterior is (1 − p_D) v (the missed detections, in input order), then for each
/// measurement z in turn and each component j the sensor can detect (p_D > 0):
/// a component of weight p_D wⱼ qⱼ(z) / (κ(z) + Σₗ p_D wₗ qₗ(z)), mean mⱼ + Kⱼ (z − ẑⱼ)
/// and covariance Pⱼ − Kⱼ Sⱼ Kⱼᵀ, with Sⱼ = H Pⱼ Hᵀ + R, Kⱼ = Pⱼ Hᵀ Sⱼ⁻¹, qⱼ(z) =
/// N(z; ẑⱼ, Sⱼ). For a sensor linear in the position (H = [I 0]) ẑ, H P Hᵀ and P Hᵀ are
/// read off the component; otherwise they are its [`unscented_moments`](super::unscented_moments).
/// A measurement's own covariance replaces R for it. Components of zero weight are dropped.
///
/// The gate, as [`crate::gating`] states it: a pair at squared Mahalanobis distance
/// (z − ẑ)ᵀ S⁻¹ (z − ẑ) beyond γ takes no part (unless no pair of a clutter-free sensor's
/// measurement is inside, when none is gated), and a child lighter than the floor is
/// not emitted.
pub fn update(
    predicted: &GaussianMixture,
    step: &UpdateStep<'_>,
    gating: &Gating,
    measurements: &[Measurement],
) -> Result<UpdateOutcome, FilterError> {
    gating.validate()?;
    for measurement in measurements {
        step.sensor.validate(measurement)?;
    }
    let mut posterior = Vec::new();
    let mut seen = Vec::new();
    for component in predicted.iter().filter(|c| c.weight > 0.0) {
        let p_d = detection_probability(component, step, &mut DVector::zeros(0));
        let missed = (1.0 - p_d) * component.weight;
        if missed > 0.0 {
            posterior.push(Gaussian {
                weight: missed,
                ..component.clone()
            });
        }
        if p_d > 0.0 {
            seen.push(project(component, p_d, step)?);
        }
    }
    let gate = gating.distance_threshold(step.sensor.dim());
    let log_clutter = step.sensor.clutter_intensity().ln();
    let mut association = Vec::with_capacity(measurements.len());
    for measurement in measurements {
        let noise = measurement
            .cov
            .clone()
            .unwrap_or_else(|| step.sensor.noise_cov());
        let pairs: Vec<Pair> = seen
            .iter()
            .map(|s| Pair::of(s, measurement, &noise, step))
            .collect();
        let mut inside: Vec<bool> = pairs.iter().map(|p| p.distance_sq <= gate).collect();
        if log_clutter == f64::NEG_INFINITY && !inside.contains(&true) {
            inside.fill(true);
        }
        let terms: Vec<f64> = pairs
            .iter()
            .zip(&seen)
            .zip(&inside)
            .filter(|(_, inside)| **inside)
            .map(|((pair, s), _)| (s.p_d * s.component.weight).ln() + pair.log_q)
            .collect();
        let log_normaliser = log_sum_exp(&[&[log_clutter][..], &terms].concat());
        if log_normaliser == f64::NEG_INFINITY {
            association.push(0.0);
            continue;
        }
        association.push(terms.iter().map(|t| (t - log_normaliser).exp()).sum());
        let kept = pairs
            .into_iter()
            .zip(&seen)
            .zip(inside)
            .filter(|(_, inside)| *inside);
        for ((pair, s), _) in kept {
            let weight = ((s.p_d * s.component.weight).ln() + pair.log_q - log_normaliser).exp();
            if weight > 0.0 && weight >= gating.min_weight {
                posterior.push(pair.child(s, weight));
            }
        }
    }
    Ok(UpdateOutcome {
        posterior: GaussianMixture::from_components(posterior),
        association,
    })
}

/// `component` seen by the sensor: linear when it measures the leading position entries.
fn project<'a>(
    component: &'a Gaussian,
    p_d: f64,
    step: &UpdateStep<'_>,
) -> Result<Seen<'a>, FilterError> {
    let linear = step
        .sensor
        .linear_position_dims()
        .filter(|&d| d <= step.motion.position_dims());
    let (z_hat, z_cov, cross_cov) = match linear {
        Some(d) => {
            let n = component.dim();
            let h = DMatrix::<f64>::identity(d, n);
            (
                &h * &component.mean,
                &h * &component.cov * h.transpose(),
                &component.cov * h.transpose(),
            )
        }
        None => {
            let moments =
                super::unscented_moments(component, step.motion, step.sensor, step.unscented)?;
            (moments.mean, moments.cov, moments.cross_cov)
        }
    };
    Ok(Seen {
        component,
        p_d,
        z_hat,
        z_cov,
        cross_cov,
    })
}

/// One component with one measurement: residual, innovation covariance and likelihood.
struct Pair {
    residual: DVector<f64>,
    s: DMatrix<f64>,
    distance_sq: f64,
    /// ln N(z; ẑ, S).
    log_q: f64,
}

impl Pair {
    fn of(
        seen: &Seen<'_>,
        measurement: &Measurement,
        noise: &DMatrix<f64>,
        step: &UpdateStep<'_>,
    ) -> Self {
        let residual = step.sensor.residual(&measurement.z, &seen.z_hat);
        let s = &seen.z_cov + noise;
        let factor = robust_cholesky(&s);
        let distance_sq = residual.dot(&factor.solve(&residual));
        let m = residual.len() as f64;
        let log_q = -0.5 * (distance_sq + m * TAU.ln() + log_determinant(&factor));
        Self {
            residual,
            s,
            distance_sq,
            log_q,
        }
    }

    /// The Kalman-corrected child of weight `weight`.
    fn child(&self, seen: &Seen<'_>, weight: f64) -> Gaussian {
        let gain = &seen.cross_cov * robust_cholesky(&self.s).inverse();
        let mean = &seen.component.mean + &gain * &self.residual;
        let cov = &seen.component.cov - &gain * &self.s * gain.transpose();
        let cov = (&cov + cov.transpose()) * 0.5;
        Gaussian::new(weight, mean, cov, seen.component.label)
    }
}
