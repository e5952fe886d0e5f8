//! The filter on synthetic foreground maps: people drawn as the person model's regions.

use nalgebra::{Matrix3, Matrix3x4, Vector3};

use super::*;
use crate::camera::multi_bernoulli::{ForegroundMap, PersonProjector, Region};

/// A camera at `eye` looking at `target`, 500 px focal length, 640 × 480, no roll.
fn look_at(eye: [f64; 3], target: [f64; 3]) -> [[f64; 4]; 3] {
    let eye = Vector3::from(eye);
    let forward = (Vector3::from(target) - eye).normalize();
    let right = forward.cross(&Vector3::z()).normalize();
    let down = forward.cross(&right);
    let rotation = Matrix3::from_rows(&[right.transpose(), down.transpose(), forward.transpose()]);
    let k = Matrix3::new(500.0, 0.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0);
    let mut extrinsics = Matrix3x4::zeros();
    extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    extrinsics.set_column(3, &(-rotation * eye));
    let p = k * extrinsics;
    std::array::from_fn(|r| std::array::from_fn(|c| p[(r, c)]))
}

fn room_camera() -> [[f64; 4]; 3] {
    look_at([0.0, 0.0, 2.5], [1.5, 1.0, 1.2])
}

/// A foreground map in which the people `(x, y, height)` are foreground (1) and the rest background
/// (0), with a speck of noise every few pixels.
fn draw(projector: &PersonProjector, people: &[(f64, f64, f64)]) -> ForegroundMap {
    let [width, height] = [320usize, 240usize];
    let mut values = vec![0.0f32; width * height];
    for (k, v) in values.iter_mut().enumerate() {
        if k % 97 == 0 {
            *v = 1.0;
        }
    }
    let mut region = Region::default();
    for &(x, y, h) in people {
        assert!(projector.rasterise(x, y, h, &mut region));
        for span in &region.spans {
            if span.row < 0 || span.row as usize >= height {
                continue;
            }
            let left = span.left.round().max(0.0) as usize;
            let right = (span.right.round().max(0.0) as usize).min(width);
            for col in left..right {
                values[span.row as usize * width + col] = 1.0;
            }
        }
    }
    let mut map = ForegroundMap::default();
    map.fill(width, height, &values, 0.5);
    map
}

fn published(estimates: &[PersonEstimate], config: &MultiBernoulliConfig) -> Vec<PersonEstimate> {
    estimates
        .iter()
        .filter(|e| {
            e.reported_frames >= config.confirm_frames && e.visible_head >= config.min_visible_head
        })
        .cloned()
        .collect()
}

#[test]
fn a_single_person_is_found_where_it_stands() {
    let config = MultiBernoulliConfig::default();
    let mut filter = MultiBernoulliFilter::new(config.clone(), room_camera(), [640, 480]).unwrap();
    let person = (1.8, 1.1, 1.72);
    let map = draw(filter.projector(), &[person]);
    let truth = filter
        .projector()
        .head_top(person.0, person.1, person.2)
        .unwrap();
    let mut last = Vec::new();
    for k in 0..25 {
        last = filter.step(k as f64 * 0.04, &map);
    }
    let shown = published(&last, &config);
    assert_eq!(shown.len(), 1, "{last:?}");
    let e = &shown[0];
    let error = (e.head[0] - truth[0]).hypot(e.head[1] - truth[1]);
    assert!(error < 3.0, "head {:?} against {truth:?}", e.head);
    assert!(
        (e.floor[0] - person.0).hypot(e.floor[1] - person.1) < 0.1,
        "{e:?}"
    );
    // The particles' spread (under 5 px) plus the person model's own error seen through f = 500 px
    // from the person's 2.1 m (at least 2 m): 0.04 m is some 9.5 px.
    let model_px = config.head_model_error * 500.0 / 2.0;
    assert!(
        e.covariance[0][0] > 0.0 && e.covariance[0][0] < 25.0 + model_px * model_px,
        "{e:?}"
    );
    assert!(e.visible_head > 0.9);
}

#[test]
fn an_empty_room_gives_no_estimate() {
    let config = MultiBernoulliConfig::default();
    let mut filter = MultiBernoulliFilter::new(config, room_camera(), [640, 480]).unwrap();
    let map = draw(filter.projector(), &[]);
    for k in 0..20 {
        assert!(filter.step(k as f64 * 0.04, &map).is_empty());
    }
}

/// Two people cross the camera's line of sight, one behind the other: their regions merge into one
/// foreground region and split again. Both stay estimates throughout, and both are published near their
/// heads once apart.
#[test]
fn two_people_merging_and_splitting_keep_two_estimates() {
    let config = MultiBernoulliConfig::default();
    let mut filter = MultiBernoulliFilter::new(config.clone(), room_camera(), [640, 480]).unwrap();
    let dt = 0.04;
    // Seen from (0, 0): the near person walks along y from 0.3 to 1.5 at x 1.2, the far one back from
    // 1.9 to 0.5 at x 2.4; their lines of sight cross halfway.
    let people = |k: usize| {
        let t = k as f64 * dt;
        [(1.2, 0.3 + 0.4 * t, 1.7), (2.4, 1.9 - 0.45 * t, 1.82)]
    };
    let frames = 75;
    let mut counts = Vec::new();
    let mut last = Vec::new();
    for k in 0..frames {
        let truth = people(k);
        last = filter.step(k as f64 * dt, &draw(filter.projector(), &truth));
        counts.push(last.len());
    }
    println!("estimates per frame: {counts:?}");
    assert!(counts[10..].iter().all(|&n| n == 2), "{counts:?}");
    let shown = published(&last, &config);
    assert_eq!(shown.len(), 2, "{last:?}");
    for (x, y, h) in people(frames - 1) {
        let head = filter.projector().head_top(x, y, h).unwrap();
        let nearest = shown
            .iter()
            .map(|e| (e.head[0] - head[0]).hypot(e.head[1] - head[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 4.0, "head {head:?}: {shown:?}");
    }
}
