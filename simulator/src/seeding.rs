//! Stable derivation of random streams from `(seed, label, index, …)`.
//!
//! Every random number the simulator draws comes from a stream named by a key such as
//! `(seed, "measurements", sensor name, frame index)`. The key is hashed with a fixed,
//! documented function (FNV-1a for text, SplitMix64 finalisers for mixing), never with
//! `std`'s `DefaultHasher`, whose algorithm may change between Rust releases. Two
//! processes that build the same key therefore draw the same numbers, whatever else they
//! computed before.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// SplitMix64's output function: a bijective 64-bit mixer with good avalanche.
pub(crate) fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// 64-bit FNV-1a of a byte string (used to turn labels and sensor names into numbers).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xCBF2_9CE4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3)
    })
}

/// A hash key under construction: start from the run's seed and a domain label, then
/// append the parts that name one stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct StreamKey(u64);

impl StreamKey {
    /// Starts a key in the domain `label` (e.g. `"random_walk"`) for the run's `seed`.
    pub(crate) fn new(seed: u64, label: &str) -> Self {
        StreamKey(splitmix64(seed ^ splitmix64(fnv1a(label.as_bytes()))))
    }

    /// Appends a number to the key.
    pub(crate) fn with(self, part: u64) -> Self {
        StreamKey(splitmix64(self.0.rotate_left(23) ^ splitmix64(part)))
    }

    /// Appends a text label (e.g. a sensor name) to the key.
    pub(crate) fn with_text(self, text: &str) -> Self {
        self.with(fnv1a(text.as_bytes()))
    }

    /// A ChaCha8 generator seeded from the key (ChaCha's output is fixed by its spec, so
    /// the numbers are the same on every platform and `rand_chacha` 0.3 release).
    pub(crate) fn rng(self) -> ChaCha8Rng {
        ChaCha8Rng::seed_from_u64(self.0)
    }

    /// One standard normal number that is a pure function of the key: Box–Muller on two
    /// 53-bit uniforms taken from two further SplitMix64 rounds.
    pub(crate) fn standard_normal(self) -> f64 {
        let a = splitmix64(self.0 ^ 0xA5A5_A5A5_A5A5_A5A5);
        let b = splitmix64(a);
        // (k + 1) / 2^53 lies in (0, 1], so the logarithm is finite.
        let u1 = ((a >> 11) + 1) as f64 / (1u64 << 53) as f64;
        let u2 = (b >> 11) as f64 / (1u64 << 53) as f64;
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_depend_on_every_part_and_on_order() {
        let base = StreamKey::new(7, "x");
        assert_ne!(base.with(1).with(2), base.with(2).with(1));
        assert_ne!(base.with(1), StreamKey::new(8, "x").with(1));
        assert_ne!(base.with_text("cam1"), base.with_text("cam2"));
        assert_eq!(base.with(3), StreamKey::new(7, "x").with(3));
    }

    #[test]
    fn standard_normal_has_unit_moments() {
        let key = StreamKey::new(1, "normal-test");
        let n = 20_000;
        let draws: Vec<f64> = (0..n).map(|i| key.with(i).standard_normal()).collect();
        let mean = draws.iter().sum::<f64>() / n as f64;
        let var = draws.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "mean {mean}");
        assert!((var - 1.0).abs() < 0.05, "variance {var}");
    }
}
