//! Pinhole camera: pixel coordinates of a world point through a 3×4 projection.

use nalgebra::{DMatrix, DVector, Matrix3x4, Vector3, Vector4};

use super::{
    check_uniforms, diagonal_noise, hints_of, positive, Detection, MeasurementModel, UpdateHints,
};
use serde::Serialize;

use crate::error::{invalid, FilterError};

/// Smallest |homogeneous scale| used when projecting, so that a sigma point on the
/// camera's focal plane gives a huge but finite pixel instead of a division by zero.
const MIN_HOMOGENEOUS_SCALE: f64 = 1e-12;

/// A calibrated camera: z = (u, v) = dehomogenised P · [p; 1] + noise.
///
/// A point is detectable only in front of the camera and inside the image
/// rectangle [0, width) × [0, height); clutter is uniform over that rectangle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PinholeCamera {
    projection: Matrix3x4<f64>,
    /// +1 or -1: the sign that makes the third homogeneous coordinate a depth
    /// (P may be given up to a negative scale).
    depth_sign: f64,
    image_size: [f64; 2],
    noise_cov: DMatrix<f64>,
    detection: Detection,
}

impl PinholeCamera {
    /// `projection` maps world to pixel (homogeneous); `image_size` is [width, height]
    /// in pixels; `noise_std` is [σu, σv] in pixels.
    pub fn new(
        projection: Matrix3x4<f64>,
        image_size: [f64; 2],
        noise_std: [f64; 2],
        detection: Detection,
    ) -> Result<Self, FilterError> {
        if !projection.iter().all(|x| x.is_finite()) {
            return Err(FilterError::NonFinite {
                what: "camera projection",
            });
        }
        let det = projection.fixed_view::<3, 3>(0, 0).determinant();
        let scale = projection.fixed_view::<3, 3>(0, 0).amax();
        if det.abs() <= 1e-12 * scale.powi(3) {
            return Err(invalid(
                "camera projection",
                "its left 3×3 block is singular",
            ));
        }
        positive(image_size[0], "image width")?;
        positive(image_size[1], "image height")?;
        Ok(Self {
            projection,
            depth_sign: det.signum(),
            image_size,
            noise_cov: diagonal_noise(&noise_std)?,
            detection,
        })
    }

    fn homogeneous(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.projection * Vector4::new(p.x, p.y, p.z, 1.0)
    }

    /// Depth of a world point along the optical axis (up to the projection's scale):
    /// positive in front of the camera.
    pub fn depth(&self, p: &Vector3<f64>) -> f64 {
        self.depth_sign * self.homogeneous(p).z
    }
}

impl MeasurementModel for PinholeCamera {
    fn dim(&self) -> usize {
        2
    }

    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        let h = self.homogeneous(p);
        let w = if h.z.abs() < MIN_HOMOGENEOUS_SCALE {
            MIN_HOMOGENEOUS_SCALE.copysign(h.z)
        } else {
            h.z
        };
        out[0] = h.x / w;
        out[1] = h.y / w;
    }

    fn noise_cov(&self) -> DMatrix<f64> {
        self.noise_cov.clone()
    }

    fn line_of_sight_origin(&self) -> Option<Vector3<f64>> {
        // The camera centre C solves P · [C; 1] = 0: C = −M⁻¹ p₄ (M the left 3×3 block,
        // invertible by construction).
        let m = self.projection.fixed_view::<3, 3>(0, 0).into_owned();
        let p4 = self.projection.column(3).into_owned();
        m.try_inverse().map(|inverse| -(inverse * p4))
    }

    fn detection_probability(&self, p: &Vector3<f64>) -> f64 {
        if self.depth(p) <= 0.0 {
            return 0.0;
        }
        let mut z = [0.0; 2];
        self.measure_into(p, &mut z);
        let inside =
            (0.0..self.image_size[0]).contains(&z[0]) && (0.0..self.image_size[1]).contains(&z[1]);
        if inside {
            self.detection.probability
        } else {
            0.0
        }
    }

    fn clutter_rate(&self) -> f64 {
        self.detection.clutter_rate
    }

    fn clutter_density(&self) -> f64 {
        1.0 / (self.image_size[0] * self.image_size[1])
    }

    /// Indexed by u (pixels).
    fn update_hints(&self) -> UpdateHints {
        hints_of(self, 0)
    }

    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        check_uniforms(u, 2)?;
        Ok(DVector::from_vec(vec![
            u[0] * self.image_size[0],
            u[1] * self.image_size[1],
        ]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The example camera of PROTOCOL.md: f = 800 px, principal point (320, 240),
    /// no rotation, camera centre at world (-0.3, -0.225, 2).
    fn camera() -> PinholeCamera {
        let p = Matrix3x4::new(
            800.0, 0.0, 320.0, -400.0, 0.0, 800.0, 240.0, -300.0, 0.0, 0.0, 1.0, -2.0,
        );
        PinholeCamera::new(
            p,
            [640.0, 480.0],
            [3.0, 3.0],
            Detection::new(0.95, 2.0).unwrap(),
        )
        .unwrap()
    }

    #[test]
    fn projects_points_and_limits_the_field_of_view() {
        let cam = camera();
        // A point on the optical axis, 3 m in front of the camera centre.
        let p = Vector3::new(-0.3, -0.225, 5.0);
        let z = cam.measure(&p);
        assert!((z[0] - 320.0).abs() < 1e-9 && (z[1] - 240.0).abs() < 1e-9);
        assert_eq!(cam.detection_probability(&p), 0.95);
        assert!((cam.depth(&p) - 3.0).abs() < 1e-12);
        // Behind the camera.
        assert_eq!(
            cam.detection_probability(&Vector3::new(-0.3, -0.225, 1.0)),
            0.0
        );
        // In front, but far outside the image.
        assert_eq!(
            cam.detection_probability(&Vector3::new(50.0, -0.225, 5.0)),
            0.0
        );
        assert!((cam.clutter_density() - 1.0 / (640.0 * 480.0)).abs() < 1e-18);
    }

    #[test]
    fn sees_from_its_centre() {
        let centre = camera().line_of_sight_origin().unwrap();
        assert!(
            (centre - Vector3::new(-0.3, -0.225, 2.0)).norm() < 1e-12,
            "{centre}"
        );
    }

    #[test]
    fn rejects_a_singular_projection() {
        let p = Matrix3x4::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let d = Detection::new(0.9, 0.0).unwrap();
        assert!(PinholeCamera::new(p, [640.0, 480.0], [1.0, 1.0], d).is_err());
    }
}
