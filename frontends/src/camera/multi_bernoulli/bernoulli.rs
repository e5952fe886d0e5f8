//! One Bernoulli component of the multi-Bernoulli density: a person who exists with probability `r`,
//! whose state is spread over weighted particles (the paper's SMC implementation, sec. 4).
//!
//! State: floor position `(x, y)` in metres, its velocity, and the person's height (head top above the
//! floor). Prediction (eq. 22) draws each particle from a nearly-constant-velocity motion with white-noise
//! acceleration and a random walk of the height; the update (eqs. 23, 24) weighs each particle by the
//! image likelihood and revises `r`; resampling gives each component a number of particles that grows with
//! its existence.

use rand::Rng;
use rand_distr::StandardNormal;

/// `[x, y, vx, vy, height]`: metres, metres per second, metres.
pub type PersonState = [f64; 5];

/// How a Bernoulli component moves between frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Probability of surviving one second.
    pub survival_per_second: f64,
    /// White-noise acceleration, m/s².
    pub accel_noise: f64,
    /// Random walk of the height, m/√s.
    pub height_noise: f64,
    /// Bounds of the height, m.
    pub height_bounds: (f64, f64),
}

/// The highest existence a component reaches: certainty would keep a person who left unseen for ever.
const MAX_EXISTENCE: f64 = 0.999;

/// A possible person.
#[derive(Debug, Clone, PartialEq)]
pub struct Bernoulli {
    /// Stays with the component for its life.
    pub id: u64,
    /// Probability that the person exists.
    pub existence: f64,
    /// The particles.
    pub particles: Vec<PersonState>,
    /// Their weights, summing to 1.
    pub weights: Vec<f64>,
    /// Frames in a row in which the existence reached the reporting threshold.
    pub reported_frames: u32,
    /// Frames since birth.
    pub age: u32,
}

impl Bernoulli {
    /// A component with equally weighted `particles`.
    pub fn new(id: u64, existence: f64, particles: Vec<PersonState>) -> Self {
        let n = particles.len().max(1);
        Self {
            id,
            existence,
            weights: vec![1.0 / n as f64; particles.len()],
            particles,
            reported_frames: 0,
            age: 0,
        }
    }

    /// The weighted mean state.
    pub fn mean(&self) -> PersonState {
        let mut mean = [0.0; 5];
        for (p, &w) in self.particles.iter().zip(&self.weights) {
            for (m, v) in mean.iter_mut().zip(p) {
                *m += w * v;
            }
        }
        mean
    }

    /// Moves every particle `dt` seconds on and scales the existence by the survival probability.
    pub fn predict(&mut self, dt: f64, motion: &Motion, rng: &mut impl Rng) {
        self.existence *= motion.survival_per_second.powf(dt);
        let (low, high) = motion.height_bounds;
        let height_step = motion.height_noise * dt.sqrt();
        for p in &mut self.particles {
            let ax = motion.accel_noise * rng.sample::<f64, _>(StandardNormal);
            let ay = motion.accel_noise * rng.sample::<f64, _>(StandardNormal);
            p[0] += p[2] * dt + 0.5 * ax * dt * dt;
            p[1] += p[3] * dt + 0.5 * ay * dt * dt;
            p[2] += ax * dt;
            p[3] += ay * dt;
            let dh: f64 = rng.sample(StandardNormal);
            p[4] = (p[4] + height_step * dh).clamp(low, high);
        }
    }

    /// The update of eqs. 23 and 24 with the particles' log-likelihood ratios (`−∞` for a particle that
    /// left the view: it cannot have produced this image).
    pub fn update(&mut self, log_likelihoods: &[f64]) {
        debug_assert_eq!(log_likelihoods.len(), self.particles.len());
        let peak = log_likelihoods
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if peak == f64::NEG_INFINITY {
            self.existence = 0.0;
            return;
        }
        // ϱ = Σ w·g, kept as exp(peak)·scaled so that large log-likelihoods do not overflow.
        let mut scaled = 0.0;
        for (w, &l) in self.weights.iter_mut().zip(log_likelihoods) {
            *w *= (l - peak).exp();
            scaled += *w;
        }
        if scaled <= 0.0 || !scaled.is_finite() {
            self.existence = 0.0;
            return;
        }
        for w in &mut self.weights {
            *w /= scaled;
        }
        let log_rho = peak + scaled.ln();
        let r = self.existence;
        // r ϱ / (1 − r + r ϱ), written so that a large ϱ gives no overflow.
        let odds_against = (1.0 - r) / r * (-log_rho).exp();
        self.existence = (1.0 / (1.0 + odds_against)).min(MAX_EXISTENCE);
    }

    /// Systematic resampling to `count` equally weighted particles.
    pub fn resample(&mut self, count: usize, rng: &mut impl Rng) {
        if self.particles.is_empty() || count == 0 {
            return;
        }
        let step = 1.0 / count as f64;
        let mut target = rng.gen::<f64>() * step;
        let mut cumulative = self.weights[0];
        let mut i = 0;
        let mut out = Vec::with_capacity(count);
        for _ in 0..count {
            while target > cumulative && i + 1 < self.particles.len() {
                i += 1;
                cumulative += self.weights[i];
            }
            out.push(self.particles[i]);
            target += step;
        }
        self.particles = out;
        self.weights = vec![step; count];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn the_update_follows_the_likelihood_and_resampling_keeps_the_heavy_particles() {
        let particles = vec![[0.0, 0.0, 0.0, 0.0, 1.7], [1.0, 0.0, 0.0, 0.0, 1.7]];
        let mut b = Bernoulli::new(1, 0.1, particles);
        b.update(&[2.0_f64.ln() + 500.0, 500.0]);
        assert!(b.existence > 0.99, "{}", b.existence);
        assert!((b.weights[0] - 2.0 / 3.0).abs() < 1e-12);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        b.resample(300, &mut rng);
        let share = b.particles.iter().filter(|p| p[0] == 0.0).count() as f64 / 300.0;
        assert!((share - 2.0 / 3.0).abs() < 0.01, "{share}");
        let mut absent = Bernoulli::new(2, 0.5, vec![[0.0; 5]]);
        absent.update(&[-10.0]);
        assert!(absent.existence < 1e-4);
        let mut gone = Bernoulli::new(3, 0.5, vec![[0.0; 5]]);
        gone.update(&[f64::NEG_INFINITY]);
        assert_eq!(gone.existence, 0.0);
    }

    #[test]
    fn prediction_moves_particles_on_and_lowers_the_existence() {
        let mut b = Bernoulli::new(1, 0.9, vec![[0.0, 0.0, 1.0, 0.0, 1.7]; 200]);
        let motion = Motion {
            survival_per_second: 0.81,
            accel_noise: 1.0,
            height_noise: 0.01,
            height_bounds: (1.5, 1.9),
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        b.predict(0.5, &motion, &mut rng);
        assert!((b.existence - 0.81).abs() < 1e-12);
        let mean = b.mean();
        assert!((mean[0] - 0.5).abs() < 0.05, "{mean:?}");
    }
}
