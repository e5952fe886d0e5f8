//! Rows of an image conic: where the outline of a projected ellipsoid (the head) starts and ends on each
//! row of the image.
//!
//! For the conic `C` (rows `c_ij`) the pixels `[u, v, 1]` of the outline satisfy
//! `c00 u² + 2 (c01 v + c02) u + (c11 v² + 2 c12 v + c22) = 0`. A row `v` crosses the outline where that
//! quadratic in `u` has real roots; the rows where its discriminant vanishes are the outline's top and
//! bottom.

/// An ellipse in the image given as a conic (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageEllipse {
    conic: [[f64; 3]; 3],
}

impl ImageEllipse {
    /// The ellipse of `conic`; `None` unless it is a real ellipse.
    pub fn new(conic: [[f64; 3]; 3]) -> Option<Self> {
        let c = conic;
        let determinant_2x2 = c[0][0] * c[1][1] - c[0][1] * c[0][1];
        (determinant_2x2 > 0.0 && c[0][0].abs() > 0.0).then_some(Self { conic })
    }

    /// The top and bottom image rows (`v`) of the ellipse.
    pub fn rows(&self) -> Option<(f64, f64)> {
        let c = &self.conic;
        // The discriminant of the row's quadratic, divided by 4, as a quadratic in v.
        let a = c[0][1] * c[0][1] - c[0][0] * c[1][1];
        let b = 2.0 * (c[0][1] * c[0][2] - c[0][0] * c[1][2]);
        let k = c[0][2] * c[0][2] - c[0][0] * c[2][2];
        let discriminant = b * b - 4.0 * a * k;
        if discriminant.is_nan() || discriminant <= 0.0 || a == 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        let (v1, v2) = ((-b - root) / (2.0 * a), (-b + root) / (2.0 * a));
        Some((v1.min(v2), v1.max(v2)))
    }

    /// The columns `(left, right)` where row `v` crosses the ellipse; `None` when it does not.
    pub fn columns(&self, v: f64) -> Option<(f64, f64)> {
        let c = &self.conic;
        let a = c[0][0];
        let b = 2.0 * (c[0][1] * v + c[0][2]);
        let k = c[1][1] * v * v + 2.0 * c[1][2] * v + c[2][2];
        let discriminant = b * b - 4.0 * a * k;
        if discriminant.is_nan() || discriminant <= 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        let (u1, u2) = ((-b - root) / (2.0 * a), (-b + root) / (2.0 * a));
        Some((u1.min(u2), u1.max(u2)))
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::tests::level_camera;
    use super::*;

    #[test]
    fn a_sphere_ahead_of_a_level_camera_is_a_circle_of_the_expected_size() {
        let camera = level_camera();
        // A sphere of radius 0.1 m, 3 m ahead at the camera's height: a circle of 500 · 0.1 / 3 px
        // (to first order) round the image centre.
        let conic = camera.ellipsoid_outline([3.0, 0.0, 2.5], 0.1, 0.1).unwrap();
        let ellipse = ImageEllipse::new(conic).unwrap();
        let (top, bottom) = ellipse.rows().unwrap();
        let expected = 500.0 * 0.1 / 3.0;
        assert!((240.0 - top - expected).abs() < 0.1, "{top}");
        assert!((bottom - 240.0 - expected).abs() < 0.1, "{bottom}");
        let (left, right) = ellipse.columns(240.0).unwrap();
        assert!((320.0 - left - expected).abs() < 0.1 && (right - 320.0 - expected).abs() < 0.1);
        assert!(ellipse.columns(240.0 + 2.0 * expected).is_none());
    }

    #[test]
    fn a_head_seen_from_above_reaches_above_its_projected_top() {
        let camera = level_camera();
        // 1 m ahead and 1.3 m below the camera, a head (semi-axes 0.08 and 0.115) whose top is at 1.2 m.
        let conic = camera
            .ellipsoid_outline([1.0, 0.0, 1.085], 0.08, 0.115)
            .unwrap();
        let (top, _) = ImageEllipse::new(conic).unwrap().rows().unwrap();
        let apex = camera.project([1.0, 0.0, 1.2]).unwrap();
        assert!(top < apex[1] - 5.0, "outline top {top}, apex {apex:?}");
    }
}
