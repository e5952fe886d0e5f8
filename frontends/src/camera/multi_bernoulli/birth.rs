//! Births from the foreground the current estimates do not explain.
//!
//! The paper spreads newborns uniformly over the image's quarters. Here (as in the adaptive birth of
//! Ristic, Clark, Vo & Vo for point measurements) the frame itself says where a person may have
//! appeared: the foreground pixels outside every estimated person's region are grouped into connected
//! regions, and each region large enough to be at least the head and shoulders of a person seeds one
//! newborn for the next frame. Its particles put the head top somewhere on the region's upper outline,
//! with a height drawn over the person model's range: the pixel and the height fix the floor position,
//! so the particles spread along the line of sight and the next frames' likelihood picks the depth that
//! fits the person's size and feet.

use std::collections::HashSet;

use image::{GrayImage, Luma};
use imageproc::region_labelling::{connected_components, Connectivity};
use rand::Rng;
use rand_distr::StandardNormal;

use super::bernoulli::{Bernoulli, PersonState};
use super::cover::Cover;
use super::foreground::ForegroundMap;
use super::region::{PersonProjector, Region, RowSpan};

/// Regions smaller than this many (shrunk) pixels are not looked at.
const MIN_PIXELS: usize = 12;

/// How newborns are made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BirthSettings {
    /// Existence of a newborn.
    pub existence: f64,
    /// Particles of a newborn.
    pub particles: usize,
    /// Spread of a newborn's velocity, m/s.
    pub velocity_std: f64,
    /// Smallest area of a region, as a share of the head and shoulders of a person whose head top is
    /// at the region's top.
    pub min_share: f64,
}

/// One connected region of unexplained foreground.
#[derive(Debug, Default)]
struct Unexplained {
    area: usize,
    /// The topmost pixel of each of its columns, `(column, row)`.
    tops: Vec<(u32, u32)>,
}

/// The foreground pixels of `map` that `cover` leaves free, as a mask.
fn residual(map: &ForegroundMap, cover: &Cover) -> GrayImage {
    let [width, height] = map.size();
    let mut mask = map.mask();
    for row in 0..height {
        for col in 0..width {
            let pixel = mask.get_pixel_mut(col as u32, row as u32);
            if pixel[0] == 0 {
                continue;
            }
            let span = RowSpan {
                row: row as i32,
                left: col as f32 + 0.5,
                right: col as f32 + 0.5 + f32::EPSILON * 64.0,
                weight: 1.0,
            };
            if cover.covered_length(&span) > 0.0 {
                pixel[0] = 0;
            }
        }
    }
    mask
}

/// The connected regions of `mask` with at least [`MIN_PIXELS`] pixels.
fn regions(mask: &GrayImage) -> Vec<Unexplained> {
    let labels = connected_components(mask, Connectivity::Eight, Luma([0u8]));
    let mut found: Vec<Unexplained> = Vec::new();
    let mut seen_columns: HashSet<(u32, u32)> = HashSet::new();
    for (col, row, label) in labels.enumerate_pixels() {
        let label = label[0];
        if label == 0 {
            continue;
        }
        let index = label as usize - 1;
        if found.len() <= index {
            found.resize_with(index + 1, Unexplained::default);
        }
        found[index].area += 1;
        // Pixels come row by row from the top, so a column's first pixel is its top.
        if seen_columns.insert((label, col)) {
            found[index].tops.push((col, row));
        }
    }
    found.retain(|r| r.area >= MIN_PIXELS);
    found
}

/// Newborns for the foreground of `map` that `cover` leaves unexplained; ids from `next_id` on.
pub fn newborns(
    map: &ForegroundMap,
    cover: &Cover,
    projector: &PersonProjector,
    settings: &BirthSettings,
    rng: &mut impl Rng,
    next_id: &mut u64,
) -> Vec<Bernoulli> {
    let mut out = Vec::new();
    let mut region = Region::default();
    for unexplained in regions(&residual(map, cover)) {
        if !large_enough(&unexplained, map, projector, settings, &mut region) {
            continue;
        }
        let particles = sample_particles(&unexplained, projector, settings, rng);
        if particles.is_empty() {
            continue;
        }
        out.push(Bernoulli::new(*next_id, settings.existence, particles));
        *next_id += 1;
    }
    out
}

/// Whether the region is at least `min_share` of the head and shoulders of a person of middle height
/// whose head top is the region's top.
fn large_enough(
    unexplained: &Unexplained,
    map: &ForegroundMap,
    projector: &PersonProjector,
    settings: &BirthSettings,
    region: &mut Region,
) -> bool {
    let Some(&(col, row)) = unexplained.tops.iter().min_by_key(|(_, row)| *row) else {
        return false;
    };
    let scale = projector.scale();
    let shape = projector.shape();
    let height = 0.5 * (shape.min_height + shape.max_height);
    let pixel = [(f64::from(col) + 0.5) * scale, f64::from(row) * scale];
    let Some(foot) = projector
        .geometry()
        .point_at_height(pixel, projector.floor_z() + height)
    else {
        return false;
    };
    if !projector.rasterise(foot[0], foot[1], height, region) {
        return false;
    }
    let upper = f64::from(region.upper_area_inside(map.size()));
    upper > 0.0 && unexplained.area as f64 >= settings.min_share * upper
}

/// Particles whose head top lies on the region's upper outline, of any height in the model's range.
fn sample_particles(
    unexplained: &Unexplained,
    projector: &PersonProjector,
    settings: &BirthSettings,
    rng: &mut impl Rng,
) -> Vec<PersonState> {
    let scale = projector.scale();
    let shape = projector.shape();
    let mut particles = Vec::with_capacity(settings.particles);
    for _ in 0..settings.particles * 2 {
        if particles.len() == settings.particles {
            break;
        }
        let (col, row) = unexplained.tops[rng.gen_range(0..unexplained.tops.len())];
        let pixel = [
            (f64::from(col) + rng.gen::<f64>()) * scale,
            (f64::from(row) + rng.gen::<f64>()) * scale,
        ];
        let height = rng.gen_range(shape.min_height..=shape.max_height);
        let Some(p) = projector
            .geometry()
            .point_at_height(pixel, projector.floor_z() + height)
        else {
            continue;
        };
        let vx: f64 = rng.sample(StandardNormal);
        let vy: f64 = rng.sample(StandardNormal);
        particles.push([
            p[0],
            p[1],
            settings.velocity_std * vx,
            settings.velocity_std * vy,
            height,
        ]);
    }
    particles
}
