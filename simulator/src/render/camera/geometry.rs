//! The pinhole geometry a camera renderer needs from a protocol projection `P = [M | p₄]`: the
//! camera centre `C = −M⁻¹ p₄`, the ray `C + t M⁻¹ [u, v, 1]ᵀ` through an image point (whose
//! parameter `t` is the projective depth `w` of the point it reaches, so depths along different
//! rays compare directly), the projection of world points, and ray–ellipsoid intersection.

use nalgebra::{Matrix3, Vector3};

use crate::error::{invalid, ScenarioError};

/// A camera's rays, from its 3×4 projection.
#[derive(Debug, Clone, PartialEq)]
pub struct PinholeRays {
    projection: [[f64; 4]; 3],
    centre: [f64; 3],
    /// `M⁻¹`, whose columns give a ray's direction as `u c₀ + v c₁ + c₂`.
    inverse: Matrix3<f64>,
}

impl PinholeRays {
    /// The rays of `projection`, refused when its left 3×3 block is singular or not finite.
    pub fn new(projection: &[[f64; 4]; 3]) -> Result<Self, ScenarioError> {
        let m = Matrix3::from_fn(|r, c| projection[r][c]);
        let inverse = m
            .try_inverse()
            .filter(|inv| inv.iter().all(|x| x.is_finite()))
            .ok_or_else(|| invalid("camera projection", "its left 3×3 block is singular"))?;
        let p4 = Vector3::new(projection[0][3], projection[1][3], projection[2][3]);
        let centre = -(inverse * p4);
        Ok(Self {
            projection: *projection,
            centre: [centre.x, centre.y, centre.z],
            inverse,
        })
    }

    /// The camera centre, world metres.
    pub fn centre(&self) -> [f64; 3] {
        self.centre
    }

    /// The direction of the ray through image point `(u, v)` (pixels; a pixel's centre is at
    /// `col + 0.5, row + 0.5`), scaled so that the point at parameter `t` has depth `w = t`.
    pub fn direction(&self, u: f64, v: f64) -> [f64; 3] {
        let d = self.inverse * Vector3::new(u, v, 1.0);
        [d.x, d.y, d.z]
    }

    /// The image point `(u, v)` of a world point and its depth `w`; `None` behind the camera.
    pub fn project(&self, point: [f64; 3]) -> Option<([f64; 2], f64)> {
        let row = |r: usize| {
            let p = &self.projection[r];
            p[0] * point[0] + p[1] * point[1] + p[2] * point[2] + p[3]
        };
        let w = row(2);
        (w > 1e-9).then(|| ([row(0) / w, row(1) / w], w))
    }

    /// The pixel rectangle `[col0, col1) × [row0, row1)` of a `width × height` image covering the
    /// projections of a world box; `None` when it misses the image, the whole image when a corner
    /// is behind the camera.
    pub fn pixel_box(
        &self,
        min: [f64; 3],
        max: [f64; 3],
        width: u32,
        height: u32,
    ) -> Option<[u32; 4]> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for corner in 0..8 {
            let pick = |axis: usize| {
                if corner >> axis & 1 == 0 {
                    min[axis]
                } else {
                    max[axis]
                }
            };
            let Some((uv, _)) = self.project([pick(0), pick(1), pick(2)]) else {
                return Some([0, width, 0, height]);
            };
            for i in 0..2 {
                lo[i] = lo[i].min(uv[i]);
                hi[i] = hi[i].max(uv[i]);
            }
        }
        let clip = |x: f64, limit: u32| x.clamp(0.0, f64::from(limit)) as u32;
        let rect = [
            clip(lo[0].floor(), width),
            clip(hi[0].ceil() + 1.0, width),
            clip(lo[1].floor(), height),
            clip(hi[1].ceil() + 1.0, height),
        ];
        (rect[0] < rect[1] && rect[2] < rect[3]).then_some(rect)
    }
}

/// An ellipsoid with vertical and horizontal axes: a body part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UprightEllipsoid {
    /// Centre, world metres.
    pub centre: [f64; 3],
    /// Horizontal semi-axis (the same along x and y), m.
    pub radius: f64,
    /// Vertical semi-axis, m.
    pub half_height: f64,
}

impl UprightEllipsoid {
    fn radii(&self) -> [f64; 3] {
        [self.radius, self.radius, self.half_height]
    }

    /// The smallest ray parameter `t > 0` at which `origin + t direction` enters the ellipsoid.
    pub fn entry(&self, origin: [f64; 3], direction: [f64; 3]) -> Option<f64> {
        let r = self.radii();
        let o: [f64; 3] = std::array::from_fn(|i| (origin[i] - self.centre[i]) / r[i]);
        let d: [f64; 3] = std::array::from_fn(|i| direction[i] / r[i]);
        let a = dot(d, d);
        let b = dot(o, d);
        let c = dot(o, o) - 1.0;
        let discriminant = b * b - a * c;
        if discriminant < 0.0 {
            return None;
        }
        let t = (-b - discriminant.sqrt()) / a;
        (t > 0.0).then_some(t)
    }

    /// The outward unit normal at a point of its surface.
    pub fn normal(&self, point: [f64; 3]) -> [f64; 3] {
        let r = self.radii();
        let n: [f64; 3] = std::array::from_fn(|i| (point[i] - self.centre[i]) / (r[i] * r[i]));
        let length = dot(n, n).sqrt().max(1e-12);
        n.map(|x| x / length)
    }

    /// The lower and upper corners of its bounding box.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let r = self.radii();
        (
            std::array::from_fn(|i| self.centre[i] - r[i]),
            std::array::from_fn(|i| self.centre[i] + r[i]),
        )
    }
}

/// The dot product of two 3-vectors.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The point `origin + t direction`.
pub fn along(origin: [f64; 3], direction: [f64; 3], t: f64) -> [f64; 3] {
    std::array::from_fn(|i| origin[i] + t * direction[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera_pose::{look_at_projection, LookAt};

    fn rays() -> PinholeRays {
        let pose = LookAt {
            eye: [0.0, 0.0, 2.5],
            target: [1.5, 1.0, 1.2],
            focal_px: 500.0,
            image_size: [640, 480],
        };
        PinholeRays::new(&look_at_projection(&pose)).unwrap()
    }

    #[test]
    fn a_ray_through_a_projected_point_reaches_it_at_its_depth() {
        let rays = rays();
        let centre = rays.centre();
        println!("camera centre {centre:?}");
        assert!((0..3).all(|i| (centre[i] - [0.0, 0.0, 2.5][i]).abs() < 1e-9));
        let point = [1.2, 0.7, 0.4];
        let (uv, w) = rays.project(point).unwrap();
        let reached = along(centre, rays.direction(uv[0], uv[1]), w);
        println!("{point:?} → {uv:?} at depth {w:.3} → {reached:?}");
        assert!((0..3).all(|i| (reached[i] - point[i]).abs() < 1e-9));
    }

    #[test]
    fn a_ray_enters_a_sphere_at_its_near_surface() {
        let sphere = UprightEllipsoid {
            centre: [0.0, 0.0, 0.0],
            radius: 1.0,
            half_height: 2.0,
        };
        let t = sphere.entry([-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
        let x = -(1.0f64 - 0.25).sqrt();
        println!("entry at t = {t:.6}, x = {:.6} (analytic {x:.6})", t - 5.0);
        assert!((t - 5.0 - x).abs() < 1e-12);
        assert!(sphere.entry([-5.0, 0.0, 2.5], [1.0, 0.0, 0.0]).is_none());
        assert!(sphere.entry([5.0, 0.0, 0.0], [1.0, 0.0, 0.0]).is_none());
        let n = sphere.normal([0.0, 0.0, 2.0]);
        assert!((n[2] - 1.0).abs() < 1e-12);
    }
}
