//! Nearly coordinated turn (Vo & Ma 2006; Pham 5.6.1), predicted with the unscented transform.

use nalgebra::{DMatrix, DVector, Vector3};

use super::{check_dt, check_gaussian_dims, check_noise, padded, MotionModel};
use crate::error::FilterError;
use crate::linalg::symmetrize;
use crate::ukf::{SigmaPoints, UnscentedParams};

/// |ω·dt| below which sin(ωΔ)/ω and (1 − cos ωΔ)/ω use their Taylor series: the
/// closed forms lose all precision as ω → 0 (0/0), the series are exact to f64 there.
const SMALL_TURN_ANGLE: f64 = 1e-4;

/// Planar state [x, y, vx, vy, ω] (ω the turn rate, rad/s):
/// the velocity rotates by ω·dt while the position follows the arc; the
/// process noise is a white acceleration entering through
/// G = [[Δ²/2, 0], [0, Δ²/2], [Δ, 0], [0, Δ]] and a turn-rate increment Δ·u
/// (Pham eq. 5.26 with Δ = dt).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinatedTurn {
    accel_noise_std: f64,
    turn_rate_noise_std: f64,
    fixed_height: f64,
    unscented: UnscentedParams,
}

impl CoordinatedTurn {
    /// `accel_noise_std` σ_w (m/s²), `turn_rate_noise_std` σ_u (rad/s²), the world
    /// height of the planar state, and the unscented-transform parameters.
    pub fn new(
        accel_noise_std: f64,
        turn_rate_noise_std: f64,
        fixed_height: f64,
        unscented: UnscentedParams,
    ) -> Result<Self, FilterError> {
        if !fixed_height.is_finite() {
            return Err(FilterError::NonFinite {
                what: "fixed height",
            });
        }
        Ok(Self {
            accel_noise_std: check_noise(accel_noise_std, "acceleration noise")?,
            turn_rate_noise_std: check_noise(turn_rate_noise_std, "turn rate noise")?,
            fixed_height,
            unscented,
        })
    }

    /// The noise-free transition of one state over `dt`.
    pub fn transition(x: &DVector<f64>, dt: f64) -> DVector<f64> {
        let (px, py, vx, vy, omega) = (x[0], x[1], x[2], x[3], x[4]);
        let theta = omega * dt;
        let (sin, cos) = theta.sin_cos();
        // a = sin(ωΔ)/ω, b = (1 − cos ωΔ)/ω.
        let (a, b) = if theta.abs() < SMALL_TURN_ANGLE {
            let t2 = theta * theta;
            (dt * (1.0 - t2 / 6.0), dt * theta / 2.0 * (1.0 - t2 / 12.0))
        } else {
            (sin / omega, (1.0 - cos) / omega)
        };
        DVector::from_vec(vec![
            px + a * vx - b * vy,
            py + b * vx + a * vy,
            cos * vx - sin * vy,
            sin * vx + cos * vy,
            omega,
        ])
    }

    /// Process noise covariance σ_w² G Gᵀ ⊕ σ_u² Δ².
    pub fn process_noise(&self, dt: f64) -> DMatrix<f64> {
        let qw = self.accel_noise_std.powi(2);
        let mut noise = DMatrix::zeros(5, 5);
        for i in 0..2 {
            noise[(i, i)] = qw * dt.powi(4) / 4.0;
            noise[(i, i + 2)] = qw * dt.powi(3) / 2.0;
            noise[(i + 2, i)] = qw * dt.powi(3) / 2.0;
            noise[(i + 2, i + 2)] = qw * dt * dt;
        }
        noise[(4, 4)] = (self.turn_rate_noise_std * dt).powi(2);
        noise
    }
}

impl MotionModel for CoordinatedTurn {
    fn state_dim(&self) -> usize {
        5
    }

    fn position_dims(&self) -> usize {
        2
    }

    fn position(&self, x: &DVector<f64>) -> Vector3<f64> {
        padded(x, 0, 2, self.fixed_height)
    }

    fn velocity(&self, x: &DVector<f64>) -> Option<Vector3<f64>> {
        Some(padded(x, 2, 2, 0.0))
    }

    fn predict(
        &self,
        mean: &DVector<f64>,
        cov: &DMatrix<f64>,
        dt: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), FilterError> {
        check_dt(dt)?;
        check_gaussian_dims(mean, cov, 5)?;
        if dt == 0.0 {
            return Ok((mean.clone(), cov.clone()));
        }
        let sigma = SigmaPoints::new(mean, cov, &self.unscented)?;
        let out = sigma.transform_into(
            |x| Self::transition(x, dt),
            |a, b, out| {
                for ((o, a), b) in out.iter_mut().zip(a).zip(b) {
                    *o = a - b;
                }
            },
        );
        Ok((out.mean, symmetrize(&(out.cov + self.process_noise(dt)))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn quarter_turn_rotates_the_velocity() {
        let x = DVector::from_vec(vec![0.0, 0.0, 10.0, 0.0, FRAC_PI_2]);
        let y = CoordinatedTurn::transition(&x, 1.0);
        // Quarter circle of radius v/ω = 20/π counter-clockwise.
        let r = 20.0 / std::f64::consts::PI;
        assert!((y[0] - r).abs() < 1e-12 && (y[1] - r).abs() < 1e-12);
        assert!(y[2].abs() < 1e-12 && (y[3] - 10.0).abs() < 1e-12);
    }

    #[test]
    fn straight_line_limit_is_continuous() {
        let straight = DVector::from_vec(vec![1.0, 2.0, 3.0, 4.0, 0.0]);
        let y0 = CoordinatedTurn::transition(&straight, 2.0);
        assert!((y0[0] - 7.0).abs() < 1e-15 && (y0[1] - 10.0).abs() < 1e-15);
        for omega in [1e-12, 1e-7, 4.9e-5, 5.1e-5, 1e-3] {
            let mut x = straight.clone();
            x[4] = omega;
            let y = CoordinatedTurn::transition(&x, 2.0);
            // Deviation from the straight line is O(ω Δ² v), nothing more.
            assert!(
                (&y - &y0).rows(0, 4).amax() < 20.0 * omega + 1e-12,
                "omega {omega}"
            );
        }
    }

    #[test]
    fn unscented_prediction_keeps_covariance_positive_definite() {
        let model =
            CoordinatedTurn::new(15.0, FRAC_PI_2 / 90.0, 0.0, UnscentedParams::default()).unwrap();
        let mean = DVector::from_vec(vec![0.0, 0.0, 2000.0, 0.0, 0.0]);
        let cov = DMatrix::from_diagonal(&DVector::from_vec(vec![
            2500.0,
            2500.0,
            2500.0,
            2500.0,
            (6f64.to_radians()).powi(2),
        ]));
        let (m, p) = model.predict(&mean, &cov, 1.0).unwrap();
        assert!((m[0] - 2000.0).abs() < 50.0);
        assert!(p.clone().cholesky().is_some());
        assert_eq!((&p - p.transpose()).amax(), 0.0);
        assert!(model.predict(&mean, &cov, -1.0).is_err());
    }
}
