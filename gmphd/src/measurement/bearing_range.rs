//! Bearing and range in the horizontal plane (Pham 5.6.1, radar-like sensors).

use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Vector3};

use super::{
    check_uniforms, diagonal_noise, finite_point, hints_of, invertible_input, positive, Detection,
    HeightPrior, MeasurementModel, UpdateHints, DEFAULT_HEIGHT_STD,
};
use serde::Serialize;

use crate::error::FilterError;

/// The measurement entry that is an angle (the bearing): its residual is wrapped.
const ANGULAR: [usize; 1] = [0];

/// z = [bearing, range]: bearing = atan2(Δy, Δx), range = √(Δx² + Δy²) from the
/// sensor position, heights ignored.
///
/// Detectable within `max_range`; clutter is uniform over [−π, π) × [0, max_range].
/// Heights are not measured: inverted points take the height of the sensor's
/// [`HeightPrior`] (by default the sensor's own height with a 10 m standard deviation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BearingRange {
    position: Vector3<f64>,
    noise_cov: DMatrix<f64>,
    max_range: f64,
    detection: Detection,
    height_prior: HeightPrior,
}

impl BearingRange {
    /// `noise_std` is [σθ (rad), σr (m)].
    pub fn new(
        position: [f64; 3],
        noise_std: [f64; 2],
        max_range: f64,
        detection: Detection,
    ) -> Result<Self, FilterError> {
        let position = finite_point(position, "bearing-range sensor position")?;
        Ok(Self {
            position,
            noise_cov: diagonal_noise(&noise_std)?,
            max_range: positive(max_range, "bearing-range max range")?,
            detection,
            // A radar-like sensor most plausibly sees objects around its own height.
            height_prior: HeightPrior::new(position.z, DEFAULT_HEIGHT_STD)?,
        })
    }

    /// Sets the height given to points inverted from this sensor's measurements.
    pub fn with_height_prior(mut self, height_prior: HeightPrior) -> Self {
        self.height_prior = height_prior;
        self
    }
}

impl MeasurementModel for BearingRange {
    fn dim(&self) -> usize {
        2
    }

    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        let dx = p.x - self.position.x;
        let dy = p.y - self.position.y;
        out[0] = dy.atan2(dx);
        out[1] = dx.hypot(dy);
    }

    fn noise_cov(&self) -> DMatrix<f64> {
        self.noise_cov.clone()
    }

    fn line_of_sight_origin(&self) -> Option<Vector3<f64>> {
        Some(self.position)
    }

    fn detection_probability(&self, p: &Vector3<f64>) -> f64 {
        let range = (p.x - self.position.x).hypot(p.y - self.position.y);
        if range <= self.max_range {
            self.detection.probability
        } else {
            0.0
        }
    }

    fn clutter_rate(&self) -> f64 {
        self.detection.clutter_rate
    }

    fn clutter_density(&self) -> f64 {
        1.0 / (TAU * self.max_range)
    }

    fn angular_entries(&self) -> &[usize] {
        &ANGULAR
    }

    /// Indexed by range, which is never wrapped.
    fn update_hints(&self) -> UpdateHints {
        hints_of(self, 1)
    }

    fn invert_with_noise(
        &self,
        z: &DVector<f64>,
        noise: &DMatrix<f64>,
    ) -> Option<(Vector3<f64>, Matrix3<f64>)> {
        if !invertible_input(z, noise, 2) || z[1] <= 0.0 {
            return None;
        }
        let (bearing, range) = (z[0], z[1]);
        let (sin, cos) = bearing.sin_cos();
        // Columns: ∂(x, y)/∂bearing, ∂(x, y)/∂range.
        let jacobian = Matrix2::new(-range * sin, cos, range * cos, sin);
        let noise = Matrix2::from_fn(|r, c| noise[(r, c)]);
        let cov_xy = jacobian * noise * jacobian.transpose();
        Some(self.height_prior.complete(
            self.position.x + range * cos,
            self.position.y + range * sin,
            &((cov_xy + cov_xy.transpose()) * 0.5),
        ))
    }

    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        check_uniforms(u, 2)?;
        Ok(DVector::from_vec(vec![
            -PI + u[0] * TAU,
            u[1] * self.max_range,
        ]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bearing_range_geometry_and_wrap() {
        let s = BearingRange::new(
            [1000.0, 1000.0, 0.0],
            [PI / 30.0, 10.0],
            3000.0,
            Detection::new(0.98, 10.0).unwrap(),
        )
        .unwrap();
        let z = s.measure(&Vector3::new(1000.0, 2000.0, 55.0));
        assert!((z[0] - PI / 2.0).abs() < 1e-12 && (z[1] - 1000.0).abs() < 1e-9);
        assert_eq!(
            s.detection_probability(&Vector3::new(5000.0, 1000.0, 0.0)),
            0.0
        );
        let r = s.residual(
            &DVector::from_vec(vec![-3.0, 5.0]),
            &DVector::from_vec(vec![3.0, 1.0]),
        );
        assert!((r[0] - (TAU - 6.0)).abs() < 1e-12 && (r[1] - 4.0).abs() < 1e-12);
        let c = s.sample_clutter(&[0.5, 0.5]).unwrap();
        assert!(c[0].abs() < 1e-12 && (c[1] - 1500.0).abs() < 1e-9);
    }
}
