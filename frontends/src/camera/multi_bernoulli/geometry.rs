//! The camera's geometry from its projection matrix: projecting world points to pixels, the camera's
//! centre, and the floor point under a pixel at a given height.
//!
//! The world frame is the descriptors' one: metres, `z` up, the floor at `z = floor_z`.

use crate::camera::error::{CameraError, CameraResult};

/// A pinhole camera given by its 3 × 4 projection `P` (world → homogeneous pixel).
#[derive(Debug, Clone, PartialEq)]
pub struct CameraGeometry {
    projection: [[f64; 4]; 3],
    /// The inverse of the projection's left 3 × 3 block, turning a pixel into its ray's direction.
    inverse: nalgebra::Matrix3<f64>,
    /// +1 when points in front of the camera have a positive third homogeneous coordinate, else −1
    /// (a projection matrix is defined up to scale, sign included).
    depth_sign: f64,
    centre: [f64; 3],
    /// Width and height of the image, pixels.
    size: [f64; 2],
}

impl CameraGeometry {
    /// The camera of `projection` over an image of `size` pixels; refused when the projection's left
    /// 3 × 3 block is singular (no centre) or a number is not finite.
    pub fn new(projection: [[f64; 4]; 3], size: [u32; 2]) -> CameraResult<Self> {
        let invalid = |problem: &str| CameraError::InvalidConfig {
            field: "camera projection",
            problem: problem.to_string(),
        };
        if projection.iter().flatten().any(|v| !v.is_finite()) {
            return Err(invalid("a value is not finite"));
        }
        if size[0] == 0 || size[1] == 0 {
            return Err(invalid("the image size is zero"));
        }
        let m = nalgebra::Matrix3::from_fn(|r, c| projection[r][c]);
        let p4 = nalgebra::Vector3::new(projection[0][3], projection[1][3], projection[2][3]);
        let determinant = m.determinant();
        let inverse = m
            .try_inverse()
            .filter(|_| determinant.abs() > 1e-12)
            .ok_or_else(|| invalid("its left 3 x 3 block is singular"))?;
        let centre = inverse * -p4;
        Ok(Self {
            projection,
            inverse,
            depth_sign: determinant.signum(),
            centre: [centre[0], centre[1], centre[2]],
            size: size.map(f64::from),
        })
    }

    /// Width and height of the image, pixels.
    pub fn size(&self) -> [f64; 2] {
        self.size
    }

    /// The camera's centre in world coordinates.
    pub fn centre(&self) -> [f64; 3] {
        self.centre
    }

    /// The pixel `[u, v]` of world point `x`, or `None` when it lies behind the camera (or on its plane).
    pub fn project(&self, x: [f64; 3]) -> Option<[f64; 2]> {
        let row = |r: usize| {
            let p = &self.projection[r];
            p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3]
        };
        let w = row(2) * self.depth_sign;
        (w > 1e-6).then(|| {
            let w = row(2);
            [row(0) / w, row(1) / w]
        })
    }

    /// The point at height `z` seen at pixel `[u, v]`: where the pixel's ray meets the horizontal
    /// plane at `z`; `None` when the ray runs parallel to it or meets it behind the camera.
    pub fn point_at_height(&self, pixel: [f64; 2], z: f64) -> Option<[f64; 3]> {
        let direction = self.inverse * nalgebra::Vector3::new(pixel[0], pixel[1], 1.0);
        // The ray is centre + t·direction; its forward sense is the one the projection sees in front.
        let direction = direction * self.depth_sign;
        if direction[2].abs() < 1e-12 {
            return None;
        }
        let t = (z - self.centre[2]) / direction[2];
        (t > 0.0).then(|| {
            [
                self.centre[0] + t * direction[0],
                self.centre[1] + t * direction[1],
                z,
            ]
        })
    }

    /// The horizontal unit vector across the line of sight to the floor point `(x, y)`: the direction
    /// in which a vertical body's width is seen. `None` right under the camera.
    pub fn across_sight(&self, x: f64, y: f64) -> Option<[f64; 2]> {
        let (dx, dy) = (x - self.centre[0], y - self.centre[1]);
        let length = dx.hypot(dy);
        (length > 1e-9).then(|| [-dy / length, dx / length])
    }

    /// The outline in the image of the upright ellipsoid centred at `centre` with horizontal semi-axis
    /// `radius` and vertical semi-axis `half_height`: the conic `C` (symmetric 3 × 3, rows) such that the
    /// outline's pixels `p = [u, v, 1]` have `pᵀ C p = 0`. It is the inverse of the projected dual
    /// quadric `P Q* Pᵀ` (Hartley & Zisserman, sec. 8.3); `None` when that is singular (the camera on the
    /// ellipsoid's surface).
    pub fn ellipsoid_outline(
        &self,
        centre: [f64; 3],
        radius: f64,
        half_height: f64,
    ) -> Option<[[f64; 3]; 3]> {
        let semi_axes = [radius, radius, half_height];
        // Q* = T diag(a², a², b², −1) Tᵀ with T the translation to `centre`: Q*_ij = a_i² δ_ij − c_i c_j
        // for i, j < 3, Q*_i3 = −c_i, Q*_33 = −1.
        let dual = nalgebra::Matrix4::from_fn(|i, j| {
            let c = |k: usize| if k < 3 { centre[k] } else { 1.0 };
            let diagonal = if i == j && i < 3 {
                semi_axes[i].powi(2)
            } else {
                0.0
            };
            diagonal - c(i) * c(j)
        });
        let p = nalgebra::Matrix3x4::from_fn(|r, c| self.projection[r][c]);
        let conic = (p * dual * p.transpose()).try_inverse()?;
        Some(std::array::from_fn(|r| {
            std::array::from_fn(|c| 0.5 * (conic[(r, c)] + conic[(c, r)]))
        }))
    }

    /// Horizontal distance from the camera's centre to the floor point `(x, y)`.
    pub fn ground_distance(&self, x: f64, y: f64) -> f64 {
        (x - self.centre[0]).hypot(y - self.centre[1])
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A level camera at (0, 0, 2.5) looking along +x, 500 px focal length, 640 × 480.
    pub(crate) fn level_camera() -> CameraGeometry {
        // Camera axes in world coordinates: x right = −y world, y down = −z world, z forward = +x world.
        let rotation = [[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]];
        let eye = [0.0, 0.0, 2.5];
        let k = [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]];
        let mut p = [[0.0; 4]; 3];
        for r in 0..3 {
            for c in 0..3 {
                p[r][c] = (0..3).map(|i| k[r][i] * rotation[i][c]).sum();
            }
            let t: Vec<f64> = (0..3)
                .map(|i| -(0..3).map(|j| rotation[i][j] * eye[j]).sum::<f64>())
                .collect();
            p[r][3] = (0..3).map(|i| k[r][i] * t[i]).sum();
        }
        CameraGeometry::new(p, [640, 480]).unwrap()
    }

    #[test]
    fn centre_projection_and_back_projection_agree() {
        let camera = level_camera();
        let c = camera.centre();
        assert!((c[0]).abs() < 1e-9 && c[1].abs() < 1e-9 && (c[2] - 2.5).abs() < 1e-9);
        let x = [3.0, 0.5, 1.0];
        let pixel = camera.project(x).unwrap();
        let back = camera.point_at_height(pixel, 1.0).unwrap();
        assert!((back[0] - 3.0).abs() < 1e-9 && (back[1] - 0.5).abs() < 1e-9);
        assert!(camera.project([-1.0, 0.0, 1.0]).is_none(), "behind");
        let scaled = CameraGeometry::new(
            camera.projection.map(|row| row.map(|v| -2.0 * v)),
            [640, 480],
        )
        .unwrap();
        let same = scaled.project(x).unwrap();
        assert!((same[0] - pixel[0]).abs() < 1e-9 && (same[1] - pixel[1]).abs() < 1e-9);
        assert!(scaled.point_at_height(pixel, 1.0).is_some());
    }

    #[test]
    fn a_singular_projection_is_refused() {
        assert!(CameraGeometry::new([[0.0; 4]; 3], [640, 480]).is_err());
    }
}
