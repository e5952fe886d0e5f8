//! A seeded synthetic camera scene shared by the camera tests: a smooth random-colour background,
//! per-pixel sensor noise, and three coloured elliptical "people" (40 x 100 px) that walk across the
//! image and cross one another.

// Each test crate that includes this module uses only part of it.
#![allow(dead_code)]

use image::{Rgb, RgbImage};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Image width.
pub const WIDTH: u32 = 640;
/// Image height.
pub const HEIGHT: u32 = 480;
/// Frames of empty background at the start (the KDE model's default N = 16 learns from them).
pub const EMPTY_FRAMES: usize = 16;
/// Frames in which the people walk.
pub const PEOPLE_FRAMES: usize = 60;
/// Ellipse semi-axes: 40 px wide, 100 px tall.
pub const SEMI_WIDTH: f64 = 20.0;
/// Vertical semi-axis.
pub const SEMI_HEIGHT: f64 = 50.0;
/// Standard deviation of the per-pixel, per-channel sensor noise, in grey levels.
pub const NOISE_SIGMA: f64 = 3.0;

/// One person in one frame.
#[derive(Debug, Clone, Copy)]
pub struct Person {
    /// Ellipse centre x.
    pub cx: f64,
    /// Ellipse centre y.
    pub cy: f64,
    /// Body colour.
    pub colour: [f64; 3],
}

impl Person {
    /// True head point: the top of the ellipse.
    pub fn head(&self) -> [f64; 2] {
        [self.cx, self.cy - SEMI_HEIGHT]
    }

    /// True if the two people's bounding boxes, grown by `margin` px, overlap.
    pub fn near(&self, other: &Person, margin: f64) -> bool {
        (self.cx - other.cx).abs() < 2.0 * SEMI_WIDTH + margin
            && (self.cy - other.cy).abs() < 2.0 * SEMI_HEIGHT + margin
    }
}

/// The people visible in frame `k` (none during the empty frames). A walks right, B walks left and
/// C walks slowly down: A crosses C (around people-frame 16), then B (31); B crosses C (42).
pub fn people(k: usize) -> Vec<Person> {
    if k < EMPTY_FRAMES {
        return Vec::new();
    }
    let t = (k - EMPTY_FRAMES) as f64;
    vec![
        Person {
            cx: 40.0 + 9.0 * t,
            cy: 200.0,
            colour: [205.0, 50.0, 45.0],
        },
        Person {
            cx: 600.0 - 9.0 * t,
            cy: 250.0,
            colour: [45.0, 165.0, 70.0],
        },
        Person {
            cx: 190.0 + 0.5 * t,
            cy: 140.0 + 2.5 * t,
            colour: [60.0, 80.0, 205.0],
        },
    ]
}

/// The static scene behind the people.
pub struct Scene {
    background: Vec<[f64; 3]>,
    rng: ChaCha8Rng,
}

impl Scene {
    /// A background of smooth random colour waves (each channel a sum of random low-frequency
    /// sinusoids around mid grey) plus a gentle brightness gradient.
    pub fn new(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let waves: Vec<[f64; 5]> = (0..12)
            .map(|_| {
                [
                    rng.gen_range(0.0..3.0),                   // channel
                    rng.gen_range(-0.03..0.03),                // x frequency (rad/px)
                    rng.gen_range(-0.03..0.03),                // y frequency
                    rng.gen_range(0.0..std::f64::consts::TAU), // phase
                    rng.gen_range(8.0..18.0),                  // amplitude
                ]
            })
            .collect();
        let mut background = Vec::with_capacity((WIDTH * HEIGHT) as usize);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                let (xf, yf) = (x as f64, y as f64);
                let mut colour = [120.0 + 0.05 * xf - 0.03 * yf; 3];
                for w in &waves {
                    colour[w[0] as usize] += w[4] * (w[1] * xf + w[2] * yf + w[3]).sin();
                }
                background.push(colour);
            }
        }
        Self { background, rng }
    }

    /// Renders frame `k`: background, then people far to near (larger cy is nearer), shaded from
    /// head to feet, then Gaussian sensor noise on every channel of every pixel.
    pub fn render(&mut self, k: usize) -> RgbImage {
        let noise = Normal::new(0.0, NOISE_SIGMA).expect("valid sigma");
        let mut pixels = self.background.clone();
        let mut walkers = people(k);
        walkers.sort_by(|a, b| a.cy.total_cmp(&b.cy));
        for person in &walkers {
            paint_ellipse(&mut pixels, person);
        }
        let mut image = RgbImage::new(WIDTH, HEIGHT);
        for (pixel, colour) in image.pixels_mut().zip(&pixels) {
            *pixel =
                Rgb(colour
                    .map(|c| (c + noise.sample(&mut self.rng)).round().clamp(0.0, 255.0) as u8));
        }
        image
    }
}

fn paint_ellipse(pixels: &mut [[f64; 3]], person: &Person) {
    let rows = (person.cy - SEMI_HEIGHT).floor().max(0.0) as u32
        ..((person.cy + SEMI_HEIGHT).ceil() as u32).min(HEIGHT);
    for y in rows {
        let dy = (y as f64 + 0.5 - person.cy) / SEMI_HEIGHT;
        for x in 0..WIDTH {
            let dx = (x as f64 + 0.5 - person.cx) / SEMI_WIDTH;
            if dx * dx + dy * dy <= 1.0 {
                // Lighter at the head, darker at the feet, like a lit figure.
                let shade = 1.05 - 0.15 * (dy + 1.0) / 2.0;
                pixels[(y * WIDTH + x) as usize] = person.colour.map(|c| c * shade);
            }
        }
    }
}
