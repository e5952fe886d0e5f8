//! RANSAC fit of the dominant near-horizontal plane in a point set (the ground, for a LIDAR on a vehicle).

use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Parameters of the RANSAC ground-plane fit ([`super::GroundRemoval::Ransac`]); defaults suit a vehicle-mounted
/// LIDAR.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RansacPlaneParams {
    /// Plane hypotheses tried. Default 400: in a room whose walls fill much of the view a third of the scan may
    /// be floor, and the chance that no hypothesis is drawn from floor points alone is then 0.963⁴⁰⁰ ≈ 3·10⁻⁷
    /// (with 100 it was 2.4 %, and then a tilted plane through floor and walls is taken for the ground).
    /// Hypotheses steeper than `max_tilt_deg` are dropped before their inliers are counted, so most cost little.
    pub iterations: usize,
    /// Points within this distance (metres) of the plane are ground. Default 0.15 m: several times a LIDAR's
    /// range noise (2–3 cm) plus small unevenness, still below kerbs and wheels.
    pub distance_threshold: f64,
    /// Largest tilt (degrees) of the ground plane from the sensor's x-y plane. Default 15°.
    pub max_tilt_deg: f64,
    /// Fewest points on the plane for it to be taken as ground. Default 100.
    pub min_inliers: usize,
    /// Seed of the hypothesis sampler (the same scan always gives the same ground). Default 0.
    pub seed: u64,
}

impl Default for RansacPlaneParams {
    fn default() -> Self {
        Self {
            iterations: 400,
            distance_threshold: 0.15,
            max_tilt_deg: 15.0,
            min_inliers: 100,
            seed: 0,
        }
    }
}

/// A plane `normal · p + offset = 0` with a unit normal pointing up (`normal.z > 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit normal, with a non-negative z component.
    pub normal: Vector3<f64>,
    /// Offset: minus the distance of the plane from the origin along the normal.
    pub offset: f64,
}

impl Plane {
    /// The plane through three points, or `None` if they are (nearly) collinear.
    pub fn through(a: Vector3<f64>, b: Vector3<f64>, c: Vector3<f64>) -> Option<Self> {
        let (ab, ac) = (b - a, c - a);
        let cross = ab.cross(&ac);
        // Relative test: the sine of the angle between the two edges must not vanish.
        if cross.norm() <= 1e-9 * ab.norm() * ac.norm() || cross.norm() == 0.0 {
            return None;
        }
        Some(Self::from_normal_and_point(cross.normalize(), a))
    }

    /// The plane with the given unit normal through `point`, oriented so that the normal points up.
    fn from_normal_and_point(normal: Vector3<f64>, point: Vector3<f64>) -> Self {
        let normal = if normal.z < 0.0 { -normal } else { normal };
        Self {
            normal,
            offset: -normal.dot(&point),
        }
    }

    /// Signed distance of `point` from the plane (positive above it).
    pub fn signed_distance(&self, point: &[f64; 3]) -> f64 {
        self.normal.dot(&Vector3::from(*point)) + self.offset
    }

    /// Least-squares plane through a set of points (normal = direction of least spread), if they span a plane.
    fn least_squares<'a>(points: impl Iterator<Item = &'a [f64; 3]> + Clone) -> Option<Self> {
        let count = points.clone().count();
        if count < 3 {
            return None;
        }
        let mean = points
            .clone()
            .map(|p| Vector3::from(*p))
            .sum::<Vector3<f64>>()
            / count as f64;
        let scatter = points
            .map(|p| Vector3::from(*p) - mean)
            .fold(Matrix3::zeros(), |acc, d| acc + d * d.transpose());
        let eigen = SymmetricEigen::new(scatter);
        let smallest = eigen.eigenvalues.imin();
        let normal = eigen.eigenvectors.column(smallest).into_owned();
        (normal.norm() > 0.0).then(|| Self::from_normal_and_point(normal.normalize(), mean))
    }
}

/// The ground plane found by [`fit_ground_plane`] and how many points support it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundPlaneFit {
    /// The fitted plane.
    pub plane: Plane,
    /// Number of points within the distance threshold of it.
    pub inliers: usize,
}

/// Least-squares refinements of the chosen plane at most (each kept only while it lowers the cost).
const REFINEMENTS: usize = 3;
/// The refinements fit the points within this fraction of `distance_threshold`: the band is meant to hold the
/// ground's noise and unevenness, and its outer part holds the feet of walls and objects too, which would tilt
/// a least-squares plane.
const REFINEMENT_BAND: f64 = 1.0 / 3.0;

/// Finds the near-horizontal plane that fits the most points best, by RANSAC over three-point hypotheses
/// scored as MSAC does (Torr & Zisserman 2000: each point costs its squared distance from the plane, at most
/// `distance_threshold²`), followed by least-squares refinements on the points nearest the winner (within a
/// third of the threshold), each kept only if it is still near-horizontal and lowers the cost. Why not the
/// inlier count of plain RANSAC: within a band as wide as `distance_threshold` a plane tilted by a few degrees
/// can hold as many points as the true ground (the foot of a wall on one side, feet), and in a room such a plane
/// leaves a strip of floor by the far wall above the band. Returns `None` if the plane has fewer than
/// `min_inliers` points within the threshold.
pub fn fit_ground_plane(points: &[[f64; 3]], params: &RansacPlaneParams) -> Option<GroundPlaneFit> {
    if points.len() < 3 {
        return None;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let min_normal_z = params.max_tilt_deg.to_radians().cos();
    let threshold = params.distance_threshold;
    let mut best: Option<(Plane, f64)> = None;
    for _ in 0..params.iterations {
        let sample = rand::seq::index::sample(&mut rng, points.len(), 3);
        let vertex = |k: usize| Vector3::from(points[sample.index(k)]);
        let Some(plane) = Plane::through(vertex(0), vertex(1), vertex(2)) else {
            continue;
        };
        if plane.normal.z < min_normal_z {
            continue;
        }
        let cost = msac_cost(points, &plane, threshold);
        if best.is_none_or(|(_, b)| cost < b) {
            best = Some((plane, cost));
        }
    }
    let (mut plane, mut cost) = best?;
    for _ in 0..REFINEMENTS {
        let support = points
            .iter()
            .filter(|p| plane.signed_distance(p).abs() <= threshold * REFINEMENT_BAND);
        let Some(refined) = Plane::least_squares(support) else {
            break;
        };
        let refined_cost = msac_cost(points, &refined, threshold);
        if refined.normal.z < min_normal_z || refined_cost >= cost {
            break;
        }
        (plane, cost) = (refined, refined_cost);
    }
    let inliers = count_inliers(points, &plane, threshold);
    (inliers >= params.min_inliers).then_some(GroundPlaneFit { plane, inliers })
}

/// MSAC's cost of a plane: each point's squared distance from it, at most `threshold²`.
fn msac_cost(points: &[[f64; 3]], plane: &Plane, threshold: f64) -> f64 {
    let cap = threshold * threshold;
    points
        .iter()
        .map(|p| plane.signed_distance(p).powi(2).min(cap))
        .sum()
}

fn count_inliers(points: &[[f64; 3]], plane: &Plane, distance_threshold: f64) -> usize {
    points
        .iter()
        .filter(|p| plane.signed_distance(p).abs() <= distance_threshold)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    fn params() -> RansacPlaneParams {
        RansacPlaneParams {
            iterations: 100,
            distance_threshold: 0.05,
            max_tilt_deg: 15.0,
            min_inliers: 50,
            seed: 3,
        }
    }

    #[test]
    fn finds_a_tilted_floor_under_clutter_and_a_wall() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut points = Vec::new();
        // Floor z = -1.7 + 0.05 x (about 2.9° of slope), 600 points with 1 cm noise.
        for _ in 0..600 {
            let (x, y) = (rng.gen_range(-10.0..10.0), rng.gen_range(-10.0..10.0));
            points.push([x, y, -1.7 + 0.05 * x + rng.gen_range(-0.01..0.01)]);
        }
        // A wall x = 4 with more points than the floor: too steep to be ground.
        for _ in 0..900 {
            points.push([4.0, rng.gen_range(-10.0..10.0), rng.gen_range(-1.7..2.0)]);
        }
        // Scattered clutter.
        for _ in 0..200 {
            points.push([
                rng.gen_range(-10.0..10.0),
                rng.gen_range(-10.0..10.0),
                rng.gen_range(-1.0..2.0),
            ]);
        }
        let fit = fit_ground_plane(&points, &params()).expect("floor not found");
        let expected_normal = Vector3::new(-0.05, 0.0, 1.0).normalize();
        assert!(
            fit.plane.normal.dot(&expected_normal) > 0.9999,
            "normal {:?}",
            fit.plane.normal
        );
        // The wall's foot and the clutter inside the inlier band pull the least-squares refinement a little; the
        // plane must still lie well inside the 5 cm band around the true floor.
        let offset_error = fit.plane.signed_distance(&[0.0, 0.0, -1.7]);
        assert!(
            offset_error.abs() < 0.02,
            "plane misses the floor by {offset_error} m at the origin"
        );
        assert!(fit.inliers >= 600, "{} inliers", fit.inliers);
    }

    #[test]
    fn a_wall_foot_does_not_tilt_the_floor_of_a_room() {
        // A 3 m × 2 m floor seen with 1 cm noise and a wall at x = 3 m of which 2000 points per metre of
        // height lie on it. Within a 0.15 m band a plane tilted by 5.7° about the room's middle holds every
        // floor point and 0.15 m more of the wall's foot than the level floor: the inlier count prefers it,
        // and a room LIDAR then takes the floor by one wall for an object.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut points = Vec::new();
        for _ in 0..2000 {
            let (x, y) = (rng.gen_range(0.0..3.0), rng.gen_range(0.0..2.0));
            points.push([x, y, rng.gen_range(-0.01..0.01)]);
        }
        for _ in 0..5000 {
            points.push([3.0, rng.gen_range(0.0..2.0), rng.gen_range(0.0..2.5)]);
        }
        let params = RansacPlaneParams {
            distance_threshold: 0.15,
            ..RansacPlaneParams::default()
        };
        let fit = fit_ground_plane(&points, &params).expect("floor not found");
        assert!(
            fit.plane.normal.z > 0.5_f64.to_radians().cos(),
            "normal {:?}",
            fit.plane.normal
        );
        for corner in [[0.0, 0.0, 0.0], [3.0, 2.0, 0.0]] {
            let error = fit.plane.signed_distance(&corner);
            assert!(
                error.abs() < 0.02,
                "the plane misses the floor by {error} m at {corner:?}"
            );
        }
    }

    #[test]
    fn no_ground_when_only_walls_or_too_few_points() {
        let wall: Vec<[f64; 3]> = (0..400)
            .map(|k| [2.0, (k % 20) as f64 * 0.1, (k / 20) as f64 * 0.1])
            .collect();
        assert_eq!(fit_ground_plane(&wall, &params()), None);
        let floor: Vec<[f64; 3]> = (0..20)
            .map(|k| [k as f64, (k * 7 % 5) as f64, -1.5])
            .collect();
        assert_eq!(fit_ground_plane(&floor, &params()), None);
        assert_eq!(fit_ground_plane(&floor[..2], &params()), None);
    }

    #[test]
    fn collinear_points_make_no_plane() {
        let p = |x: f64| Vector3::new(x, 2.0 * x, 0.5);
        assert_eq!(Plane::through(p(0.0), p(1.0), p(2.0)), None);
        let plane = Plane::through(p(0.0), p(1.0), Vector3::new(0.0, 0.0, 1.0)).unwrap();
        assert!((plane.normal.norm() - 1.0).abs() < 1e-12 && plane.normal.z >= 0.0);
    }
}
