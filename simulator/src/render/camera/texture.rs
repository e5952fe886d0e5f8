//! Procedural textures of the rendered room and its people: seeded value noise (a hashed lattice,
//! bilinearly interpolated), so that surfaces carry the fine structure real floors, walls and clothes
//! have and a background model must learn, and every value is a pure function of its key.

use crate::seeding::splitmix64;

/// A value in `[0, 1)` that is a pure function of `(key, i, j)`.
pub fn lattice_value(key: u64, i: i64, j: i64) -> f64 {
    let h = splitmix64(key ^ splitmix64((i as u64).wrapping_mul(0x9E37_79B9) ^ (j as u64) << 32));
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// Smooth noise in `[0, 1)` at `(x, y)`, varying over one lattice unit; `key` chooses the field.
pub fn value_noise(key: u64, x: f64, y: f64) -> f64 {
    let (i, j) = (x.floor(), y.floor());
    let (fx, fy) = (smooth(x - i), smooth(y - j));
    let (i, j) = (i as i64, j as i64);
    let top = lerp(lattice_value(key, i, j), lattice_value(key, i + 1, j), fx);
    let bottom = lerp(
        lattice_value(key, i, j + 1),
        lattice_value(key, i + 1, j + 1),
        fx,
    );
    lerp(top, bottom, fy)
}

/// Two octaves of [`value_noise`], centred on 0 and within about ±0.5: coarse blotches and grain.
pub fn fabric_noise(key: u64, x: f64, y: f64) -> f64 {
    0.65 * value_noise(key, x, y) + 0.35 * value_noise(key ^ 0x5bd1, 3.1 * x, 3.1 * y) - 0.5
}

/// Scales an RGB colour.
pub fn shade(colour: [f64; 3], factor: f64) -> [f64; 3] {
    colour.map(|c| c * factor)
}

/// The smoothstep weight of a fraction, so that noise has no creases at lattice lines.
fn smooth(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_continuous_and_bounded() {
        let mut worst_step: f64 = 0.0;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..4000 {
            let x = k as f64 * 0.001 - 2.0;
            let v = value_noise(7, x, 0.3 * x);
            worst_step = worst_step.max((value_noise(7, x + 1e-4, 0.3 * (x + 1e-4)) - v).abs());
            lo = lo.min(v);
            hi = hi.max(v);
        }
        println!("value noise over 4 units: [{lo:.3}, {hi:.3}], largest step over 1e-4: {worst_step:.2e}");
        assert!(lo >= 0.0 && hi < 1.0 && hi - lo > 0.3);
        assert!(worst_step < 1e-3);
        assert_eq!(value_noise(7, 0.25, 0.5), value_noise(7, 0.25, 0.5));
        assert_ne!(value_noise(7, 0.25, 0.5), value_noise(8, 0.25, 0.5));
    }
}
