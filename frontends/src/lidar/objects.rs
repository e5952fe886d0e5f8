//! From a segment's points to the object it is: its centre and the height the project's targets use (the
//! top of the head), and whether it is person-sized at all.
//!
//! Heights and horizontal positions are taken in the ground's frame (up = the ground plane's normal, turned
//! towards the sensor; heights above the plane), so a sensor mounted upside down on a ceiling or tilted
//! gives the same answers as a level one. Without a ground plane (ground removal `none`, or no plane found)
//! up is the sensor's +z, heights are relative to the sensor and the height limits are not applied.
//!
//! The centre: a LIDAR sees one side of a body. On an upright cylinder of radius R swept by rays equally
//! spaced in azimuth, the visible points' mean lies (π/4)·R nearer the sensor than the axis (the mean of
//! √(R² − y²) for y uniform in [−R, R]), so the visible centroid is pushed back along the horizontal ray
//! by that much.

use super::error::LidarConfigError;
use super::ransac_plane::Plane;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_4;

/// What an object's reported point is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimate {
    /// A person: the body axis (visible centroid pushed back by (π/4)·`body_radius`) at the head's top.
    #[default]
    Person,
    /// The mean of the visible points (for objects that are not people; size limits still apply).
    Centroid,
}

/// How objects are estimated and which segments are kept:
///
/// ```toml
/// [objects]
/// estimate = "person"       # or "centroid"
/// body_radius = 0.17        # metres
/// # head_height = 1.75      # metres above the ground; absent: the segment's highest point
/// max_width = 1.2           # metres: wider segments are walls, cars, hedges
/// min_top_height = 0.8      # metres above the ground: lower segments are kerbs, legs, ground noise
/// max_top_height = 2.2      # metres above the ground: taller ones are poles, walls, trees
/// split_width = 0.6         # metres: wider segments may be several people side by side
/// person_spacing = 0.3      # metres: two head tops at least this far apart are two people
/// part_reach = 0.45         # metres: a lower object nearer a taller one than this is part of its person…
/// part_drop = 0.25          # metres: …when its top is at least this much lower
/// centre_std = 0.05         # metres: a reported point's typical error
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObjectConfig {
    /// Person (default) or centroid.
    pub estimate: Estimate,
    /// Horizontal radius of a body, metres. Default 0.17 m: a torso 0.42 m across the shoulders and 0.28 m
    /// deep, as a circle of about the same perimeter.
    pub body_radius: f64,
    /// The reported height above the ground (metres), for sensors that cannot see the top of a head (a level
    /// sensor at head height, whose rings at 20 m are 0.7 m apart). Absent (default): the segment's highest
    /// point, right for a sensor that looks down on people.
    pub head_height: Option<f64>,
    /// Segments wider than this (metres, horizontal extent along or across the ray) are not people. 1.2 m.
    pub max_width: f64,
    /// Segments whose highest point is lower than this above the ground are not people. 0.8 m: a person 25 m
    /// from a VLP-16 at 1.8 m is hit by its −2° ring only, 0.93 m up; legs seen under an arm or a neighbour
    /// reach 0.7 m.
    pub min_top_height: f64,
    /// Segments whose highest point is higher than this above the ground are not people (poles, walls).
    /// 2.2 m.
    pub max_top_height: f64,
    /// A segment wider than this (metres) is looked at for several heads (people standing shoulder to shoulder
    /// form one segment). 0.6 m: wider than one person's shoulders.
    pub split_width: f64,
    /// Head tops at least this far apart horizontally (metres) belong to different people. 0.3 m: closer than
    /// two people's heads can be, farther than one head's points.
    pub person_spacing: f64,
    /// An object whose reported point lies within this horizontal distance (metres) of a taller object's,
    /// and whose top is at least `part_drop` lower, is part of that person (an arm, the legs, a shoulder
    /// seen as its own segment) and is not reported. 0.45 m: about the distance between the heads of two
    /// people shoulder to shoulder. 0 turns it off.
    pub part_reach: f64,
    /// See `part_reach`. 0.25 m: a shoulder or arm seen apart from its head tops out 0.25–0.35 m below the
    /// head's top (on the rendered room), more than two adults standing side by side usually differ. A child
    /// close beside an adult is taken for a part: lower `part_reach` for such scenes.
    pub part_drop: f64,
    /// How far a reported point typically lies from the object's true one, metres (a standard deviation in
    /// each direction); 0 leaves the measurements' uncertainty to the descriptor's `noise_std` alone.
    /// Default 0.05 m. Why: a point is estimated from the part of a body the beams hit, a few centimetres off
    /// however exact the sensor (on the rendered room's ceiling LIDAR the person estimate's RMS error is
    /// 0.046–0.051 m horizontally and 0.033–0.035 m in height, while a sensor noise of 0.01 rad is 1 cm
    /// there); a fusion that takes such points for centimetre-exact lets them pull the cameras' better fixes
    /// aside. Each measurement is then published with its own covariance
    /// ([`crate::lidar::measurement_covariance`]).
    pub centre_std: f64,
}

impl Default for ObjectConfig {
    fn default() -> Self {
        Self {
            estimate: Estimate::Person,
            body_radius: 0.17,
            head_height: None,
            max_width: 1.2,
            min_top_height: 0.8,
            max_top_height: 2.2,
            split_width: 0.6,
            person_spacing: 0.3,
            part_reach: 0.45,
            part_drop: 0.25,
            centre_std: 0.05,
        }
    }
}

impl ObjectConfig {
    /// Every segment is an object, reported at its visible centroid.
    pub fn centroids() -> Self {
        Self {
            estimate: Estimate::Centroid,
            max_width: f64::INFINITY,
            min_top_height: f64::NEG_INFINITY,
            max_top_height: f64::INFINITY,
            split_width: f64::INFINITY,
            part_reach: 0.0,
            ..Self::default()
        }
    }

    /// Checks that the parameters can be used.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the bad parameter.
    pub fn validate(&self) -> Result<(), LidarConfigError> {
        if !(self.body_radius.is_finite() && self.body_radius >= 0.0) {
            return Err(LidarConfigError::NotPositive {
                name: "objects.body_radius",
                value: self.body_radius,
            });
        }
        if !(self.person_spacing.is_finite() && self.person_spacing > 0.0) {
            return Err(LidarConfigError::NotPositive {
                name: "objects.person_spacing",
                value: self.person_spacing,
            });
        }
        for (name, value) in [
            ("objects.part_reach", self.part_reach),
            ("objects.part_drop", self.part_drop),
            ("objects.centre_std", self.centre_std),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(LidarConfigError::Negative { name, value });
            }
        }
        if self.max_width.is_nan() || self.max_width <= 0.0 {
            return Err(LidarConfigError::NotPositive {
                name: "objects.max_width",
                value: self.max_width,
            });
        }
        for (name, value) in [
            ("objects.min_top_height", self.min_top_height),
            ("objects.max_top_height", self.max_top_height),
            ("objects.head_height", self.head_height.unwrap_or(0.0)),
        ] {
            if value.is_nan() || (name == "objects.head_height" && !value.is_finite()) {
                return Err(LidarConfigError::NotFinite { name, value });
            }
        }
        Ok(())
    }
}

/// The ground's frame: up, and the height of the sensor origin above the ground (0 without a ground).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundFrame {
    /// Unit up vector in the sensor frame.
    pub up: Vector3<f64>,
    /// Height of the sensor above the ground, metres, if a ground plane is known.
    pub sensor_height: Option<f64>,
}

impl GroundFrame {
    /// The frame of a ground plane, its normal turned towards the sensor; sensor +z without one.
    pub fn new(plane: Option<&Plane>) -> Self {
        match plane {
            // The origin's signed distance is the offset; the sensor is above the ground.
            Some(plane) if plane.offset < 0.0 => Self {
                up: -plane.normal,
                sensor_height: Some(-plane.offset),
            },
            Some(plane) => Self {
                up: plane.normal,
                sensor_height: Some(plane.offset),
            },
            None => Self {
                up: Vector3::z(),
                sensor_height: None,
            },
        }
    }
}

/// One object found in a scan.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectedObject {
    /// Index of its segment in [`super::Segmentation::clusters`].
    pub cluster: usize,
    /// The reported point (sensor frame, metres): see [`Estimate`].
    pub centre: [f64; 3],
    /// Height of the segment's highest point above the ground (above the sensor without a ground).
    pub top_height: f64,
    /// Largest horizontal extent, along or across the ray (metres).
    pub width: f64,
}

/// The object of the segment `indices` of `points` (segment number `cluster`), or `None` when it is not
/// person-sized.
pub fn detect_object(
    points: &[[f64; 3]],
    (cluster, indices): (usize, &[usize]),
    ground: &GroundFrame,
    config: &ObjectConfig,
) -> Option<DetectedObject> {
    let up = ground.up;
    let base = ground.sensor_height.unwrap_or(0.0);
    let count = indices.len() as f64;
    let (mut horizontal_sum, mut sum, mut top) =
        (Vector3::zeros(), Vector3::zeros(), f64::NEG_INFINITY);
    for &i in indices {
        let p = Vector3::from(points[i]);
        let along_up = up.dot(&p);
        horizontal_sum += p - up * along_up;
        sum += p;
        top = top.max(along_up + base);
    }
    let horizontal = horizontal_sum / count;
    let width = horizontal_extent(points, indices, &up, &horizontal);
    let limits_apply = ground.sensor_height.is_some();
    let top_ok = !limits_apply || (config.min_top_height..=config.max_top_height).contains(&top);
    if width > config.max_width || !top_ok {
        return None;
    }
    let centre = match config.estimate {
        Estimate::Centroid => sum / count,
        Estimate::Person => {
            let distance = horizontal.norm();
            let axis = if distance > 0.0 {
                horizontal * (1.0 + FRAC_PI_4 * config.body_radius / distance)
            } else {
                horizontal
            };
            let height = config.head_height.filter(|_| limits_apply).unwrap_or(top);
            axis + up * (height - base)
        }
    };
    Some(DetectedObject {
        cluster,
        centre: centre.into(),
        top_height: top,
        width,
    })
}

/// The spread of the points' horizontal positions along the ray to `mean` and across it.
fn horizontal_extent(
    points: &[[f64; 3]],
    indices: &[usize],
    up: &Vector3<f64>,
    mean: &Vector3<f64>,
) -> f64 {
    let along = if mean.norm() > 0.0 {
        mean.normalize()
    } else {
        up.cross(&Vector3::x()).normalize()
    };
    let across = up.cross(&along);
    let mut bounds = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
    for &i in indices {
        let p = Vector3::from(points[i]);
        for (axis, bound) in [along, across].iter().zip(bounds.iter_mut()) {
            let value = axis.dot(&p);
            bound[0] = bound[0].min(value);
            bound[1] = bound[1].max(value);
        }
    }
    bounds
        .iter()
        .map(|[low, high]| high - low)
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cylinders_visible_side_is_pushed_back_to_its_axis() {
        // The near half of a cylinder of radius 0.2 at 10 m, seen from the origin, rays 0.2° apart.
        let radius = 0.2;
        let mut points = Vec::new();
        for k in -6..=6 {
            let azimuth = (0.2 * k as f64).to_radians();
            // Ray–circle intersection with the circle centred at (10, 0).
            let (s, c) = azimuth.sin_cos();
            let b = 10.0 * c;
            let disc = b * b - (100.0 - radius * radius);
            if disc < 0.0 {
                continue;
            }
            let t = b - disc.sqrt();
            for z in [-0.5, 0.0, 0.3] {
                points.push([t * c, t * s, z]);
            }
        }
        let indices: Vec<usize> = (0..points.len()).collect();
        let ground = GroundFrame {
            up: Vector3::z(),
            sensor_height: Some(1.8),
        };
        let config = ObjectConfig {
            body_radius: radius,
            ..ObjectConfig::default()
        };
        let object = detect_object(&points, (0, &indices), &ground, &config).unwrap();
        let (centre, top, width) = (object.centre, object.top_height, object.width);
        println!("centre {centre:?}, top {top:.2}, width {width:.3}");
        assert!((centre[0] - 10.0).abs() < 0.02, "{centre:?}");
        assert!(centre[1].abs() < 1e-9);
        assert!((top - 2.1).abs() < 1e-12 && (centre[2] - 0.3).abs() < 1e-12);
        let pole = ObjectConfig {
            max_top_height: 2.0,
            ..config.clone()
        };
        assert!(detect_object(&points, (0, &indices), &ground, &pole).is_none());
        let narrow = ObjectConfig {
            max_width: 0.2,
            ..config
        };
        assert!(detect_object(&points, (0, &indices), &ground, &narrow).is_none());
    }

    #[test]
    fn the_ground_frame_points_up_towards_the_sensor() {
        // A ceiling sensor upside down: the floor is the plane z = 2.5 of its frame.
        let floor = Plane {
            normal: Vector3::z(),
            offset: -2.5,
        };
        let frame = GroundFrame::new(Some(&floor));
        assert_eq!(frame.up, -Vector3::z());
        assert_eq!(frame.sensor_height, Some(2.5));
        let level = GroundFrame::new(Some(&Plane {
            normal: Vector3::z(),
            offset: 1.8,
        }));
        assert_eq!((level.up, level.sensor_height), (Vector3::z(), Some(1.8)));
    }
}
