//! Dropping the pieces of a person that are not a person: a LIDAR looking down on people often sees
//! part of a body apart from the rest, as its own segment — an arm or the legs beside the torso, the
//! shoulder or hip a neighbour's body cuts off, a shoulder the range image parts from its head — and each
//! such segment would report a second "head" on the person, a quarter of a metre (a shoulder) to a metre
//! below the real one. Two people's heads are never that close: people stand shoulder to shoulder at
//! most, some 0.45 m from head to head, and a person half a metre shorter than the one beside them stands
//! no closer. So an object whose top is `part_drop` or more below
//! another's and whose reported point lies within `part_reach` of it horizontally is taken for part of
//! that person and dropped.

use super::objects::{DetectedObject, GroundFrame, ObjectConfig};
use nalgebra::Vector3;

/// `objects` without those that are parts of a taller object's person (see the module documentation),
/// in their order.
pub(super) fn drop_body_parts(
    objects: Vec<DetectedObject>,
    ground: &GroundFrame,
    config: &ObjectConfig,
) -> Vec<DetectedObject> {
    let horizontal = |object: &DetectedObject| {
        let p = Vector3::from(object.centre);
        p - ground.up * ground.up.dot(&p)
    };
    let places: Vec<Vector3<f64>> = objects.iter().map(horizontal).collect();
    let is_part = |k: usize| {
        (0..objects.len()).any(|other| {
            objects[other].top_height - objects[k].top_height >= config.part_drop
                && (places[other] - places[k]).norm() < config.part_reach
        })
    };
    let keep: Vec<bool> = (0..objects.len()).map(|k| !is_part(k)).collect();
    objects
        .into_iter()
        .zip(keep)
        .filter_map(|(object, keep)| keep.then_some(object))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn object(cluster: usize, x: f64, y: f64, top_height: f64) -> DetectedObject {
        DetectedObject {
            cluster,
            centre: [x, y, top_height - 2.5],
            top_height,
            width: 0.3,
        }
    }

    #[test]
    fn a_low_piece_beside_a_head_is_dropped_and_a_neighbour_is_kept() {
        let ground = GroundFrame {
            up: Vector3::z(),
            sensor_height: Some(2.5),
        };
        let objects = vec![
            object(0, 1.0, 1.0, 1.75),
            // An arm or the legs, 0.2 m from the head and 0.8 m below it.
            object(1, 1.2, 1.0, 0.95),
            // A neighbour shoulder to shoulder, a little shorter.
            object(2, 1.0, 1.45, 1.62),
            // A low object far from everyone (a child, a dog, a chair: not a body part).
            object(3, 2.5, 0.5, 1.0),
        ];
        let kept: Vec<usize> = drop_body_parts(objects, &ground, &ObjectConfig::default())
            .iter()
            .map(|o| o.cluster)
            .collect();
        assert_eq!(kept, vec![0, 2, 3]);
    }
}
