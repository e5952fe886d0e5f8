//! Building a camera's 3×4 projection from where it is and what it looks at.

use nalgebra::{Matrix3, Matrix3x4, Vector3};

use crate::error::{invalid, ScenarioError};

/// Intrinsics and pose of a pinhole camera that looks at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookAt {
    /// Camera centre, world metres.
    pub eye: [f64; 3],
    /// The world point on the optical axis (it projects to the principal point).
    pub target: [f64; 3],
    /// Focal length in pixels (square pixels, no skew).
    pub focal_px: f64,
    /// Image `[width, height]` in pixels; the principal point is its centre.
    pub image_size: [u32; 2],
}

impl LookAt {
    /// The projection `K [R | −R·eye]`, rows as the protocol writes them, after checking
    /// that the pose defines one (see [`look_at_projection`]).
    pub fn projection(&self) -> Result<[[f64; 4]; 3], ScenarioError> {
        let forward = Vector3::from(self.target) - Vector3::from(self.eye);
        let horizontal = forward.xy().norm();
        if !(forward.iter().all(|x| x.is_finite()) && horizontal > 1e-9 * forward.norm()) {
            return Err(invalid(
                "camera look-at",
                "the optical axis is zero, vertical or not finite, so the image's up is undefined",
            ));
        }
        if !(self.focal_px > 0.0 && self.focal_px.is_finite()) {
            return Err(invalid(
                "camera focal length",
                format!("{} px is not a finite number > 0", self.focal_px),
            ));
        }
        Ok(look_at_projection(self))
    }
}

/// The projection `K [R | −R·eye]` of a level camera at `pose.eye` looking at
/// `pose.target`, rows as the protocol writes them.
///
/// The camera frame is the computer-vision one: `x` right, `y` down in the image, `z`
/// along the optical axis; "up" in the image is world `+z` (no roll). The pose must have a
/// non-vertical optical axis and a positive focal length (else the matrix holds NaN);
/// [`LookAt::projection`] checks that first.
pub fn look_at_projection(pose: &LookAt) -> [[f64; 4]; 3] {
    let eye = Vector3::from(pose.eye);
    let forward = (Vector3::from(pose.target) - eye).normalize();
    let right = forward.cross(&Vector3::z()).normalize();
    let down = forward.cross(&right);
    // World → camera rotation: its rows are the camera axes in world coordinates.
    let rotation = Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
    let [width, height] = pose.image_size;
    let f = pose.focal_px;
    let intrinsics = Matrix3::new(
        f,
        0.0,
        f64::from(width) / 2.0,
        0.0,
        f,
        f64::from(height) / 2.0,
        0.0,
        0.0,
        1.0,
    );
    let mut extrinsics = Matrix3x4::zeros();
    extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    extrinsics.set_column(3, &(-rotation * eye));
    let p = intrinsics * extrinsics;
    std::array::from_fn(|r| std::array::from_fn(|c| p[(r, c)]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector4;

    fn project(p: &[[f64; 4]; 3], x: [f64; 3]) -> (f64, f64, f64) {
        let m = Matrix3x4::from_fn(|r, c| p[r][c]);
        let h = m * Vector4::new(x[0], x[1], x[2], 1.0);
        (h.x / h.z, h.y / h.z, h.z)
    }

    #[test]
    fn target_projects_to_the_principal_point_and_up_is_up() {
        let pose = LookAt {
            eye: [0.0, 0.0, 2.5],
            target: [1.5, 1.0, 1.2],
            focal_px: 600.0,
            image_size: [640, 480],
        };
        let p = pose.projection().unwrap();
        let (u, v, depth) = project(&p, pose.target);
        assert!((u - 320.0).abs() < 1e-9 && (v - 240.0).abs() < 1e-9);
        assert!(depth > 0.0);
        // A point above the target is higher in the image (smaller v).
        let (_, v_above, _) = project(&p, [1.5, 1.0, 1.5]);
        assert!(v_above < 240.0);
        // Behind the camera the depth is negative.
        assert!(project(&p, [-1.5, -1.0, 2.5]).2 < 0.0);
    }

    #[test]
    fn a_vertical_axis_is_rejected() {
        let pose = LookAt {
            eye: [0.0, 0.0, 3.0],
            target: [0.0, 0.0, 0.0],
            focal_px: 600.0,
            image_size: [640, 480],
        };
        assert!(pose.projection().is_err());
    }
}
