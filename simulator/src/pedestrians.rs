//! Pedestrians walking on a ground plane, seen by one camera: MOT ground-truth boxes and a detector's
//! `det.txt` made from them, for testing image-plane trackers on crowded motion nobody tuned for them.
//!
//! The walkers ([`walk`]): groups of one to three people (60 / 30 / 10 %) walking side by side
//! 0.7 m apart, each group on a straight course through a random visible point in a uniformly random
//! direction (so courses cross), starting 2.5 m outside the image and ending 2.5 m after it has left it again
//! (people enter and leave at the image borders, also at the top, far away, and at the bottom, under the
//! camera). Preferred speed N(1.3, 0.3) m/s clamped to [0.5, 2] m/s (Weidmann's walking speeds), heading
//! wandering as an Ornstein–Uhlenbeck process (σ 0.15 rad, 2 s) around the course, and a 40 % chance of
//! one stop of 1–4 s on the way, with a half-second acceleration back to pace. New groups arrive, one
//! every exponential(1 s) while fewer than `people` persons are in or heading into view; the scene is
//! walked for 40 s before the first frame so that it starts populated.
//!
//! The camera (`boxes.rs`, [`CrowdSequence`]): a box spans the projections of the head (height N(1.72, 0.07) m) and the
//! feet, 0.41 times as wide as it is high, centred under the head; a person is in the truth of a frame
//! when the top-centre of the box — the head point, the MOT reader's `TopCentre` anchor — is in the image.
//! Detections: each true box missed with `miss_probability`, its four edges jittered by
//! N(0, `edge_jitter_px`²), plus Poisson(`false_boxes_per_frame`) false boxes, their head points
//! uniform over the image, 60–300 px high. Everything is a function of the seed.

mod boxes;

use nalgebra::Vector2;
use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Exp, Normal};

pub use boxes::{CrowdSequence, MotBox};

use crate::camera_pose::LookAt;
use crate::error::{invalid, ScenarioError};

/// Seconds walked before the first frame, so that the first frame already has a crowd.
const WARM_UP_S: f64 = 40.0;
/// Spacing of people walking side by side, metres.
const GROUP_SPACING_M: f64 = 0.7;
/// A walker within this of the end of its course has arrived, metres.
const ARRIVAL_M: f64 = 0.5;
/// Standard deviation and time constant of the heading's wander, rad and s.
const WANDER: (f64, f64) = (0.15, 2.0);
/// Time to get back to pace after a stop, s.
const START_UP_S: f64 = 0.5;

/// What to generate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrowdConfig {
    /// Seeds every random draw.
    pub seed: u64,
    /// Persons kept in or heading into view (1 to ~15 for a street camera).
    pub people: usize,
    /// Length of the sequence, s.
    pub duration_s: f64,
    /// Frames per second.
    pub fps: f64,
    /// The camera.
    pub camera: LookAt,
    /// Probability that the detector misses a true box.
    pub miss_probability: f64,
    /// Mean number of false boxes per frame.
    pub false_boxes_per_frame: f64,
    /// Standard deviation of the noise on each box edge, px.
    pub edge_jitter_px: f64,
}

impl CrowdConfig {
    /// A 1920 × 1080 camera 8 m up looking down at a square 10 m ahead (f = 1000 px), 25 fps, 60 s,
    /// 10 % misses, 2 false boxes per frame, 2 px edge jitter.
    pub fn street(seed: u64, people: usize) -> Self {
        Self {
            seed,
            people,
            duration_s: 60.0,
            fps: 25.0,
            camera: LookAt {
                eye: [0.0, 0.0, 8.0],
                target: [0.0, 10.0, 0.0],
                focal_px: 1000.0,
                image_size: [1920, 1080],
            },
            miss_probability: 0.1,
            false_boxes_per_frame: 2.0,
            edge_jitter_px: 2.0,
        }
    }

    /// Checks every value; the error names the offending one.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        let checks = [
            (
                "pedestrian duration_s",
                self.duration_s > 0.0 && self.duration_s.is_finite(),
            ),
            ("pedestrian fps", self.fps > 0.0 && self.fps.is_finite()),
            (
                "pedestrian miss_probability",
                (0.0..=1.0).contains(&self.miss_probability),
            ),
            (
                "pedestrian false_boxes_per_frame",
                self.false_boxes_per_frame >= 0.0 && self.false_boxes_per_frame.is_finite(),
            ),
            (
                "pedestrian edge_jitter_px",
                self.edge_jitter_px >= 0.0 && self.edge_jitter_px.is_finite(),
            ),
        ];
        for (name, ok) in checks {
            if !ok {
                return Err(invalid(name, "out of range"));
            }
        }
        self.camera.projection().map(|_| ())
    }
}

/// One person's ground position at one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PersonAt {
    /// Identity, from 1.
    pub id: u64,
    /// Ground position, metres.
    pub position: [f64; 2],
    /// Height of the head above the ground, metres.
    pub head_height: f64,
}

/// A group walking one course.
struct Group {
    /// Identities and lateral offsets (metres, to the left of the course) of its members.
    members: Vec<(u64, f64, f64)>,
    position: Vector2<f64>,
    goal: Vector2<f64>,
    speed: f64,
    heading_offset: f64,
    /// Distance left before the stop, and how long it lasts.
    stop: Option<(f64, f64)>,
    /// Time since the group last stood, s (for the start-up).
    walking_s: f64,
}

/// Every person's position at each of the `duration_s · fps` frames.
pub fn walk(config: &CrowdConfig) -> Result<Vec<Vec<PersonAt>>, ScenarioError> {
    config.validate()?;
    let projection = boxes::Projector::new(&config.camera)?;
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let dt = 1.0 / config.fps;
    let frames = (config.duration_s * config.fps).round() as usize;
    let warm_up = (WARM_UP_S * config.fps).round() as usize;
    let arrivals = Exp::new(1.0).map_err(|e| invalid("pedestrian arrivals", e.to_string()))?;
    let mut groups: Vec<Group> = Vec::new();
    let mut next_id = 1;
    let mut next_arrival = 0.0;
    let mut out = Vec::with_capacity(frames);
    for k in 0..warm_up + frames {
        let t = k as f64 * dt;
        let present: usize = groups.iter().map(|g| g.members.len()).sum();
        if t >= next_arrival && present < config.people {
            let group = new_group(&mut rng, &projection, &mut next_id, config.people - present);
            groups.push(group);
            next_arrival = t + arrivals.sample(&mut rng);
        }
        for group in &mut groups {
            step_group(group, &mut rng, dt);
        }
        groups.retain(|g| (g.goal - g.position).norm() > ARRIVAL_M);
        if k >= warm_up {
            out.push(groups.iter().flat_map(members_at).collect());
        }
    }
    Ok(out)
}

/// A new group of at most `room` people on a fresh course.
fn new_group(
    rng: &mut ChaCha8Rng,
    projection: &boxes::Projector,
    next_id: &mut u64,
    room: usize,
) -> Group {
    let size = match rng.gen::<f64>() {
        u if u < 0.6 => 1,
        u if u < 0.9 => 2,
        _ => 3,
    }
    .min(room.max(1));
    let (start, goal) = projection.course(rng);
    let members = (0..size)
        .map(|i| {
            let id = *next_id;
            *next_id += 1;
            let offset = (i as f64 - (size - 1) as f64 / 2.0) * GROUP_SPACING_M;
            let head: f64 = Normal::new(1.72, 0.07).map_or(1.72, |n| n.sample(rng));
            (id, offset, head.clamp(1.5, 1.95))
        })
        .collect();
    let pace: f64 = Normal::new(1.3, 0.3).map_or(1.3, |n| n.sample(rng));
    let stop = (rng.gen::<f64>() < 0.4).then(|| {
        let along = rng.gen::<f64>() * (goal - start).norm();
        (along, rng.gen_range(1.0..4.0))
    });
    Group {
        members,
        position: start,
        goal,
        speed: pace.clamp(0.5, 2.0),
        heading_offset: 0.0,
        stop,
        walking_s: START_UP_S,
    }
}

/// Moves a group one frame on: stand while stopped, else walk toward the goal, heading wandering.
fn step_group(group: &mut Group, rng: &mut ChaCha8Rng, dt: f64) {
    let (sigma, tau) = WANDER;
    let decay = (-dt / tau).exp();
    let shock =
        Normal::new(0.0, sigma * (1.0 - decay * decay).sqrt()).map_or(0.0, |n| n.sample(rng));
    group.heading_offset = group.heading_offset * decay + shock;
    let to_goal = group.goal - group.position;
    let remaining = to_goal.norm();
    if let Some((stop_at, duration)) = &mut group.stop {
        if remaining <= *stop_at {
            *duration -= dt;
            group.walking_s = 0.0;
            if *duration <= 0.0 {
                group.stop = None;
            }
            return;
        }
    }
    group.walking_s += dt;
    let pace = group.speed * (group.walking_s / START_UP_S).min(1.0);
    let heading = to_goal.y.atan2(to_goal.x) + group.heading_offset;
    let step = (pace * dt).min(remaining);
    group.position += step * Vector2::new(heading.cos(), heading.sin());
}

/// The members of a group where they are now: side by side across its course.
fn members_at(group: &Group) -> impl Iterator<Item = PersonAt> + '_ {
    let along = (group.goal - group.position).normalize();
    let left = Vector2::new(-along.y, along.x);
    group.members.iter().map(move |&(id, offset, head_height)| {
        let p = group.position + offset * left;
        PersonAt {
            id,
            position: [p.x, p.y],
            head_height,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walkers_keep_pedestrian_speeds_and_the_crowd_its_size() {
        let config = CrowdConfig::street(3, 10);
        let frames = walk(&config).unwrap();
        let mut speeds = Vec::new();
        for pair in frames.windows(2) {
            for a in &pair[0] {
                if let Some(b) = pair[1].iter().find(|b| b.id == a.id) {
                    let d = Vector2::from(b.position) - Vector2::from(a.position);
                    speeds.push(d.norm() * config.fps);
                }
            }
        }
        let moving: Vec<f64> = speeds.iter().copied().filter(|&s| s > 0.45).collect();
        let stopped = speeds.len() - moving.len();
        let fastest = moving.iter().copied().fold(0.0, f64::max);
        let mean_crowd = frames.iter().map(Vec::len).sum::<usize>() as f64 / frames.len() as f64;
        println!(
            "{} person-frames, {stopped} standing or starting, fastest {fastest:.2} m/s, mean crowd {mean_crowd:.1}",
            speeds.len()
        );
        assert!(fastest <= 2.0 * 1.01 + 0.1, "{fastest}");
        assert!(stopped > 0, "nobody ever stopped");
        assert!(mean_crowd > 5.0 && mean_crowd <= 10.0, "{mean_crowd}");
    }

    #[test]
    fn the_same_seed_walks_the_same_crowd() {
        let config = CrowdConfig::street(11, 6);
        assert_eq!(walk(&config).unwrap(), walk(&config).unwrap());
        let other = CrowdConfig::street(12, 6);
        assert_ne!(walk(&config).unwrap(), walk(&other).unwrap());
    }
}
