//! The static part of a rendered camera frame: the inside of the room's box as the camera sees it,
//! a plank floor, painted walls with skirting boards, a door and a picture, each with the fine
//! texture of [`texture`](super::texture). Rendered once per camera; every frame
//! starts from it.

use super::geometry::{along, PinholeRays};
use super::texture::{fabric_noise, lattice_value, shade, value_noise};

/// Width of a floor plank, m.
const PLANK_M: f64 = 0.14;
/// Height of the skirting boards, m.
const SKIRTING_M: f64 = 0.08;
/// Floor colour (oak), RGB.
pub const FLOOR_RGB: [f64; 3] = [150.0, 116.0, 82.0];
const WALL_RGB: [f64; 3] = [196.0, 190.0, 178.0];
const CEILING_RGB: [f64; 3] = [215.0, 213.0, 208.0];
const SKIRTING_RGB: [f64; 3] = [120.0, 110.0, 100.0];
/// Door colour (stained wood), RGB.
pub const DOOR_RGB: [f64; 3] = [104.0, 76.0, 58.0];
const PICTURE_RGB: [f64; 3] = [70.0, 96.0, 120.0];

/// Where a background pixel's ray ends.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Surface {
    Floor,
    Ceiling,
    /// A wall: the axis it is normal to (0 = x, 1 = y) and whether it is the room's upper side.
    Wall {
        axis: usize,
        upper: bool,
    },
}

/// The room as one camera sees it without anybody in it.
#[derive(Debug, Clone)]
pub struct StaticBackground {
    /// Linear RGB per pixel, row-major, before illumination and noise.
    pub colour: Vec<[f32; 3]>,
    /// Per pixel, the floor point `[x, y]` its ray reaches, or NaN where it reaches a wall.
    pub floor: Vec<[f32; 2]>,
}

/// Renders the empty room box `[min, max]` for a `width × height` camera; `key` seeds its textures
/// (the same for every camera of a room, so they see one world).
pub fn render_background(
    rays: &PinholeRays,
    size: [u32; 2],
    min: [f64; 3],
    max: [f64; 3],
    key: u64,
) -> StaticBackground {
    let pixels = size[0] as usize * size[1] as usize;
    let mut out = StaticBackground {
        colour: Vec::with_capacity(pixels),
        floor: Vec::with_capacity(pixels),
    };
    let origin = rays.centre();
    for row in 0..size[1] {
        for col in 0..size[0] {
            let d = rays.direction(f64::from(col) + 0.5, f64::from(row) + 0.5);
            let (surface, t) = exit(origin, d, min, max);
            let p = along(origin, d, t);
            let colour = surface_colour(surface, p, min, key);
            out.colour.push(colour.map(|c| c as f32));
            out.floor.push(match surface {
                Surface::Floor => [p[0] as f32, p[1] as f32],
                _ => [f32::NAN; 2],
            });
        }
    }
    out
}

/// Where a ray from inside the box leaves it: the first face it meets going forward.
fn exit(origin: [f64; 3], d: [f64; 3], min: [f64; 3], max: [f64; 3]) -> (Surface, f64) {
    let mut best = (Surface::Floor, f64::INFINITY);
    for axis in 0..3 {
        if d[axis].abs() < 1e-12 {
            continue;
        }
        let upper = d[axis] > 0.0;
        let bound = if upper { max[axis] } else { min[axis] };
        let t = ((bound - origin[axis]) / d[axis]).max(0.0);
        if t < best.1 {
            let surface = match (axis, upper) {
                (2, false) => Surface::Floor,
                (2, true) => Surface::Ceiling,
                _ => Surface::Wall { axis, upper },
            };
            best = (surface, t);
        }
    }
    best
}

fn surface_colour(surface: Surface, p: [f64; 3], min: [f64; 3], key: u64) -> [f64; 3] {
    match surface {
        Surface::Floor => floor_colour(p, key),
        Surface::Ceiling => shade(
            CEILING_RGB,
            1.0 + 0.04 * fabric_noise(key ^ 3, p[0] * 4.0, p[1] * 4.0),
        ),
        Surface::Wall { axis, upper } => {
            // The coordinate along the wall, from the room's corner.
            let along = p[1 - axis] - min[1 - axis];
            wall_colour(axis, upper, along, p[2] - min[2], key)
        }
    }
}

/// Planks along x, each of its own tone, with grain stretched along the plank and dark seams.
fn floor_colour(p: [f64; 3], key: u64) -> [f64; 3] {
    let plank = (p[1] / PLANK_M).floor();
    let across = p[1] / PLANK_M - plank;
    let tone = 0.88 + 0.24 * lattice_value(key ^ 11, plank as i64, 0);
    let grain = fabric_noise(key ^ 13 ^ plank as u64, p[0] * 6.0, p[1] * 90.0);
    let seam = if !(0.04..=0.96).contains(&across) {
        0.7
    } else {
        1.0
    };
    shade(FLOOR_RGB, tone * (1.0 + 0.22 * grain) * seam)
}

/// Paint with a faint roller texture; a skirting board; a door on the far y wall, a picture on the
/// near x wall.
fn wall_colour(axis: usize, upper: bool, along: f64, z: f64, key: u64) -> [f64; 3] {
    let paint = shade(
        WALL_RGB,
        1.0 + 0.05 * fabric_noise(key ^ 17 ^ axis as u64, along * 8.0, z * 8.0),
    );
    let door = axis == 1 && upper && (0.55..1.40).contains(&along) && z < 2.05;
    if door {
        let panel = value_noise(key ^ 19, along * 4.0, z * 40.0);
        let frame_line = (along - 0.55).abs() < 0.04 || z > 2.0;
        return shade(DOOR_RGB, if frame_line { 0.8 } else { 0.92 + 0.16 * panel });
    }
    if z < SKIRTING_M {
        return shade(
            SKIRTING_RGB,
            1.0 + 0.05 * fabric_noise(key ^ 23, along * 20.0, z * 20.0),
        );
    }
    let picture = axis == 0 && !upper && (0.6..1.4).contains(&along) && (1.1..1.7).contains(&z);
    if picture {
        let strokes = fabric_noise(key ^ 29, along * 9.0, z * 9.0);
        return shade(PICTURE_RGB, 1.0 + 0.6 * strokes);
    }
    paint
}
