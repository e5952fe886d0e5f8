//! Running-statistics background model: one Gaussian per pixel and rgI component, its mean and
//! variance tracked by exponential forgetting. Cheaper than the kernel density (constant work and
//! 24 bytes per pixel whatever the memory length) but it can represent only a single background value
//! per pixel.

use image::GrayImage;

use super::background::{BackgroundModel, FOREGROUND};
use super::chromaticity::{Rgi, RgiImage, RGI_SCALE};
use super::config::RunningStatsConfig;

/// The running-statistics background model.
pub struct RunningStatsBackground {
    pixel_count: usize,
    learning_frames: u32,
    learned: u32,
    learning_rate: f32,
    threshold_sq: f32,
    /// Variance floor per component, in stored (byte) units.
    min_variance: [f32; 3],
    /// Per pixel, the mean of r, g, I in stored units.
    mean: Vec<[f32; 3]>,
    /// Per pixel, the variance of r, g, I in stored units.
    variance: Vec<[f32; 3]>,
}

impl RunningStatsBackground {
    /// An empty model for `pixel_count` pixels; it averages the next `config.learning_frames` frames.
    pub fn new(config: &RunningStatsConfig, pixel_count: usize) -> Self {
        let min_std = [config.min_std_r, config.min_std_g, config.min_std_i];
        Self {
            pixel_count,
            learning_frames: config.learning_frames,
            learned: 0,
            learning_rate: config.learning_rate,
            threshold_sq: config.threshold_sigmas * config.threshold_sigmas,
            min_variance: std::array::from_fn(|d| (min_std[d] * RGI_SCALE[d]).powi(2)),
            mean: vec![[0.0; 3]; pixel_count],
            variance: vec![[0.0; 3]; pixel_count],
        }
    }
}

impl BackgroundModel for RunningStatsBackground {
    fn is_learning(&self) -> bool {
        self.learned < self.learning_frames
    }

    fn classify(&self, frame: &RgiImage, foreground: &mut GrayImage) {
        debug_assert_eq!(frame.pixels().len(), self.pixel_count);
        let stats = self.mean.iter().zip(&self.variance);
        for ((mask, &x), (mean, variance)) in foreground.iter_mut().zip(frame.pixels()).zip(stats) {
            let distance_sq: f32 = (0..3)
                .map(|d| {
                    let diff = x[d] as f32 - mean[d];
                    diff * diff / variance[d].max(self.min_variance[d])
                })
                .sum();
            *mask = if distance_sq > self.threshold_sq {
                FOREGROUND
            } else {
                0
            };
        }
    }

    fn reference(&self, index: usize) -> Rgi {
        self.mean[index].map(|m| m.round().clamp(0.0, 255.0) as u8)
    }

    fn update(&mut self, frame: &RgiImage, foreground: &GrayImage) {
        debug_assert_eq!(frame.pixels().len(), self.pixel_count);
        let learning = self.is_learning();
        let stats = self.mean.iter_mut().zip(self.variance.iter_mut());
        if learning {
            // Welford's running mean and population variance over the learning frames.
            self.learned += 1;
            let n = self.learned as f32;
            for ((mean, variance), &x) in stats.zip(frame.pixels()) {
                for d in 0..3 {
                    let value = x[d] as f32;
                    let diff = value - mean[d];
                    mean[d] += diff / n;
                    variance[d] += (diff * (value - mean[d]) - variance[d]) / n;
                }
            }
            return;
        }
        let rate = self.learning_rate;
        for ((mean, variance), (&x, &mask)) in
            stats.zip(frame.pixels().iter().zip(foreground.iter()))
        {
            if mask != 0 {
                continue;
            }
            for d in 0..3 {
                let diff = x[d] as f32 - mean[d];
                mean[d] += rate * diff;
                // Exponentially weighted variance (West, 1979).
                variance[d] = (1.0 - rate) * (variance[d] + rate * diff * diff);
            }
        }
    }
}
