//! People as a camera sees them: a head (an ellipsoid whose top is the target's position, hair
//! over skin), a torso and legs (ellipsoids of clothes, striped or plain, in colours seeded per
//! person — some close to the floor's and the door's), lit from above, drawn into a frame through
//! a depth buffer so that nearer people hide farther ones; and the soft shadow each casts at its
//! feet.

use super::geometry::{along, dot, PinholeRays, UprightEllipsoid};
use super::texture::{fabric_noise, shade};
use rand::Rng;

use crate::seeding::StreamKey;

const HAIR: [[f64; 3]; 5] = [
    [38.0, 28.0, 22.0],
    [92.0, 62.0, 36.0],
    [150.0, 118.0, 76.0],
    [70.0, 66.0, 64.0],
    [20.0, 18.0, 18.0],
];
const SKIN: [[f64; 3]; 3] = [
    [226.0, 188.0, 160.0],
    [192.0, 142.0, 108.0],
    [128.0, 88.0, 64.0],
];
const SHIRTS: [[f64; 3]; 7] = [
    [176.0, 44.0, 48.0],
    [44.0, 74.0, 148.0],
    [62.0, 122.0, 70.0],
    [206.0, 180.0, 70.0],
    [100.0, 74.0, 56.0],
    [228.0, 226.0, 220.0],
    [92.0, 92.0, 98.0],
];
const TROUSERS: [[f64; 3]; 5] = [
    [44.0, 52.0, 82.0],
    [30.0, 30.0, 34.0],
    [146.0, 118.0, 86.0],
    [96.0, 96.0, 102.0],
    [110.0, 80.0, 60.0],
];
/// Direction the light comes from (above, a little to one side).
const LIGHT: [f64; 3] = [0.27, 0.18, 0.946];
/// Half-width of the square of floor around the feet that a shadow may darken, m.
const SHADOW_REACH_M: f64 = 0.6;

/// How one person looks, seeded per (run, target).
#[derive(Debug, Clone, PartialEq)]
pub struct Appearance {
    /// Hair colour, RGB.
    pub hair: [f64; 3],
    /// Skin colour.
    pub skin: [f64; 3],
    /// Shirt colour.
    pub shirt: [f64; 3],
    /// Trousers colour.
    pub trousers: [f64; 3],
    /// Period of the shirt's horizontal stripes, m; `None` for a plain shirt.
    pub stripes_m: Option<f64>,
    /// Horizontal semi-axis of the head, m.
    pub head_radius: f64,
    /// Horizontal semi-axis of the torso, m.
    pub torso_radius: f64,
    /// Seeds the texture of the clothes.
    key: u64,
}

impl Appearance {
    /// The appearance of target `id` in run `seed`.
    pub fn seeded(seed: u64, id: u64) -> Self {
        let key = StreamKey::new(seed, "camera_person").with(id);
        let unit = |part: u64| key.with(part).rng().gen::<f64>();
        let pick = |part: u64, n: usize| key.with(part).rng().gen_range(0..n);
        Self {
            hair: HAIR[pick(1, HAIR.len())],
            skin: SKIN[pick(2, SKIN.len())],
            shirt: SHIRTS[pick(3, SHIRTS.len())],
            trousers: TROUSERS[pick(4, TROUSERS.len())],
            stripes_m: (unit(5) < 0.5).then(|| 0.05 + 0.06 * unit(6)),
            head_radius: 0.08 + 0.015 * unit(7),
            torso_radius: 0.15 + 0.04 * unit(8),
            key: key.rng().gen(),
        }
    }
}

/// Which part of a body a point belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Part {
    Head,
    Torso,
    Legs,
}

/// One person at one instant: three ellipsoids under the head's top.
#[derive(Debug, Clone)]
pub struct Body<'a> {
    parts: [(UprightEllipsoid, Part); 3],
    head_top: [f64; 3],
    look: &'a Appearance,
}

impl<'a> Body<'a> {
    /// The body whose head's top is at `head_top`.
    pub fn new(head_top: [f64; 3], look: &'a Appearance) -> Self {
        let [x, y, z] = head_top;
        let head_half = 0.115;
        let torso_half = 0.3;
        let torso_z = z - 2.0 * head_half + 0.04 - torso_half;
        let legs_top = torso_z - 0.15;
        let part = |z: f64, radius: f64, half_height: f64| UprightEllipsoid {
            centre: [x, y, z],
            radius,
            half_height,
        };
        Self {
            parts: [
                (part(z - head_half, look.head_radius, head_half), Part::Head),
                (part(torso_z, look.torso_radius, torso_half), Part::Torso),
                (
                    part(legs_top / 2.0, 0.13, legs_top / 2.0 + 0.01),
                    Part::Legs,
                ),
            ],
            head_top,
            look,
        }
    }

    /// The head's ellipsoid.
    #[cfg(test)]
    pub fn head(&self) -> UprightEllipsoid {
        self.parts[0].0
    }

    /// Draws the body into `frame` (linear RGB, row-major, `size` pixels) where it is nearer than
    /// `depth`, which it updates; only the pixels of its projected bounding box are visited.
    pub fn paint(
        &self,
        rays: &PinholeRays,
        size: [u32; 2],
        frame: &mut [[f32; 3]],
        depth: &mut [f32],
    ) {
        let (mut lo, mut hi) = self.parts[0].0.bounds();
        for (part, _) in &self.parts[1..] {
            let (a, b) = part.bounds();
            lo = std::array::from_fn(|i| lo[i].min(a[i]));
            hi = std::array::from_fn(|i| hi[i].max(b[i]));
        }
        let Some([c0, c1, r0, r1]) = rays.pixel_box(lo, hi, size[0], size[1]) else {
            return;
        };
        let origin = rays.centre();
        for row in r0..r1 {
            for col in c0..c1 {
                let d = rays.direction(f64::from(col) + 0.5, f64::from(row) + 0.5);
                let index = row as usize * size[0] as usize + col as usize;
                if let Some((t, colour)) = self.hit(origin, d) {
                    if (t as f32) < depth[index] {
                        depth[index] = t as f32;
                        frame[index] = colour.map(|c| c as f32);
                    }
                }
            }
        }
    }

    /// The nearest part a ray meets, and the lit colour there.
    fn hit(&self, origin: [f64; 3], d: [f64; 3]) -> Option<(f64, [f64; 3])> {
        let (t, shape, part) = self
            .parts
            .iter()
            .filter_map(|(shape, part)| shape.entry(origin, d).map(|t| (t, shape, *part)))
            .min_by(|a, b| a.0.total_cmp(&b.0))?;
        let p = along(origin, d, t);
        let light = 0.5 + 0.5 * dot(shape.normal(p), LIGHT).max(0.0);
        Some((t, shade(self.surface_colour(part, p), light)))
    }

    fn surface_colour(&self, part: Part, p: [f64; 3]) -> [f64; 3] {
        let look = self.look;
        // Texture coordinates: the angle around the body's axis and the height.
        let around = (p[1] - self.head_top[1]).atan2(p[0] - self.head_top[0]) * 0.2;
        let cloth = |colour: [f64; 3], key: u64| {
            shade(
                colour,
                1.0 + 0.3 * fabric_noise(look.key ^ key, around * 40.0, p[2] * 25.0),
            )
        };
        match part {
            Part::Head if p[2] > self.head_top[2] - 0.1 => cloth(look.hair, 1),
            Part::Head => look.skin,
            Part::Torso => match look.stripes_m {
                Some(period) if (p[2] / period).rem_euclid(1.0) < 0.5 => {
                    cloth(shade(look.shirt, 0.62), 2)
                }
                _ => cloth(look.shirt, 2),
            },
            Part::Legs => cloth(look.trousers, 3),
        }
    }
}

/// Darkens the floor around the feet of a person standing at `(x, y)`: a soft Gaussian shadow of
/// `strength` (the share of light it takes at its centre) and `width_m` standard deviation.
pub fn paint_shadow(
    feet: [f64; 2],
    strength: f64,
    width_m: f64,
    rays: &PinholeRays,
    size: [u32; 2],
    floor: &[[f32; 2]],
    frame: &mut [[f32; 3]],
) {
    let lo = [feet[0] - SHADOW_REACH_M, feet[1] - SHADOW_REACH_M, 0.0];
    let hi = [feet[0] + SHADOW_REACH_M, feet[1] + SHADOW_REACH_M, 0.0];
    let Some([c0, c1, r0, r1]) = rays.pixel_box(lo, hi, size[0], size[1]) else {
        return;
    };
    let scale = -1.0 / (2.0 * width_m * width_m) as f32;
    for row in r0..r1 {
        for col in c0..c1 {
            let index = row as usize * size[0] as usize + col as usize;
            let [x, y] = floor[index];
            if x.is_nan() {
                continue;
            }
            let d2 = (x - feet[0] as f32).powi(2) + (y - feet[1] as f32).powi(2);
            let factor = 1.0 - strength as f32 * (d2 * scale).exp();
            frame[index] = frame[index].map(|c| c * factor);
        }
    }
}
