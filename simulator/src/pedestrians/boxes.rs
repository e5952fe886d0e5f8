//! The camera's side of the pedestrian sequences: projecting people to boxes, courses through the view,
//! the true boxes of each frame and the detector's boxes made from them, as MOT text.

use std::fmt::Write as _;

use nalgebra::{Matrix3x4, Vector2, Vector4};
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

use super::{walk, CrowdConfig, PersonAt};
use crate::camera_pose::LookAt;
use crate::error::{invalid, ScenarioError};

/// Box width over box height of a walking person.
const ASPECT: f64 = 0.41;
/// Heights of false boxes, px.
const FALSE_BOX_HEIGHT_PX: (f64, f64) = (60.0, 300.0);
/// Step along a course when looking for where it leaves the image, and the farthest it looks, metres.
const COURSE_STEP_M: (f64, f64) = (0.1, 200.0);
/// How far outside the image a course starts and ends (beyond side-by-side neighbours), metres.
const OUTSIDE_M: f64 = 2.5;
/// Head height used to place courses, metres.
const COURSE_HEAD_M: f64 = 1.72;
/// Salt of the detector's random stream, so that it differs from the walkers' of the same seed.
const DETECTOR_SALT: u64 = 0x6465_7465_6374_6f72;

/// One MOT box: `frame, id, left, top, width, height` (frames from 1, id −1 for detections).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotBox {
    /// MOT frame number, from 1.
    pub frame: usize,
    /// Identity (−1 for a detection).
    pub id: i64,
    /// Left edge, px.
    pub left: f64,
    /// Top edge, px.
    pub top: f64,
    /// Width, px.
    pub width: f64,
    /// Height, px.
    pub height: f64,
}

impl MotBox {
    /// The MOT text line, score 1 and no world coordinates.
    fn line(&self) -> String {
        format!(
            "{},{},{:.2},{:.2},{:.2},{:.2},1,-1,-1,-1",
            self.frame, self.id, self.left, self.top, self.width, self.height
        )
    }
}

/// A generated sequence: the camera, the true boxes and the detections of every frame.
#[derive(Debug, Clone, PartialEq)]
pub struct CrowdSequence {
    /// The camera's projection, rows as the protocol writes them.
    pub projection: [[f64; 4]; 3],
    /// Image `[width, height]`, px.
    pub image_size: [u32; 2],
    /// Frames per second.
    pub fps: f64,
    /// True boxes of each frame (those whose head point is in the image).
    pub truth: Vec<Vec<MotBox>>,
    /// Detections of each frame.
    pub detections: Vec<Vec<MotBox>>,
}

impl CrowdSequence {
    /// Walks the crowd of `config` and films it.
    pub fn generate(config: &CrowdConfig) -> Result<Self, ScenarioError> {
        let projector = Projector::new(&config.camera)?;
        let people = walk(config)?;
        let truth: Vec<Vec<MotBox>> = people
            .iter()
            .enumerate()
            .map(|(k, frame)| {
                frame
                    .iter()
                    .filter_map(|p| projector.true_box(k + 1, p))
                    .collect()
            })
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(config.seed ^ DETECTOR_SALT);
        let mut detections = Vec::with_capacity(truth.len());
        for (k, frame) in truth.iter().enumerate() {
            detections.push(detect(config, &projector, &mut rng, k + 1, frame)?);
        }
        Ok(Self {
            projection: projector.rows,
            image_size: config.camera.image_size,
            fps: config.fps,
            truth,
            detections,
        })
    }

    /// The ground truth as a MOT `gt.txt`.
    pub fn gt_txt(&self) -> String {
        mot_text(&self.truth)
    }

    /// The detections as a MOT `det.txt`.
    pub fn det_txt(&self) -> String {
        mot_text(&self.detections)
    }
}

fn mot_text(frames: &[Vec<MotBox>]) -> String {
    let mut text = String::new();
    for b in frames.iter().flatten() {
        let _ = writeln!(text, "{}", b.line());
    }
    text
}

/// One frame of the detector: the true boxes it finds, jittered, and its false boxes.
fn detect(
    config: &CrowdConfig,
    projector: &Projector,
    rng: &mut ChaCha8Rng,
    frame: usize,
    truth: &[MotBox],
) -> Result<Vec<MotBox>, ScenarioError> {
    let jitter = Normal::new(0.0, config.edge_jitter_px)
        .map_err(|e| invalid("pedestrian edge_jitter_px", e.to_string()))?;
    let mut out = Vec::with_capacity(truth.len() + 4);
    for b in truth {
        if rng.gen::<f64>() < config.miss_probability {
            continue;
        }
        let [l, t, r, bottom] = [b.left, b.top, b.left + b.width, b.top + b.height]
            .map(|edge| edge + jitter.sample(rng));
        out.push(MotBox {
            frame,
            id: -1,
            left: l,
            top: t,
            width: (r - l).max(1.0),
            height: (bottom - t).max(1.0),
        });
    }
    let false_boxes = if config.false_boxes_per_frame > 0.0 {
        Poisson::new(config.false_boxes_per_frame)
            .map_err(|e| invalid("pedestrian false_boxes_per_frame", e.to_string()))?
            .sample(rng) as usize
    } else {
        0
    };
    let [w, h] = projector.size;
    for _ in 0..false_boxes {
        let height = rng.gen_range(FALSE_BOX_HEIGHT_PX.0..FALSE_BOX_HEIGHT_PX.1);
        let width = ASPECT * height;
        let (u, v) = (rng.gen::<f64>() * w, rng.gen::<f64>() * h);
        out.push(MotBox {
            frame,
            id: -1,
            left: u - width / 2.0,
            top: v,
            width,
            height,
        });
    }
    Ok(out)
}

/// The camera as the generator uses it.
pub(super) struct Projector {
    rows: [[f64; 4]; 3],
    matrix: Matrix3x4<f64>,
    size: [f64; 2],
}

impl Projector {
    /// The camera of `pose`, checked.
    pub(super) fn new(pose: &LookAt) -> Result<Self, ScenarioError> {
        let rows = pose.projection()?;
        Ok(Self {
            rows,
            matrix: Matrix3x4::from_fn(|r, c| rows[r][c]),
            size: pose.image_size.map(f64::from),
        })
    }

    /// The pixel of a world point, if it is in front of the camera.
    fn project(&self, x: f64, y: f64, z: f64) -> Option<[f64; 2]> {
        let p = self.matrix * Vector4::new(x, y, z, 1.0);
        (p.z > 1e-6).then(|| [p.x / p.z, p.y / p.z])
    }

    fn in_image(&self, [u, v]: [f64; 2]) -> bool {
        (0.0..self.size[0]).contains(&u) && (0.0..self.size[1]).contains(&v)
    }

    /// Whether the head of a person standing at `ground` is in the image.
    fn head_visible(&self, ground: Vector2<f64>) -> bool {
        self.project(ground.x, ground.y, COURSE_HEAD_M)
            .is_some_and(|p| self.in_image(p))
    }

    /// The box of a person in frame `frame`, if the head point is in the image.
    fn true_box(&self, frame: usize, person: &PersonAt) -> Option<MotBox> {
        let [x, y] = person.position;
        let head = self.project(x, y, person.head_height)?;
        let feet = self.project(x, y, 0.0)?;
        let height = feet[1] - head[1];
        if !(self.in_image(head) && height > 1.0) {
            return None;
        }
        let width = ASPECT * height;
        Some(MotBox {
            frame,
            id: person.id as i64,
            left: head[0] - width / 2.0,
            top: head[1],
            width,
            height,
        })
    }

    /// A course through a random visible point in a random direction, from [`OUTSIDE_M`] before it enters
    /// the image to as far after it leaves.
    pub(super) fn course(&self, rng: &mut ChaCha8Rng) -> (Vector2<f64>, Vector2<f64>) {
        let through = loop {
            let candidate = Vector2::new(rng.gen_range(-40.0..40.0), rng.gen_range(0.0..60.0));
            if self.head_visible(candidate) {
                break candidate;
            }
        };
        let angle = rng.gen_range(0.0..std::f64::consts::TAU);
        let direction = Vector2::new(angle.cos(), angle.sin());
        (
            self.exit(through, -direction),
            self.exit(through, direction),
        )
    }

    /// [`OUTSIDE_M`] beyond where the course from `from` along `direction` leaves the image.
    fn exit(&self, from: Vector2<f64>, direction: Vector2<f64>) -> Vector2<f64> {
        let (step, limit) = COURSE_STEP_M;
        let mut travelled = 0.0;
        while travelled < limit && self.head_visible(from + travelled * direction) {
            travelled += step;
        }
        from + (travelled + OUTSIDE_M) * direction
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detections_miss_jitter_and_add_false_boxes_as_configured() {
        let config = CrowdConfig::street(5, 12);
        let sequence = CrowdSequence::generate(&config).unwrap();
        let true_boxes: usize = sequence.truth.iter().map(Vec::len).sum();
        let detections: usize = sequence.detections.iter().map(Vec::len).sum();
        let frames = sequence.truth.len() as f64;
        let expected = 0.9 * true_boxes as f64 + 2.0 * frames;
        let heights: Vec<f64> = sequence.truth.iter().flatten().map(|b| b.height).collect();
        let (low, high) = heights
            .iter()
            .fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        println!(
            "{frames} frames, {true_boxes} true boxes ({:.1} a frame, {low:.0}–{high:.0} px high), \
             {detections} detections (expected {expected:.0})",
            true_boxes as f64 / frames
        );
        assert!((detections as f64 - expected).abs() < 0.03 * expected);
        assert!(sequence.det_txt().lines().count() == detections);
        assert!(sequence.gt_txt().lines().count() == true_boxes);
    }

    #[test]
    fn people_enter_and_leave_at_the_image_borders() {
        let sequence = CrowdSequence::generate(&CrowdConfig::street(8, 8)).unwrap();
        let [w, h] = sequence.image_size.map(f64::from);
        let mut first_seen = std::collections::BTreeMap::new();
        for b in sequence.truth.iter().skip(1).flatten() {
            first_seen
                .entry(b.id)
                .or_insert((b.left + b.width / 2.0, b.top));
        }
        let initial: Vec<i64> = sequence.truth[0].iter().map(|b| b.id).collect();
        let entries: Vec<_> = first_seen
            .iter()
            .filter(|(id, _)| !initial.contains(id))
            .map(|(_, &p)| p)
            .collect();
        let border = |(u, v): (f64, f64)| u.min(w - u).min(v).min(h - v);
        let farthest = entries.iter().map(|&p| border(p)).fold(0.0, f64::max);
        println!(
            "{} people entered, at most {farthest:.1} px inside the border",
            entries.len()
        );
        assert!(entries.len() > 10);
        assert!(farthest < 40.0, "{farthest}");
    }
}
