//! 3-D LIDAR (Lee et al. 2010): range, azimuth and elevation of a cluster centroid.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{DMatrix, DVector, Matrix3, Quaternion, UnitQuaternion, Vector3};

use super::{
    check_uniforms, diagonal_noise, finite_point, hints_of, invertible_input, positive, Detection,
    MeasurementModel, UpdateHints,
};
use serde::Serialize;

use crate::error::{invalid, FilterError};

/// The measurement entry that is an angle (the azimuth): its residual is wrapped.
const ANGULAR: [usize; 1] = [1];

/// How far from 1 the norm of a configured orientation quaternion may be.
const UNIT_QUATERNION_TOLERANCE: f64 = 1e-6;

/// z = [range, azimuth, elevation] of a point in the sensor frame, azimuth =
/// atan2(y, x), elevation = atan2(z, √(x² + y²)).
///
/// Detectable within `max_range` and the elevation limits; clutter is uniform over
/// [0, max_range] × [−π, π) × [el_min, el_max].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Lidar {
    position: Vector3<f64>,
    /// Sensor → world rotation.
    orientation: UnitQuaternion<f64>,
    noise_cov: DMatrix<f64>,
    max_range: f64,
    elevation_limits: [f64; 2],
    detection: Detection,
}

impl Lidar {
    /// `orientation` is the sensor → world quaternion [w, x, y, z] (unit within 1e-6);
    /// `noise_std` is [σr (m), σaz (rad), σel (rad)]; `elevation_limits` is [min, max]
    /// within [−π/2, π/2].
    pub fn new(
        position: [f64; 3],
        orientation: [f64; 4],
        noise_std: [f64; 3],
        max_range: f64,
        elevation_limits: [f64; 2],
        detection: Detection,
    ) -> Result<Self, FilterError> {
        let position = finite_point(position, "lidar position")?;
        let [w, x, y, z] = orientation;
        let quaternion = Quaternion::new(w, x, y, z);
        if !quaternion.norm().is_finite()
            || (quaternion.norm() - 1.0).abs() > UNIT_QUATERNION_TOLERANCE
        {
            return Err(invalid(
                "lidar orientation",
                format!("quaternion norm {} is not 1", quaternion.norm()),
            ));
        }
        let [el_min, el_max] = elevation_limits;
        if !(el_min >= -FRAC_PI_2 && el_max <= FRAC_PI_2 && el_min < el_max) {
            return Err(invalid(
                "lidar elevation limits",
                format!("[{el_min}, {el_max}] is not an interval within [-pi/2, pi/2]"),
            ));
        }
        Ok(Self {
            position,
            orientation: UnitQuaternion::from_quaternion(quaternion),
            noise_cov: diagonal_noise(&noise_std)?,
            max_range: positive(max_range, "lidar max range")?,
            elevation_limits,
            detection,
        })
    }

    fn to_sensor_frame(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.orientation
            .inverse_transform_vector(&(p - self.position))
    }
}

impl MeasurementModel for Lidar {
    fn dim(&self) -> usize {
        3
    }

    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        let s = self.to_sensor_frame(p);
        let horizontal = s.x.hypot(s.y);
        out.copy_from_slice(&[s.norm(), s.y.atan2(s.x), s.z.atan2(horizontal)]);
    }

    fn noise_cov(&self) -> DMatrix<f64> {
        self.noise_cov.clone()
    }

    fn line_of_sight_origin(&self) -> Option<Vector3<f64>> {
        Some(self.position)
    }

    fn detection_probability(&self, p: &Vector3<f64>) -> f64 {
        // Range and elevation as `measure_into` computes them (the azimuth does not matter).
        let s = self.to_sensor_frame(p);
        let (range, elevation) = (s.norm(), s.z.atan2(s.x.hypot(s.y)));
        let [el_min, el_max] = self.elevation_limits;
        if range <= self.max_range && elevation >= el_min && elevation <= el_max {
            self.detection.probability
        } else {
            0.0
        }
    }

    fn clutter_rate(&self) -> f64 {
        self.detection.clutter_rate
    }

    fn clutter_density(&self) -> f64 {
        let [el_min, el_max] = self.elevation_limits;
        1.0 / (self.max_range * TAU * (el_max - el_min))
    }

    fn angular_entries(&self) -> &[usize] {
        &ANGULAR
    }

    /// Indexed by range, which is never wrapped.
    fn update_hints(&self) -> UpdateHints {
        hints_of(self, 0)
    }

    fn invert_with_noise(
        &self,
        z: &DVector<f64>,
        noise: &DMatrix<f64>,
    ) -> Option<(Vector3<f64>, Matrix3<f64>)> {
        if !invertible_input(z, noise, 3) || z[0] <= 0.0 {
            return None;
        }
        let (range, (sin_az, cos_az), (sin_el, cos_el)) = (z[0], z[1].sin_cos(), z[2].sin_cos());
        let direction = Vector3::new(cos_el * cos_az, cos_el * sin_az, sin_el);
        // Columns: ∂s/∂range, ∂s/∂azimuth, ∂s/∂elevation of the sensor-frame point s.
        let jacobian_sensor = Matrix3::from_columns(&[
            direction,
            range * Vector3::new(-cos_el * sin_az, cos_el * cos_az, 0.0),
            range * Vector3::new(-sin_el * cos_az, -sin_el * sin_az, cos_el),
        ]);
        let rotation = self.orientation.to_rotation_matrix();
        let jacobian = rotation.matrix() * jacobian_sensor;
        let noise = Matrix3::from_fn(|r, c| noise[(r, c)]);
        let cov = jacobian * noise * jacobian.transpose();
        Some((
            self.position + rotation * (range * direction),
            (cov + cov.transpose()) * 0.5,
        ))
    }

    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        check_uniforms(u, 3)?;
        let [el_min, el_max] = self.elevation_limits;
        Ok(DVector::from_vec(vec![
            u[0] * self.max_range,
            -PI + u[1] * TAU,
            el_min + u[2] * (el_max - el_min),
        ]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_in_the_rotated_sensor_frame() {
        // Sensor at (1, 0, 0) yawed by +90°: its x axis points along world y.
        let half = std::f64::consts::FRAC_PI_4;
        let lidar = Lidar::new(
            [1.0, 0.0, 0.0],
            [half.cos(), 0.0, 0.0, half.sin()],
            [0.1, 0.01, 0.01],
            100.0,
            [-0.3, 0.3],
            Detection::new(0.9, 5.0).unwrap(),
        )
        .unwrap();
        let z = lidar.measure(&Vector3::new(1.0, 10.0, 0.0));
        assert!((z[0] - 10.0).abs() < 1e-12 && z[1].abs() < 1e-12 && z[2].abs() < 1e-12);
        assert_eq!(
            lidar.detection_probability(&Vector3::new(1.0, 10.0, 0.0)),
            0.9
        );
        // Too steep and too far.
        assert_eq!(
            lidar.detection_probability(&Vector3::new(1.0, 1.0, 5.0)),
            0.0
        );
        assert_eq!(
            lidar.detection_probability(&Vector3::new(1.0, 200.0, 0.0)),
            0.0
        );
        let r = lidar.residual(
            &DVector::from_vec(vec![1.0, 3.1, 0.0]),
            &DVector::from_vec(vec![1.0, -3.1, 0.0]),
        );
        assert!((r[1] - (6.2 - TAU)).abs() < 1e-12);
    }

    #[test]
    fn rejects_non_unit_quaternion_and_bad_limits() {
        let d = Detection::new(0.9, 0.0).unwrap();
        assert!(Lidar::new(
            [0.0; 3],
            [2.0, 0.0, 0.0, 0.0],
            [0.1; 3],
            10.0,
            [-0.1, 0.1],
            d
        )
        .is_err());
        assert!(Lidar::new(
            [0.0; 3],
            [1.0, 0.0, 0.0, 0.0],
            [0.1; 3],
            10.0,
            [0.1, -0.1],
            d
        )
        .is_err());
    }
}
