//! The drawings' geometry, in world coordinates: a camera's viewing frustum from its projection
//! matrix, a microphone pair's TDOA hyperbola, and a 2σ ellipse from a covariance.

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

/// A point in the world frame, metres.
pub type Point = [f64; 3];

/// How far a frustum's edges are drawn when they do not reach the floor, metres.
pub const FRUSTUM_REACH_M: f64 = 6.0;

/// A camera's viewing frustum: its centre, and where the rays through the image corners meet
/// the floor (`z = floor_z`) or end after [`FRUSTUM_REACH_M`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frustum {
    /// The camera centre.
    pub centre: Point,
    /// The ends of the four corner rays, in image order (top left, top right, bottom right,
    /// bottom left).
    pub corners: [Point; 4],
}

/// The frustum of a camera with 3×4 `projection` (world → pixel) and `image_size` [w, h];
/// `None` when the projection's left 3×3 block is singular.
pub fn camera_frustum(
    projection: &[[f64; 4]; 3],
    image_size: [u32; 2],
    floor_z: f64,
) -> Option<Frustum> {
    let m = Matrix3::from_fn(|r, c| projection[r][c]);
    let p4 = Vector3::new(projection[0][3], projection[1][3], projection[2][3]);
    let inverse = m.try_inverse()?;
    let centre = -(inverse * p4);
    let (w, h) = (f64::from(image_size[0]), f64::from(image_size[1]));
    let corner = |u: f64, v: f64| -> Point {
        // Points centre + t·d with t > 0 project to (u, v) in front of the camera.
        let d = inverse * Vector3::new(u, v, 1.0);
        let norm = d.norm();
        let reach = FRUSTUM_REACH_M / norm;
        let t = if d.z < 0.0 {
            ((floor_z - centre.z) / d.z).clamp(0.0, reach)
        } else {
            reach
        };
        let end = centre + d * t;
        [end.x, end.y, end.z]
    };
    Some(Frustum {
        centre: [centre.x, centre.y, centre.z],
        corners: [
            corner(0.0, 0.0),
            corner(w, 0.0),
            corner(w, h),
            corner(0.0, h),
        ],
    })
}

/// The branch of points `x` in the horizontal plane of a microphone pair with
/// ‖x − m₂‖ − ‖x − m₁‖ = `speed_of_sound` · `tau` (the TDOA measurement's locus), as a polyline
/// of points inside the box `[lo, hi]` (x and y), split where it leaves the box. Empty when
/// |c·tau| is not below the baseline (no such point exists).
pub fn tdoa_hyperbola(
    mics: &[Point; 2],
    speed_of_sound: f64,
    tau: f64,
    lo: [f64; 2],
    hi: [f64; 2],
) -> Vec<Vec<Point>> {
    const STEPS: usize = 120;
    const REACH: f64 = 5.0;
    let (m1, m2) = (mics[0], mics[1]);
    let axis = [m2[0] - m1[0], m2[1] - m1[1]];
    let baseline = axis[0].hypot(axis[1]);
    let half_difference = speed_of_sound * tau / 2.0;
    let focal = baseline / 2.0;
    if !(baseline > 0.0 && half_difference.is_finite() && half_difference.abs() < focal) {
        return Vec::new();
    }
    let (ex, ey) = (axis[0] / baseline, axis[1] / baseline);
    let centre = [(m1[0] + m2[0]) / 2.0, (m1[1] + m2[1]) / 2.0];
    let z = (m1[2] + m2[2]) / 2.0;
    let minor = (focal * focal - half_difference * half_difference).sqrt();
    let inside = |p: &Point| (lo[0]..=hi[0]).contains(&p[0]) && (lo[1]..=hi[1]).contains(&p[1]);
    let mut pieces: Vec<Vec<Point>> = vec![Vec::new()];
    for i in 0..=STEPS {
        let t = -REACH + 2.0 * REACH * i as f64 / STEPS as f64;
        // Local frame: x along m₁ → m₂, m₁ at −focal. tau > 0 is nearer m₁ (local x < 0).
        let (lx, ly) = (-half_difference * t.cosh(), minor * t.sinh());
        let p = [
            centre[0] + lx * ex - ly * ey,
            centre[1] + lx * ey + ly * ex,
            z,
        ];
        let current = pieces.last_mut().expect("never empty");
        if inside(&p) {
            current.push(p);
        } else if !current.is_empty() {
            pieces.push(Vec::new());
        }
    }
    pieces.retain(|piece| piece.len() >= 2);
    pieces
}

/// An ellipse in a view's plane: semi-axes in metres and the major axis' angle (radians,
/// counter-clockwise from the view's first axis).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Ellipse {
    /// Semi-major axis, metres.
    pub major: f64,
    /// Semi-minor axis, metres.
    pub minor: f64,
    /// Angle of the major axis, radians.
    pub angle: f64,
}

/// The 2σ ellipse (Mahalanobis distance 2) of the 2×2 covariance `[[a, b], [b, c]]`.
pub fn two_sigma_ellipse(a: f64, b: f64, c: f64) -> Ellipse {
    let mean = (a + c) / 2.0;
    let spread = (((a - c) / 2.0).powi(2) + b * b).sqrt();
    let (large, small) = ((mean + spread).max(0.0), (mean - spread).max(0.0));
    Ellipse {
        major: 2.0 * large.sqrt(),
        minor: 2.0 * small.sqrt(),
        angle: 0.5 * (2.0 * b).atan2(a - c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn distance(a: &Point, b: &Point) -> f64 {
        (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
    }

    #[test]
    fn a_frustum_starts_at_the_camera_centre_and_its_corners_project_to_the_image_corners() {
        // A camera at (1, 2, 3) looking straight down (-z), f = 500, 640 × 480.
        let (f, cx, cy) = (500.0, 320.0, 240.0);
        let k = Matrix3::new(f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0);
        let r = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
        let c = Vector3::new(1.0, 2.0, 3.0);
        let kr = k * r;
        let t = -(kr * c);
        let p = [
            [kr[(0, 0)], kr[(0, 1)], kr[(0, 2)], t.x],
            [kr[(1, 0)], kr[(1, 1)], kr[(1, 2)], t.y],
            [kr[(2, 0)], kr[(2, 1)], kr[(2, 2)], t.z],
        ];
        let frustum = camera_frustum(&p, [640, 480], 0.0).expect("regular");
        assert!(distance(&frustum.centre, &[1.0, 2.0, 3.0]) < 1e-9);
        let project = |x: &Point| {
            let h: Vec<f64> = (0..3)
                .map(|row| p[row][0] * x[0] + p[row][1] * x[1] + p[row][2] * x[2] + p[row][3])
                .collect();
            [h[0] / h[2], h[1] / h[2], h[2]]
        };
        for (corner, pixel) in
            frustum
                .corners
                .iter()
                .zip([[0.0, 0.0], [640.0, 0.0], [640.0, 480.0], [0.0, 480.0]])
        {
            assert!(corner[2].abs() < 1e-9, "on the floor: {corner:?}");
            let uvw = project(corner);
            assert!((uvw[0] - pixel[0]).abs() < 1e-6 && (uvw[1] - pixel[1]).abs() < 1e-6);
            assert!(uvw[2] > 0.0, "in front of the camera");
        }
        let singular = [
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        assert!(camera_frustum(&singular, [640, 480], 0.0).is_none());
    }

    #[test]
    fn every_hyperbola_point_has_the_measured_range_difference() {
        let mics = [[1.0, 0.0, 1.5], [1.5, 0.0, 1.5]];
        let c = 343.0;
        let tau = 0.0005;
        let pieces = tdoa_hyperbola(&mics, c, tau, [0.0, 0.0], [3.0, 2.0]);
        let points: Vec<&Point> = pieces.iter().flatten().collect();
        assert!(points.len() > 20, "{} points", points.len());
        for p in points {
            let difference = distance(p, &mics[1]) - distance(p, &mics[0]);
            assert!((difference - c * tau).abs() < 1e-9, "{p:?}: {difference}");
            assert!(p[0] >= 0.0 && p[0] <= 3.0 && p[1] >= 0.0 && p[1] <= 2.0);
        }
        // tau = 0 is the perpendicular bisector; an impossible tau draws nothing.
        let bisector = tdoa_hyperbola(&mics, c, 0.0, [0.0, 0.0], [3.0, 2.0]);
        assert!(bisector
            .iter()
            .flatten()
            .all(|p| (p[0] - 1.25).abs() < 1e-9));
        assert!(tdoa_hyperbola(&mics, c, 0.01, [0.0, 0.0], [3.0, 2.0]).is_empty());
        assert!(tdoa_hyperbola(&mics, c, f64::NAN, [0.0, 0.0], [3.0, 2.0]).is_empty());
    }

    #[test]
    fn the_two_sigma_ellipse_follows_the_covariance() {
        let round = two_sigma_ellipse(0.04, 0.0, 0.04);
        assert!((round.major - 0.4).abs() < 1e-12 && (round.minor - 0.4).abs() < 1e-12);
        let tilted = two_sigma_ellipse(0.05, 0.03, 0.05);
        assert!((tilted.major - 2.0 * 0.08f64.sqrt()).abs() < 1e-12);
        assert!((tilted.minor - 2.0 * 0.02f64.sqrt()).abs() < 1e-12);
        assert!((tilted.angle - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
    }
}
