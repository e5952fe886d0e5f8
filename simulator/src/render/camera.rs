//! The raw frames of a scenario's camera, rendered from the truth: the room's box (a plank floor,
//! painted walls, a door, `camera_background.rs`) under a slowly drifting illumination, every
//! present target as a textured body whose head's top is its truth position (`camera_people.rs`),
//! a soft shadow at each one's feet, nearer people hiding farther ones through a depth buffer, and
//! white sensor noise. Each frame is a pure function of (scenario, sensor, seed, time).
//!
//! The projection is the sensor's protocol `CameraModel`, so a head drawn here projects where the
//! fusion's camera model expects it. Only each body's and shadow's projected bounding box is
//! rasterised, so frames render at video rate (`render_camera` in `simulator/examples` prints it).

use image::RgbImage;
use protocol::SensorModel;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

mod background;
pub mod geometry;
mod output;
mod people;
mod texture;

use crate::error::{invalid, ScenarioError};
use crate::scenario::Scenario;
use crate::seeding::{splitmix64, StreamKey};
use background::{render_background, StaticBackground};
use geometry::PinholeRays;
pub use output::{frame_times, write_frame_directory, write_raw_rgb, write_y4m, RenderedFrames};
pub use people::Appearance;
use people::{paint_shadow, Body};

/// Entries of the table sensor noise is drawn from.
const NOISE_TABLE_LEN: usize = 4096;

/// The room the cameras see and how they see it.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraRoom {
    /// Lower corner of the room's box (floor and walls) in world coordinates, m.
    pub min: [f64; 3],
    /// Upper corner (walls and ceiling), m.
    pub max: [f64; 3],
    /// Standard deviation of the sensor noise, grey levels per channel.
    pub noise_std: f64,
    /// Amplitude of the slow illumination drift, as a share of the light (0.06: ±6 %).
    pub drift: f64,
    /// Share of the light a shadow takes at the centre of a person's feet.
    pub shadow_strength: f64,
    /// Standard deviation of a shadow's soft disc on the floor, m.
    pub shadow_width_m: f64,
}

impl Default for CameraRoom {
    /// The default room's box (walls 5 cm outside the cameras in its top corners), noise 3 grey
    /// levels, ±6 % drift, shadows taking 45 % of the light over 0.16 m.
    fn default() -> Self {
        Self {
            min: [-0.05, -0.05, 0.0],
            max: [3.05, 2.05, 2.6],
            noise_std: 3.0,
            drift: 0.06,
            shadow_strength: 0.45,
            shadow_width_m: 0.16,
        }
    }
}

/// Renders the frames of one camera of a scenario.
pub struct CameraRenderer {
    room: CameraRoom,
    rays: PinholeRays,
    size: [u32; 2],
    background: StaticBackground,
    /// The scenario whose people are drawn, and how each of its targets looks.
    scenario: Scenario,
    appearances: Vec<Appearance>,
    seed: u64,
    noise_key: StreamKey,
    noise: Vec<f32>,
    /// Phases of the two sinusoids of the illumination drift.
    drift_phase: [f64; 2],
    frame: Vec<[f32; 3]>,
    depth: Vec<f32>,
}

impl CameraRenderer {
    /// The renderer of camera `sensor` of `scenario` in run `seed`; refused when the sensor is
    /// missing, not a camera, or its projection has no inverse.
    pub fn new(
        scenario: &Scenario,
        sensor: &str,
        room: &CameraRoom,
        seed: u64,
    ) -> Result<Self, ScenarioError> {
        let (_, spec) = scenario.sensor(sensor)?;
        let SensorModel::Camera(model) = &spec.model else {
            return Err(invalid(
                format!("sensor {sensor}"),
                "is not a camera, so it has no frames to render",
            ));
        };
        let rays = PinholeRays::new(&model.projection)?;
        let size = model.image_size;
        let room_key = StreamKey::new(seed, "camera_room").rng().gen();
        let background = render_background(&rays, size, room.min, room.max, room_key);
        let appearances = scenario
            .targets
            .iter()
            .map(|t| Appearance::seeded(seed, t.id))
            .collect();
        let noise_key = StreamKey::new(seed, "camera_noise").with_text(sensor);
        let mut table_rng = noise_key.rng();
        let noise = (0..NOISE_TABLE_LEN)
            .map(|_| {
                let z: f64 = StandardNormal.sample(&mut table_rng);
                (z * room.noise_std) as f32
            })
            .collect();
        let mut phase_rng = StreamKey::new(seed, "camera_drift").with_text(sensor).rng();
        let drift_phase = [
            phase_rng.gen::<f64>() * std::f64::consts::TAU,
            phase_rng.gen::<f64>() * std::f64::consts::TAU,
        ];
        let pixels = background.colour.len();
        Ok(Self {
            room: room.clone(),
            rays,
            size,
            background,
            scenario: scenario.clone(),
            appearances,
            seed,
            noise_key,
            noise,
            drift_phase,
            frame: vec![[0.0; 3]; pixels],
            depth: vec![f32::INFINITY; pixels],
        })
    }

    /// The image `[width, height]`.
    pub fn size(&self) -> [u32; 2] {
        self.size
    }

    /// The frame the camera takes at scenario time `t`.
    pub fn render(&mut self, t: f64) -> RgbImage {
        let mut image = RgbImage::new(self.size[0], self.size[1]);
        self.render_into(t, &mut image);
        image
    }

    /// Renders the frame at scenario time `t` into `image`, which must have the camera's size.
    pub fn render_into(&mut self, t: f64, image: &mut RgbImage) {
        assert_eq!(
            image.dimensions(),
            (self.size[0], self.size[1]),
            "frame size"
        );
        self.frame.copy_from_slice(&self.background.colour);
        self.depth.fill(f32::INFINITY);
        let (present, heads): (Vec<usize>, Vec<[f64; 3]>) =
            self.scenario.present_at(self.seed, t).into_iter().unzip();
        for head in &heads {
            paint_shadow(
                [head[0], head[1]],
                self.room.shadow_strength,
                self.room.shadow_width_m,
                &self.rays,
                self.size,
                &self.background.floor,
                &mut self.frame,
            );
        }
        for (&i, head) in present.iter().zip(&heads) {
            Body::new(*head, &self.appearances[i]).paint(
                &self.rays,
                self.size,
                &mut self.frame,
                &mut self.depth,
            );
        }
        let gain = self.illumination(t) as f32;
        let key = splitmix64(self.noise_key.with(t.to_bits()).rng().gen());
        quantise(&self.frame, gain, &self.noise, key, image);
    }

    /// The light's gain at time `t`: two slow sinusoids (47 s and 11 s periods) of amplitude
    /// `drift` in all.
    fn illumination(&self, t: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        let slow = (tau * t / 47.0 + self.drift_phase[0]).sin();
        let faster = (tau * t / 11.0 + self.drift_phase[1]).sin();
        1.0 + self.room.drift * (0.7 * slow + 0.3 * faster)
    }
}

/// Scales the linear frame by the light's gain, adds table noise drawn by a xorshift stream seeded
/// with `key`, and rounds to bytes.
fn quantise(frame: &[[f32; 3]], gain: f32, noise: &[f32], key: u64, image: &mut RgbImage) {
    let mut state = key | 1;
    let mask = (NOISE_TABLE_LEN - 1) as u64;
    for (pixel, colour) in image.pixels_mut().zip(frame) {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        for (c, value) in colour.iter().enumerate() {
            let draw = noise[((state >> (12 * c + 4)) & mask) as usize];
            // Rounds to nearest: + 0.5 then truncation, for the clamped (non-negative) value; a
            // call of `round` per channel cost 7 % of rendering the room.
            pixel.0[c] = ((value * gain + draw).clamp(0.0, 255.0) + 0.5) as u8;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    fn quiet_room() -> CameraRoom {
        CameraRoom {
            noise_std: 0.0,
            drift: 0.0,
            ..CameraRoom::default()
        }
    }

    /// The rows and columns where two frames differ by more than `threshold` in some channel.
    fn changed(a: &RgbImage, b: &RgbImage, threshold: i32) -> Vec<(u32, u32)> {
        a.enumerate_pixels()
            .filter(|(x, y, p)| {
                let q = b.get_pixel(*x, *y);
                (0..3).any(|c| (i32::from(p.0[c]) - i32::from(q.0[c])).abs() > threshold)
            })
            .map(|(x, y, _)| (x, y))
            .collect()
    }

    #[test]
    fn frames_are_a_function_of_seed_sensor_and_time() {
        let scenario = crate::default_room();
        let room = CameraRoom::default();
        let mut a = CameraRenderer::new(&scenario, "cam1", &room, 5).unwrap();
        let mut b = CameraRenderer::new(&scenario, "cam1", &room, 5).unwrap();
        let later = a.render(12.0);
        let _ = b.render(3.0);
        assert_eq!(
            b.render(12.0),
            later,
            "a frame depends on what was rendered before"
        );
        let mut other = CameraRenderer::new(&scenario, "cam1", &room, 6).unwrap();
        assert_ne!(other.render(12.0), later);
        assert!(CameraRenderer::new(&scenario, "mics_s", &room, 5).is_err());
        assert!(CameraRenderer::new(&scenario, "nope", &room, 5).is_err());
    }

    #[test]
    fn the_top_of_a_drawn_head_is_the_projected_truth() {
        let scenario = crate::default_room();
        for camera in ["cam1", "cam2"] {
            let (_, spec) = scenario.sensor(camera).unwrap();
            let SensorModel::Camera(model) = &spec.model else {
                unreachable!()
            };
            let rays = PinholeRays::new(&model.projection).unwrap();
            let mut renderer = CameraRenderer::new(&scenario, camera, &quiet_room(), 1).unwrap();
            let empty = renderer.render(0.0);
            // At 1 s only target 1 is in the room.
            let t = 1.0;
            let frame = renderer.render(t);
            let head = scenario.position_of(0, 1, t);
            let ([u, v], _) = rays.project(head).unwrap();
            let (silhouette_top, top_u) =
                silhouette_top(&rays, &Body::new(head, &renderer.appearances[0]).head());
            let near_head: Vec<(u32, u32)> = changed(&frame, &empty, 0)
                .into_iter()
                .filter(|&(x, _)| (f64::from(x) + 0.5 - u).abs() < 30.0)
                .collect();
            let top = near_head.iter().map(|&(_, y)| y).min().unwrap();
            let top_columns: Vec<f64> = near_head
                .iter()
                .filter(|&&(_, y)| y == top)
                .map(|&(x, _)| f64::from(x) + 0.5)
                .collect();
            let column = top_columns.iter().sum::<f64>() / top_columns.len() as f64;
            println!(
                "{camera}: the head's top projects to ({u:.1}, {v:.1}), the head's outline is highest at ({top_u:.1}, {silhouette_top:.1}); the drawn head's top row is {top}, at x {column:.1}"
            );
            assert!(
                (f64::from(top) + 0.5 - silhouette_top).abs() <= 1.0,
                "top row {top} against {silhouette_top:.1}"
            );
            assert!(
                (column - top_u).abs() <= 3.0,
                "column {column:.1} against {top_u:.1}"
            );
        }
    }

    /// The highest image point of an ellipsoid's outline, from points all over its surface.
    fn silhouette_top(rays: &PinholeRays, head: &geometry::UprightEllipsoid) -> (f64, f64) {
        let mut best = (f64::INFINITY, 0.0);
        for i in 0..400 {
            for j in 0..200 {
                let (azimuth, polar) = (
                    i as f64 / 400.0 * std::f64::consts::TAU,
                    j as f64 / 200.0 * std::f64::consts::PI,
                );
                let p = [
                    head.centre[0] + head.radius * polar.sin() * azimuth.cos(),
                    head.centre[1] + head.radius * polar.sin() * azimuth.sin(),
                    head.centre[2] + head.half_height * polar.cos(),
                ];
                let ([u, v], _) = rays.project(p).unwrap();
                if v < best.0 {
                    best = (v, u);
                }
            }
        }
        best
    }

    #[test]
    fn a_nearer_person_hides_a_farther_one() {
        let mut scenario = crate::default_room();
        // Two people on one line of sight of cam1 (at the origin): the far one taller.
        let line = |d: f64, z: f64| [0.75 * d, 0.5 * d, z];
        for (target, position) in scenario
            .targets
            .iter_mut()
            .zip([line(1.2, 1.6), line(2.2, 1.9)])
        {
            target.appear_s = 0.0;
            target.motion = crate::Motion::ConstantVelocity(crate::ConstantVelocity {
                position,
                velocity: [0.0; 3],
            });
        }
        scenario.targets.truncate(2);
        let mut both = CameraRenderer::new(&scenario, "cam1", &quiet_room(), 1).unwrap();
        let mut alone = scenario.clone();
        alone.targets.truncate(1);
        let mut near_only = CameraRenderer::new(&alone, "cam1", &quiet_room(), 1).unwrap();
        let near_frame = near_only.render(1.0);
        let differs = changed(&both.render(1.0), &near_frame, 2);
        let mut nobody = scenario.clone();
        nobody.targets.clear();
        let empty = CameraRenderer::new(&nobody, "cam1", &quiet_room(), 1)
            .unwrap()
            .render(1.0);
        let near_silhouette: std::collections::HashSet<(u32, u32)> =
            changed(&near_frame, &empty, 2).into_iter().collect();
        let overdrawn = differs
            .iter()
            .filter(|p| near_silhouette.contains(p))
            .count();
        println!(
            "the far person shows in {} pixels; {overdrawn} of the near person's {} pixels changed",
            differs.len(),
            near_silhouette.len()
        );
        assert!(differs.len() > 100, "the far person is not drawn");
        // Its shadow on the floor may darken floor pixels, never the near person.
        assert_eq!(overdrawn, 0, "the far person is drawn over the near one");
    }

    #[test]
    fn render_time_of_the_default_rooms_cameras() {
        let scenario = crate::default_room();
        let mut renderers: Vec<CameraRenderer> = ["cam1", "cam2"]
            .iter()
            .map(|c| CameraRenderer::new(&scenario, c, &CameraRoom::default(), 1).unwrap())
            .collect();
        let mut image = RgbImage::new(640, 480);
        let frames = 50;
        let started = Instant::now();
        for k in 0..frames {
            for renderer in &mut renderers {
                renderer.render_into(10.0 + k as f64 / 25.0, &mut image);
            }
        }
        let per_frame = started.elapsed().as_secs_f64() / (2 * frames) as f64;
        println!(
            "{:.2} ms (wall clock, so more on a loaded host) per 640×480 frame with 3 people: the two cameras at 25 Hz take {:.0} % of one core",
            per_frame * 1e3,
            100.0 * per_frame * 50.0
        );
    }
}
