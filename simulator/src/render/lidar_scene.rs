//! What a simulated LIDAR's rays hit: the floor, the inside of a room, static distractors (poles,
//! boxes) and people, each an analytic primitive with a closed-form ray intersection.
//!
//! A person is drawn from their truth position, which is the top of the head: a sphere head whose
//! top is that point, on an elliptic cylinder (torso and legs as one) from the floor to the
//! shoulders, its long axis across the walking direction.

use nalgebra::Vector3;

/// Head radius, m.
pub const HEAD_RADIUS_M: f64 = 0.11;
/// Shoulders below the top of the head, m.
pub const SHOULDERS_BELOW_TOP_M: f64 = 0.25;
/// Half the shoulder width (the body's semi-axis across the walking direction), m.
pub const HALF_SHOULDER_WIDTH_M: f64 = 0.21;
/// Half the chest depth (the body's semi-axis along the walking direction), m.
pub const HALF_CHEST_DEPTH_M: f64 = 0.14;

/// A vertical pole standing on the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pole {
    /// Axis position `[x, y]`, m.
    pub centre: [f64; 2],
    /// Radius, m.
    pub radius: f64,
    /// Height of the top above the floor, m.
    pub height: f64,
}

/// Everything but the people: floor, room walls and distractors (world frame).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LidarScene {
    /// Height of the floor plane, if there is one.
    pub floor_z: Option<f64>,
    /// The room as an axis-aligned box `[min, max]` seen from inside (walls, floor, ceiling), if any.
    pub room: Option<[[f64; 3]; 2]>,
    /// Vertical poles.
    pub poles: Vec<Pole>,
    /// Solid axis-aligned boxes `[min, max]` (crates, cabinets).
    pub boxes: Vec<[[f64; 3]; 2]>,
}

impl LidarScene {
    /// The default room of `simulator::default_room()`: 3 m × 2 m, 2.5 m high, floor at z = 0, empty.
    pub fn default_room() -> Self {
        Self {
            floor_z: Some(0.0),
            room: Some([[0.0, 0.0, 0.0], [3.0, 2.0, 2.5]]),
            ..Self::default()
        }
    }

    /// Flat open ground at z = 0 with the given poles.
    pub fn open_ground(poles: Vec<Pole>) -> Self {
        Self {
            floor_z: Some(0.0),
            poles,
            ..Self::default()
        }
    }

    /// The nearest hit of the static scene along `origin + t · direction` (unit direction), `t > 0`.
    pub(crate) fn nearest_static(&self, origin: &Vector3<f64>, direction: &Vector3<f64>) -> f64 {
        let mut nearest = f64::INFINITY;
        if let Some(floor_z) = self.floor_z {
            nearest = nearest.min(plane_z_hit(origin, direction, floor_z));
        }
        if let Some(room) = &self.room {
            nearest = nearest.min(box_exit(origin, direction, room));
        }
        for pole in &self.poles {
            let cylinder = Cylinder {
                centre: pole.centre,
                axes: [[1.0 / pole.radius, 0.0], [0.0, 1.0 / pole.radius]],
                z: [
                    self.floor_z.unwrap_or(0.0),
                    self.floor_z.unwrap_or(0.0) + pole.height,
                ],
            };
            nearest = nearest.min(cylinder.hit(origin, direction));
        }
        for solid in &self.boxes {
            nearest = nearest.min(box_entry(origin, direction, solid));
        }
        nearest
    }
}

/// One person's body, built from the top of the head and the walking direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Body {
    head_centre: Vector3<f64>,
    torso: Cylinder,
}

impl Body {
    /// The body whose head top is `top`, walking along the unit horizontal vector `heading`, on a
    /// floor at `floor_z`.
    pub(crate) fn new(top: [f64; 3], heading: [f64; 2], floor_z: f64) -> Self {
        let [hx, hy] = heading;
        Self {
            head_centre: Vector3::new(top[0], top[1], top[2] - HEAD_RADIUS_M),
            torso: Cylinder {
                centre: [top[0], top[1]],
                // Unit axis vectors over their semi-axis lengths: the ellipse is |A (p − c)| ≤ 1.
                axes: [
                    [hx / HALF_CHEST_DEPTH_M, hy / HALF_CHEST_DEPTH_M],
                    [-hy / HALF_SHOULDER_WIDTH_M, hx / HALF_SHOULDER_WIDTH_M],
                ],
                z: [floor_z, top[2] - SHOULDERS_BELOW_TOP_M],
            },
        }
    }

    /// The nearest hit along the ray, `t > 0`, or infinity.
    pub(crate) fn hit(&self, origin: &Vector3<f64>, direction: &Vector3<f64>) -> f64 {
        sphere_hit(origin, direction, &self.head_centre, HEAD_RADIUS_M)
            .min(self.torso.hit(origin, direction))
    }
}

/// A vertical elliptic cylinder with a flat top: points with `|A (p_xy − centre)| ≤ 1` between two
/// heights. `axes` are the rows of `A` (for a circle of radius r: the identity over r).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cylinder {
    centre: [f64; 2],
    axes: [[f64; 2]; 2],
    z: [f64; 2],
}

impl Cylinder {
    /// The ray's nearest hit of the side or the top, `t > 0`, or infinity.
    fn hit(&self, origin: &Vector3<f64>, direction: &Vector3<f64>) -> f64 {
        let local = |x: f64, y: f64| {
            [
                self.axes[0][0] * x + self.axes[0][1] * y,
                self.axes[1][0] * x + self.axes[1][1] * y,
            ]
        };
        let o = local(origin.x - self.centre[0], origin.y - self.centre[1]);
        let d = local(direction.x, direction.y);
        let a = d[0] * d[0] + d[1] * d[1];
        let b = o[0] * d[0] + o[1] * d[1];
        let c = o[0] * o[0] + o[1] * o[1] - 1.0;
        let mut nearest = f64::INFINITY;
        let discriminant = b * b - a * c;
        if a > 0.0 && discriminant >= 0.0 {
            let t = (-b - discriminant.sqrt()) / a;
            let z = origin.z + t * direction.z;
            if t > 0.0 && (self.z[0]..=self.z[1]).contains(&z) {
                nearest = t;
            }
        }
        let t = plane_z_hit(origin, direction, self.z[1]);
        if t.is_finite() && origin.z > self.z[1] {
            let p = local(
                origin.x + t * direction.x - self.centre[0],
                origin.y + t * direction.y - self.centre[1],
            );
            if p[0] * p[0] + p[1] * p[1] <= 1.0 {
                nearest = nearest.min(t);
            }
        }
        nearest
    }
}

/// Where the ray meets the horizontal plane at `z` (`t > 0`), or infinity.
fn plane_z_hit(origin: &Vector3<f64>, direction: &Vector3<f64>, z: f64) -> f64 {
    let t = (z - origin.z) / direction.z;
    if t > 0.0 && t.is_finite() {
        t
    } else {
        f64::INFINITY
    }
}

/// The nearest intersection with a sphere in front of the origin, or infinity.
fn sphere_hit(
    origin: &Vector3<f64>,
    direction: &Vector3<f64>,
    centre: &Vector3<f64>,
    radius: f64,
) -> f64 {
    let offset = origin - centre;
    let b = offset.dot(direction);
    let discriminant = b * b - (offset.norm_squared() - radius * radius);
    if discriminant < 0.0 {
        return f64::INFINITY;
    }
    let t = -b - discriminant.sqrt();
    if t > 0.0 {
        t
    } else {
        f64::INFINITY
    }
}

/// Where a ray from inside a box leaves it (slab method), or infinity when the origin is outside.
fn box_exit(origin: &Vector3<f64>, direction: &Vector3<f64>, bounds: &[[f64; 3]; 2]) -> f64 {
    let mut exit = f64::INFINITY;
    for axis in 0..3 {
        if !(bounds[0][axis]..=bounds[1][axis]).contains(&origin[axis]) {
            return f64::INFINITY;
        }
        let wall = if direction[axis] > 0.0 {
            bounds[1][axis]
        } else {
            bounds[0][axis]
        };
        let t = (wall - origin[axis]) / direction[axis];
        if t > 0.0 && t.is_finite() {
            exit = exit.min(t);
        }
    }
    exit
}

/// Where a ray from outside a solid box enters it (slab method), or infinity.
fn box_entry(origin: &Vector3<f64>, direction: &Vector3<f64>, bounds: &[[f64; 3]; 2]) -> f64 {
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for axis in 0..3 {
        let inverse = 1.0 / direction[axis];
        let a = (bounds[0][axis] - origin[axis]) * inverse;
        let b = (bounds[1][axis] - origin[axis]) * inverse;
        let (low, high) = if a < b { (a, b) } else { (b, a) };
        if low.is_nan() || high.is_nan() {
            // Parallel to the slab: inside it or a miss.
            if !(bounds[0][axis]..=bounds[1][axis]).contains(&origin[axis]) {
                return f64::INFINITY;
            }
            continue;
        }
        near = near.max(low);
        far = far.min(high);
    }
    if near > 0.0 && near <= far {
        near
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(origin: [f64; 3], direction: [f64; 3]) -> (Vector3<f64>, Vector3<f64>) {
        (Vector3::from(origin), Vector3::from(direction).normalize())
    }

    #[test]
    fn primitives_are_hit_where_geometry_says() {
        let (o, d) = ray([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let pole = Cylinder {
            centre: [5.0, 0.0],
            axes: [[10.0, 0.0], [0.0, 10.0]],
            z: [0.0, 2.0],
        };
        assert!((pole.hit(&o, &d) - 4.9).abs() < 1e-12);
        assert!((sphere_hit(&o, &d, &Vector3::new(3.0, 0.0, 1.0), 0.5) - 2.5).abs() < 1e-12);
        assert!((box_entry(&o, &d, &[[2.0, -1.0, 0.0], [3.0, 1.0, 2.0]]) - 2.0).abs() < 1e-12);
        assert!((box_exit(&o, &d, &[[-1.0, -1.0, 0.0], [3.0, 1.0, 2.0]]) - 3.0).abs() < 1e-12);
        let (down_o, down_d) = ray([0.0, 0.0, 2.5], [0.0, 0.0, -1.0]);
        assert!((plane_z_hit(&down_o, &down_d, 0.0) - 2.5).abs() < 1e-12);
        // Seen from straight above, a person's head top is the first thing hit.
        let body = Body::new([0.0, 0.0, 1.75], [1.0, 0.0], 0.0);
        assert!((body.hit(&down_o, &down_d) - 0.75).abs() < 1e-12);
        // From the side at chest height the torso's near face along its depth axis.
        let (side_o, side_d) = ray([-5.0, 0.0, 1.2], [1.0, 0.0, 0.0]);
        assert!((body.hit(&side_o, &side_d) - (5.0 - HALF_CHEST_DEPTH_M)).abs() < 1e-12);
        // Past the shoulders beside the head: nothing.
        let (miss_o, miss_d) = ray([-5.0, 0.5, 1.7], [1.0, 0.0, 0.0]);
        assert!(body.hit(&miss_o, &miss_d).is_infinite());
    }
}
