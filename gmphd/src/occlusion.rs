//! Detection probability lowered where a nearer object stands in a sensor's line of sight.
//!
//! A camera or a LIDAR does not see a person behind another: the front end reports nothing of
//! the hidden one for as long as the two stay in line, often a second or two. With a p_D that
//! ignores this, each of those sets counts as a miss, and a track the filter was sure of is
//! deleted and born again once the person reappears (a new identity, and a wrong count
//! meanwhile). Here a component's p_D for such a sensor is scaled by the share of it that the
//! other objects leave visible, as in the state-dependent detection probability of
//! multi-object filters with occlusion (Mahler, *Statistical Multisource-Multitarget Information
//! Fusion*, 2007, sec. 12.6; Beard, Vo & Vo, "Bayesian multi-target tracking with merged
//! measurements using labelled random finite sets", IEEE TSP 63(6), 2015).
//!
//! People stand on a floor at z = 0 and a position is the top of the head (what the cameras
//! and the LIDAR front ends report). So each object is a vertical body of `radius` from the
//! floor up to its position, and what a sensor must see of it to report it is the head and
//! shoulders, its top [`VISIBLE_TOP_M`]:
//!
//! * the **blockers** are the components of the predicted intensity heavy enough to stand for an
//!   object (weight at least [`BLOCKER_WEIGHT`]);
//! * in the horizontal plane, a blocker is in the way when it lies between the sensor and the
//!   component (nearer by more than `radius`: two labels of one object do not hide each other)
//!   within `2 · radius` of the line between them; how much of the component's width it covers
//!   falls from 1 on that line to 0 at `2 · radius`;
//! * seen from the sensor, the blocker's top casts a shadow on the component's vertical line up to
//!   the height where the ray over the blocker's head meets it: of the component's top, the part
//!   below that height is covered. A ceiling sensor looks over the heads of people near it; a
//!   sensor at head height is blocked by anyone in line;
//! * the component's p_D is multiplied by what all blockers leave,
//!   `Π (1 − width covered · top covered · blocker weight)`.
//!
//! Sensors that hear or sense around people (a microphone pair) or that have no origin (a
//! position sensor) have no [`MeasurementModel::line_of_sight_origin`] and are not affected.

use nalgebra::Vector3;

use crate::error::{invalid, FilterError};
use crate::gaussian::{GaussianMixture, Label};
use crate::measurement::MeasurementModel;
use crate::motion::MotionModel;

/// Least weight of a component that can hide others: one that the extraction would report.
pub const BLOCKER_WEIGHT: f64 = 0.5;

/// How much of a person's top, in metres, a sensor must see to report the person: the head and
/// shoulders.
pub const VISIBLE_TOP_M: f64 = 0.3;

/// The objects' size as far as blocking a sensor's view goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Occlusion {
    radius: f64,
}

impl Occlusion {
    /// Objects that block the view within `radius` metres of their position (a person's
    /// half-width across the shoulders, about 0.25 m).
    pub fn new(radius: f64) -> Result<Self, FilterError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(invalid(
                "occlusion radius",
                format!("{radius} m is not a positive number"),
            ));
        }
        Ok(Self { radius })
    }

    /// The blockers of `predicted` as `sensor` sees them, `None` for a sensor whose view
    /// nothing blocks.
    pub fn blockers(
        &self,
        predicted: &GaussianMixture,
        motion: &dyn MotionModel,
        sensor: &dyn MeasurementModel,
    ) -> Option<Blockers> {
        let origin = sensor.line_of_sight_origin()?;
        let bodies = predicted
            .iter()
            .filter(|c| c.weight >= BLOCKER_WEIGHT)
            .map(|c| {
                let position = motion.position(&c.mean);
                Body {
                    label: c.label,
                    range: horizontal(position - origin).norm(),
                    position,
                    weight: c.weight.min(1.0),
                }
            })
            .collect();
        Some(Blockers {
            origin,
            radius: self.radius,
            bodies,
        })
    }
}

/// One blocker: a heavy component's position, its horizontal range from the sensor, label and
/// weight.
#[derive(Debug, Clone, Copy)]
struct Body {
    label: Label,
    position: Vector3<f64>,
    range: f64,
    weight: f64,
}

/// What may block one sensor's view during one update.
#[derive(Debug, Clone)]
pub struct Blockers {
    origin: Vector3<f64>,
    radius: f64,
    bodies: Vec<Body>,
}

impl Blockers {
    /// The share of an object of `label` at `position` (its top) that the blockers leave in
    /// view, in [0, 1].
    pub fn visible_share(&self, label: Label, position: &Vector3<f64>) -> f64 {
        let sight = horizontal(position - self.origin);
        let range = sight.norm();
        if range <= self.radius {
            return 1.0;
        }
        let direction = sight / range;
        self.bodies
            .iter()
            .filter(|body| body.label != label && body.range < range - self.radius)
            .map(|body| 1.0 - self.covered(body, position, range, &direction) * body.weight)
            .product()
    }

    /// The share of the object at `position` (horizontal range `range` in `direction`) that
    /// `body` covers, were it surely there.
    fn covered(
        &self,
        body: &Body,
        position: &Vector3<f64>,
        range: f64,
        direction: &Vector3<f64>,
    ) -> f64 {
        let offset = horizontal(body.position - self.origin);
        let along = offset.dot(direction);
        if along <= 0.0 {
            return 0.0;
        }
        let off_line = (offset - direction * along).norm();
        let width = (1.0 - off_line / (2.0 * self.radius)).clamp(0.0, 1.0);
        // The ray over the blocker's top, continued to the object's vertical line.
        let eye = self.origin.z;
        let shadow_top = eye + (body.position.z - eye) * range / along;
        let top = ((shadow_top - (position.z - VISIBLE_TOP_M)) / VISIBLE_TOP_M).clamp(0.0, 1.0);
        width * top
    }
}

/// `v` with its height set to 0.
fn horizontal(v: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, v.y, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Gaussian;
    use crate::measurement::{Detection, Lidar, MicPair};
    use crate::motion::RandomWalk;
    use nalgebra::{DMatrix, DVector};

    fn person(label: u64, x: f64, y: f64, weight: f64) -> Gaussian {
        Gaussian::new(
            weight,
            DVector::from_vec(vec![x, y, 1.7]),
            DMatrix::identity(3, 3) * 0.01,
            Label(label),
        )
    }

    fn level_lidar() -> Lidar {
        Lidar::new(
            [0.0, 0.0, 1.7],
            [1.0, 0.0, 0.0, 0.0],
            [0.05, 0.01, 0.01],
            50.0,
            [-0.3, 0.3],
            Detection::new(0.9, 1.0).unwrap(),
        )
        .unwrap()
    }

    #[test]
    fn a_person_behind_another_is_hidden_and_one_beside_is_not() {
        let motion = RandomWalk::new(3, 0.1, 1.7).unwrap();
        let mixture = GaussianMixture::from_components(vec![
            person(1, 5.0, 0.0, 1.0),
            person(2, 12.0, 0.0, 1.0),
        ]);
        let blockers = Occlusion::new(0.25)
            .unwrap()
            .blockers(&mixture, &motion, &level_lidar())
            .unwrap();
        let at = |x: f64, y: f64| Vector3::new(x, y, 1.7);
        assert!(
            blockers.visible_share(Label(2), &at(12.0, 0.0)) < 1e-9,
            "right behind"
        );
        let half = blockers.visible_share(Label(2), &at(12.0, 0.6));
        assert!(half > 0.4 && half < 0.6, "half behind: {half}");
        assert_eq!(
            blockers.visible_share(Label(2), &at(12.0, 2.0)),
            1.0,
            "well beside"
        );
        assert_eq!(
            blockers.visible_share(Label(1), &at(5.0, 0.0)),
            1.0,
            "in front"
        );
        // A second label of the nearer person itself does not hide it.
        assert_eq!(blockers.visible_share(Label(3), &at(5.1, 0.0)), 1.0);
    }

    #[test]
    fn a_ceiling_sensor_looks_over_the_heads_of_people_near_it() {
        let motion = RandomWalk::new(3, 0.1, 1.7).unwrap();
        let ceiling = Lidar::new(
            [0.0, 0.0, 2.5],
            [0.0, 1.0, 0.0, 0.0],
            [0.05, 0.01, 0.01],
            10.0,
            [0.0, 1.5],
            Detection::new(0.9, 1.0).unwrap(),
        )
        .unwrap();
        let mixture = GaussianMixture::from_components(vec![person(1, 0.5, 0.0, 1.0)]);
        let blockers = Occlusion::new(0.25)
            .unwrap()
            .blockers(&mixture, &motion, &ceiling)
            .unwrap();
        // One metre out the ray to a head passes 0.375 m over the nearer head: seen.
        assert_eq!(
            blockers.visible_share(Label(2), &Vector3::new(1.0, 0.0, 1.7)),
            1.0
        );
        // Behind it, the rays over the nearer head reach the floor 0.6 m on: seen again.
        assert_eq!(
            blockers.visible_share(Label(2), &Vector3::new(3.0, 0.0, 1.7)),
            1.0
        );
        // Someone 0.4 m behind a person far out is hidden below 1.58 m: 0.59 of head and
        // shoulders.
        let far = GaussianMixture::from_components(vec![person(1, 2.6, 0.0, 1.0)]);
        let blockers = Occlusion::new(0.25)
            .unwrap()
            .blockers(&far, &motion, &ceiling)
            .unwrap();
        let share = blockers.visible_share(Label(2), &Vector3::new(3.0, 0.0, 1.7));
        assert!((share - 0.41).abs() < 0.01, "{share}");
    }

    #[test]
    fn light_components_hide_nothing_and_a_mic_pair_sees_around_people() {
        let motion = RandomWalk::new(3, 0.1, 1.7).unwrap();
        let occlusion = Occlusion::new(0.25).unwrap();
        let light = GaussianMixture::from_components(vec![person(1, 5.0, 0.0, 0.3)]);
        let blockers = occlusion.blockers(&light, &motion, &level_lidar()).unwrap();
        assert_eq!(
            blockers.visible_share(Label(2), &Vector3::new(12.0, 0.0, 1.7)),
            1.0
        );
        let pair = MicPair::new(
            [0.0, 0.0, 1.5],
            [0.5, 0.0, 1.5],
            343.0,
            6e-5,
            Detection::new(0.7, 1.0).unwrap(),
        )
        .unwrap();
        assert!(occlusion.blockers(&light, &motion, &pair).is_none());
        assert!(Occlusion::new(0.0).is_err());
    }
}
