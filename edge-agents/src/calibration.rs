//! What a front end actually emits, measured from its own sets: the clutter rate and detection probability
//! its descriptor should announce.
//!
//! No truth is available to an agent, so the estimate rests on persistence. A real object seen in consecutive
//! frames gives measurements close to each other; clutter seldom lands next to the previous frame's
//! measurements. Over the recent frames the estimator counts, per frame,
//!
//! - `N`: measurements;
//! - `S2`: measurements with one of the previous frame's within the gate;
//! - `S3`: measurements of `S2` whose match itself had a match in the frame before.
//!
//! With `n` objects in view, each detected independently with probability `p`, and Poisson clutter of mean
//! `λ`, the expectations are `N = n·p + λ`, `S2 ≈ n·p² + q·E[N_t·N_{t−1}]`, `S3 ≈ n·p³ + q·E[N_t·S2_{t−1}]`,
//! where `q` is the chance that a measurement falls within the gate of a given one by accident (the gate's
//! share of the measurement region: `Π 2·gate_i / width_i`). With the chance matches taken off, `p ≈ S3 / S2`
//! and `λ ≈ N − S2 / p` (a method-of-moments estimate). Clutter that persists
//! (the echo of a source that stands still) is counted as an object, and objects that come and go (a talker
//! between sentences) count as present only while they are seen: the estimate is the front end's behaviour
//! while an object is there, which is what the filter's update assumes.
//!
//! The gate is per measurement coordinate: `GATE_SIGMAS` standard deviations of the difference of two noisy
//! measurements plus how far the sensor's reading of a moving person drifts over the interval between the
//! two frames. When that gate would cover more than [`MAX_CHANCE`] of the measurement region, it is narrowed
//! to that share: a gate that covers much of the region matches mostly by chance, and the chance correction
//! then swamps what persists (a microphone pair's 3σ gate covers a quarter of its TDOA range, and with three
//! or more peaks a frame the corrected counts came out negative: no estimate at all). The narrower gate
//! misses some of an object's own frame-to-frame jitter, so `p` comes out low rather than not at all.

use std::collections::VecDeque;

/// Standard deviations of the difference of two measurements within which they match.
pub const GATE_SIGMAS: f64 = 3.0;
/// Largest chance `q` that a measurement falls within the gate of a given one by accident (see the module
/// documentation).
pub const MAX_CHANCE: f64 = 0.05;
/// Frames the estimate is taken over (the most recent ones).
pub const WINDOW_FRAMES: usize = 400;
/// Frames needed before the estimate is used.
pub const MIN_FRAMES: usize = 60;
/// Frames in which some object was seen twice in a row (`S2 > 0`) needed before `p` is estimated.
const MIN_PERSISTENT_FRAMES: usize = 20;
/// The estimated detection probability is kept within these bounds.
const P_BOUNDS: (f64, f64) = (0.05, 0.99);

/// Per-frame counts of one frame (see the module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct FrameCounts {
    measurements: usize,
    seen_twice: usize,
    seen_thrice: usize,
    /// Chance matches expected with the previous frame: `q` times its measurements times this frame's.
    chance_pairs: f64,
    /// Chance chains expected: `q` times the previous frame's `seen_twice` times this frame's measurements.
    chance_chains: f64,
}

/// The estimate from the recent frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Mean clutter measurements per set.
    pub clutter_rate: f64,
    /// Probability that an object in view gives a measurement.
    pub detection_probability: f64,
    /// Frames the estimate is based on.
    pub frames: usize,
}

/// Running estimate of one sensor's clutter rate and detection probability from its sets.
#[derive(Debug, Clone)]
pub struct RateEstimator {
    /// The noise part of the match window's half-width, per measurement coordinate.
    noise_gate: Vec<f64>,
    /// How fast a moving object's reading drifts, per coordinate and second.
    drift_rate: Vec<f64>,
    /// Width of the measurement region per coordinate.
    width: Vec<f64>,
    /// The gate of the current frame (noise part plus drift over the interval).
    gate: Vec<f64>,
    /// The previous frame's stamp and measurements, and for each whether it matched the frame before it.
    previous: Vec<(Vec<f64>, bool)>,
    previous_stamp: Option<f64>,
    window: VecDeque<FrameCounts>,
}

impl RateEstimator {
    /// An estimator for a sensor with measurement noise `noise_std` per coordinate, whose reading of a moving
    /// object drifts by up to `drift_rate` per second, over a measurement region `width` wide.
    pub fn new(noise_std: &[f64], drift_rate: &[f64], width: &[f64]) -> Self {
        Self {
            noise_gate: noise_std
                .iter()
                .map(|s| GATE_SIGMAS * std::f64::consts::SQRT_2 * s)
                .collect(),
            drift_rate: drift_rate.to_vec(),
            width: width.to_vec(),
            gate: vec![0.0; noise_std.len()],
            previous: Vec::new(),
            previous_stamp: None,
            window: VecDeque::with_capacity(WINDOW_FRAMES),
        }
    }

    /// Sets the gate for a frame `interval` seconds after the previous one; returns the chance `q` of an
    /// accidental match.
    fn set_gate(&mut self, interval: f64) -> f64 {
        for i in 0..self.gate.len() {
            self.gate[i] = self.noise_gate[i] + self.drift_rate[i] * interval;
        }
        let mut chance = self.chance();
        if chance > MAX_CHANCE {
            let shrink = (MAX_CHANCE / chance).powf(1.0 / self.gate.len() as f64);
            self.gate.iter_mut().for_each(|g| *g *= shrink);
            chance = self.chance();
        }
        chance
    }

    /// The chance `q` of an accidental match within the current gate.
    fn chance(&self) -> f64 {
        self.gate
            .iter()
            .zip(&self.width)
            .map(|(g, w)| (2.0 * g / w).min(1.0))
            .product()
    }

    /// Takes one frame's measurements (every frame, empty ones included), captured at `stamp`.
    pub fn observe(&mut self, stamp: f64, measurements: &[Vec<f64>]) {
        let interval = self
            .previous_stamp
            .map_or(0.0, |previous| (stamp - previous).abs());
        self.previous_stamp = Some(stamp);
        let chance = self.set_gate(interval);
        let previous_seen_twice = self.window.back().map_or(0, |c| c.seen_twice);
        let mut counts = FrameCounts {
            measurements: measurements.len(),
            chance_pairs: chance * (measurements.len() * self.previous.len()) as f64,
            chance_chains: chance * (measurements.len() * previous_seen_twice) as f64,
            ..FrameCounts::default()
        };
        let mut next = Vec::with_capacity(measurements.len());
        for z in measurements {
            let matched = self.previous.iter().find(|(prev, _)| self.matches(z, prev));
            if let Some((_, matched_before)) = matched {
                counts.seen_twice += 1;
                counts.seen_thrice += usize::from(*matched_before);
            }
            next.push((z.clone(), matched.is_some()));
        }
        self.previous = next;
        if self.window.len() == WINDOW_FRAMES {
            self.window.pop_front();
        }
        self.window.push_back(counts);
    }

    fn matches(&self, a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .zip(&self.gate)
                .all(|((x, y), g)| (x - y).abs() <= *g)
    }

    /// The estimate, once enough frames (and enough frames with a persistent object) were seen.
    pub fn estimate(&self) -> Option<Estimate> {
        let frames = self.window.len();
        let persistent = self.window.iter().filter(|c| c.seen_twice > 0).count();
        if frames < MIN_FRAMES || persistent < MIN_PERSISTENT_FRAMES {
            return None;
        }
        let mean =
            |f: fn(&FrameCounts) -> f64| self.window.iter().map(f).sum::<f64>() / frames as f64;
        let n = mean(|c| c.measurements as f64);
        let s2 = mean(|c| c.seen_twice as f64 - c.chance_pairs);
        let s3 = mean(|c| c.seen_thrice as f64 - c.chance_chains);
        if s2 <= 0.0 {
            return None;
        }
        let p = (s3 / s2).clamp(P_BOUNDS.0, P_BOUNDS.1);
        Some(Estimate {
            clutter_rate: (n - s2 / p).max(0.0),
            detection_probability: p,
            frames,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Frames of `objects` still objects (1-D, noise 0.01) each detected with `p`, plus Poisson(`lambda`)
    /// clutter uniform over [0, 10).
    fn frames(objects: &[f64], p: f64, lambda: f64, count: usize) -> Vec<Vec<Vec<f64>>> {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let poisson = rand_distr::Poisson::new(lambda).unwrap();
        (0..count)
            .map(|_| {
                let mut frame = Vec::new();
                for x in objects {
                    if rng.gen_bool(p) {
                        frame.push(vec![x + 0.01 * rng.gen_range(-1.0..1.0)]);
                    }
                }
                let clutter: f64 = rand_distr::Distribution::sample(&poisson, &mut rng);
                frame.extend((0..clutter as usize).map(|_| vec![rng.gen_range(0.0..10.0)]));
                frame
            })
            .collect()
    }

    #[test]
    fn recovers_the_rates_of_a_simulated_sensor() {
        for (p, lambda) in [(0.9, 0.5), (0.7, 2.0), (0.5, 1.0)] {
            let mut estimator = RateEstimator::new(&[0.01], &[0.0], &[10.0]);
            for (k, frame) in frames(&[2.0, 5.0, 8.0], p, lambda, WINDOW_FRAMES)
                .iter()
                .enumerate()
            {
                estimator.observe(k as f64 * 0.1, frame);
            }
            let estimate = estimator.estimate().unwrap();
            println!("p_D {p}, clutter {lambda}: estimated {estimate:?}");
            assert!(
                (estimate.detection_probability - p).abs() < 0.08,
                "{estimate:?}"
            );
            assert!((estimate.clutter_rate - lambda).abs() < 0.3, "{estimate:?}");
        }
    }

    #[test]
    fn a_gate_wider_than_the_readings_need_is_narrowed() {
        // Readings far more precise than announced (noise 0.4 over a region of 10: a 3σ gate would cover
        // a third of it) and two clutter measurements a frame: an estimate still comes out, if a rough
        // one (p_D 0.85 and clutter 2.7 here: at q = 0.05 chance matches are no longer rare).
        let mut estimator = RateEstimator::new(&[0.4], &[0.0], &[10.0]);
        for (k, frame) in frames(&[2.0, 5.0, 8.0], 0.7, 2.0, WINDOW_FRAMES)
            .iter()
            .enumerate()
        {
            estimator.observe(k as f64 * 0.1, frame);
        }
        assert!((estimator.set_gate(0.1) - MAX_CHANCE).abs() < 1e-12);
        let estimate = estimator.estimate().unwrap();
        assert!(
            (estimate.detection_probability - 0.7).abs() < 0.2,
            "{estimate:?}"
        );
        assert!((estimate.clutter_rate - 2.0).abs() < 0.8, "{estimate:?}");
        let mut wide = RateEstimator::new(&[0.4], &[0.0], &[10.0]);
        wide.gate = vec![3.0 * std::f64::consts::SQRT_2 * 0.4];
        assert!(wide.chance() > 0.3, "the unnarrowed gate's chance");
    }

    #[test]
    fn waits_for_enough_frames() {
        let mut estimator = RateEstimator::new(&[0.03], &[0.0], &[10.0]);
        for (k, frame) in frames(&[1.0], 0.9, 0.5, MIN_FRAMES - 1).iter().enumerate() {
            estimator.observe(k as f64, frame);
        }
        assert_eq!(estimator.estimate(), None);
        estimator.observe(100.0, &[vec![1.0]]);
        assert!(estimator.estimate().is_some());
        let mut silent = RateEstimator::new(&[0.03], &[0.0], &[10.0]);
        for k in 0..WINDOW_FRAMES {
            silent.observe(k as f64, &[]);
        }
        assert_eq!(silent.estimate(), None, "nothing persistent was ever seen");
    }
}
