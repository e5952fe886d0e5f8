//! Splitting a segment that holds several people: people who stand close together (shoulders touching,
//! seen from above) form one segment, since nothing separates their surfaces in range. Their heads stay
//! apart: the segment's highest point is a head top, the highest point more than `person_spacing` away
//! (horizontally) from every head found so far is the next, and each point goes to the nearest head.

use super::objects::{GroundFrame, ObjectConfig};
use nalgebra::Vector3;

/// At most this many heads are looked for in one segment (a wall is not a crowd).
const MAX_HEADS: usize = 16;
/// The part of a head below its top that locates it, m: about a head's radius.
const HEAD_DEPTH_M: f64 = 0.12;

/// The segment `indices` of `points` as one group per person (its point indices); the segment unchanged when it
/// is no wider than `config.split_width` or holds one head.
pub(super) fn split_people(
    points: &[[f64; 3]],
    indices: &[usize],
    ground: &GroundFrame,
    config: &ObjectConfig,
) -> Vec<Vec<usize>> {
    let base = ground.sensor_height.unwrap_or(0.0);
    let placed: Vec<(Vector3<f64>, f64)> = indices
        .iter()
        .map(|&i| {
            let p = Vector3::from(points[i]);
            let along_up = ground.up.dot(&p);
            (p - ground.up * along_up, along_up + base)
        })
        .collect();
    if horizontal_span(&placed) <= config.split_width {
        return vec![indices.to_vec()];
    }
    let mut order: Vec<usize> = (0..placed.len()).collect();
    order.sort_by(|&a, &b| placed[b].1.total_cmp(&placed[a].1));
    let mut heads: Vec<(Vector3<f64>, f64)> = Vec::new();
    for &k in &order {
        let (position, height) = &placed[k];
        if heads.len() == MAX_HEADS || *height < config.min_top_height {
            break;
        }
        if heads
            .iter()
            .all(|(h, _)| (h - position).norm() > config.person_spacing)
        {
            heads.push((*position, *height));
        }
    }
    if heads.len() < 2 {
        return vec![indices.to_vec()];
    }
    let heads: Vec<Vector3<f64>> = heads
        .iter()
        .map(|seed| head_centre(&placed, seed, config))
        .collect();
    let mut groups = vec![Vec::new(); heads.len()];
    for (k, (position, _)) in placed.iter().enumerate() {
        let nearest = (0..heads.len())
            .min_by(|&a, &b| {
                (heads[a] - position)
                    .norm()
                    .total_cmp(&(heads[b] - position).norm())
            })
            .unwrap_or(0);
        groups[nearest].push(indices[k]);
    }
    groups
}

/// The horizontal centre of the head whose highest point is `seed`: the mean of the points within half the
/// person spacing of it and at most [`HEAD_DEPTH_M`] below it (the seed is the cap's edge nearest the sensor,
/// not the head's middle).
fn head_centre(
    placed: &[(Vector3<f64>, f64)],
    (seed, top): &(Vector3<f64>, f64),
    config: &ObjectConfig,
) -> Vector3<f64> {
    let (mut sum, mut count) = (Vector3::zeros(), 0.0);
    for (position, height) in placed {
        if *height >= top - HEAD_DEPTH_M && (position - seed).norm() <= 0.5 * config.person_spacing
        {
            sum += position;
            count += 1.0;
        }
    }
    sum / count
}

/// The largest distance between the first point and any other, horizontally: a cheap bound on the width.
fn horizontal_span(placed: &[(Vector3<f64>, f64)]) -> f64 {
    let Some((first, _)) = placed.first() else {
        return 0.0;
    };
    placed
        .iter()
        .map(|(p, _)| (p - first).norm())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_heads_on_touching_bodies_make_two_groups() {
        // Seen from a level frame: two columns of points 0.45 m apart, tops at 1.75 and 1.6 m above the ground.
        let mut points = Vec::new();
        for (x, top) in [(5.0, 1.75), (5.45, 1.6)] {
            for k in 0..10 {
                for dx in [-0.1, -0.03, 0.03, 0.1] {
                    points.push([x + dx, 0.0, top - 1.8 - 0.1 * k as f64]);
                }
            }
        }
        let indices: Vec<usize> = (0..points.len()).collect();
        let ground = GroundFrame {
            up: Vector3::z(),
            sensor_height: Some(1.8),
        };
        let groups = split_people(&points, &indices, &ground, &ObjectConfig::default());
        let sizes: Vec<usize> = groups.iter().map(Vec::len).collect();
        println!("groups {sizes:?}");
        assert_eq!(sizes, vec![40, 40]);
        assert!(groups[0].iter().all(|&i| points[i][0] < 5.2));
        let one = split_people(
            &points[..40],
            &indices[..40],
            &ground,
            &ObjectConfig::default(),
        );
        assert_eq!(one.len(), 1);
    }
}
