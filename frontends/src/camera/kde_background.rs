//! Kernel-density background model in rgI chromaticity (Hoseinnezhad, Vo, Vu, sec. 3.1).
//!
//! Each pixel keeps its last N background samples. A new value x is scored by the normalised kernel
//! density of eq. 10, `y = 1/N sum_l prod_{d in r,g,I} exp(-(x_d - s_{l,d})^2 / (2 sigma_d^2))`, which
//! lies in [0, 1]; the pixel is foreground when `y` is below a threshold.
//!
//! Differences from the paper, and why:
//! - The paper replaces the whole stack entry every K0 frames (blind update). Here only pixels that
//!   were classified background are replaced (selective update), each pixel keeping its own ring
//!   position, so a person who stops is not learned as background.
//! - The paper's initial stack spans frames 0, K0, ..., (N-1) K0; here it is the first N frames, so
//!   the model is ready after N frames instead of (N-1) K0 + 1.
//! - Components are bytes (see `chromaticity`), so each one-dimensional kernel is a 511-entry table
//!   indexed by the difference and no `exp` is evaluated per pixel. The sum stops as soon as it
//!   reaches the threshold, since the pixel is background then whatever the remaining samples say.

use image::GrayImage;

use super::background::{BackgroundModel, FOREGROUND};
use super::chromaticity::{Rgi, RgiImage, RGI_SCALE};
use super::config::KdeConfig;

/// Number of possible differences of two bytes, -255..=255.
const DIFFERENCES: usize = 511;

/// The kernel-density background model.
pub struct KdeBackground {
    pixel_count: usize,
    capacity: usize,
    learned: usize,
    update_interval: u32,
    frames_since_update: u32,
    /// `threshold * N`: the kernel sum a background pixel reaches.
    threshold_sum: f32,
    /// `kernels[d][diff + 255]` is the Gaussian kernel of component d at byte difference `diff`.
    kernels: [[f32; DIFFERENCES]; 3],
    /// Pixel-major: the N samples of pixel i are `samples[i * N .. (i + 1) * N]`, so scoring a pixel
    /// reads one contiguous run.
    samples: Vec<Rgi>,
    /// Per pixel, the slot its next background sample overwrites (its oldest sample).
    next_slot: Vec<u8>,
}

impl KdeBackground {
    /// An empty model for `pixel_count` pixels; it learns from the next `config.samples` frames.
    pub fn new(config: &KdeConfig, pixel_count: usize) -> Self {
        let bandwidths = [config.bandwidth_r, config.bandwidth_g, config.bandwidth_i];
        let kernels = std::array::from_fn(|d| {
            // Bandwidth in stored (byte) units.
            let sigma = bandwidths[d] * RGI_SCALE[d];
            std::array::from_fn(|k| {
                let diff = k as f32 - 255.0;
                (-(diff * diff) / (2.0 * sigma * sigma)).exp()
            })
        });
        Self {
            pixel_count,
            capacity: config.samples,
            learned: 0,
            update_interval: config.update_interval,
            frames_since_update: 0,
            threshold_sum: config.threshold * config.samples as f32,
            kernels,
            samples: vec![[0; 3]; pixel_count * config.samples],
            next_slot: vec![0; pixel_count],
        }
    }

    fn kernel_product(&self, x: Rgi, sample: Rgi) -> f32 {
        let k = |d: usize| self.kernels[d][(x[d] as i32 - sample[d] as i32 + 255) as usize];
        k(0) * k(1) * k(2)
    }

    /// The kernel sum of `x` over `samples`, stopped once it reaches `enough`.
    fn kernel_sum_up_to(&self, x: Rgi, samples: &[Rgi], enough: f32) -> f32 {
        let mut sum = 0.0;
        for &sample in samples {
            sum += self.kernel_product(x, sample);
            if sum >= enough {
                break;
            }
        }
        sum
    }

    fn is_background(&self, x: Rgi, samples: &[Rgi]) -> bool {
        let mut sum = 0.0;
        for &sample in samples {
            sum += self.kernel_product(x, sample);
            if sum >= self.threshold_sum {
                return true;
            }
        }
        false
    }

    /// The normalised background likelihood `y` of eq. 10 for pixel `index` (row-major) taking the
    /// value `x`, over the samples learned so far: 1 when `x` equals every sample, near 0 when it is
    /// far from all. `None` if `index` is not a pixel of the model or nothing is learned yet.
    pub fn likelihood(&self, index: usize, x: Rgi) -> Option<f32> {
        if index >= self.pixel_count || self.learned == 0 {
            return None;
        }
        let samples = &self.samples[index * self.capacity..][..self.learned];
        let sum: f32 = samples.iter().map(|&s| self.kernel_product(x, s)).sum();
        Some(sum / self.learned as f32)
    }
}

impl BackgroundModel for KdeBackground {
    fn is_learning(&self) -> bool {
        self.learned < self.capacity
    }

    fn classify(&self, frame: &RgiImage, foreground: &mut GrayImage) {
        debug_assert_eq!(frame.pixels().len(), self.pixel_count);
        let masks = foreground.iter_mut();
        let stacks = self.samples.chunks_exact(self.capacity);
        for ((mask, &x), stack) in masks.zip(frame.pixels()).zip(stacks) {
            *mask = if self.is_background(x, stack) {
                0
            } else {
                FOREGROUND
            };
        }
    }

    fn foreground_values(
        &self,
        frame: &RgiImage,
        saturation: f32,
        values: &mut Vec<f32>,
        foreground: &mut GrayImage,
    ) {
        debug_assert_eq!(frame.pixels().len(), self.pixel_count);
        let n = self.capacity as f32;
        // The sum can stop once it says "background" on both counts.
        let enough = self.threshold_sum.max(saturation * n);
        values.clear();
        values.resize(self.pixel_count, 0.0);
        let stacks = self.samples.chunks_exact(self.capacity);
        let pixels = foreground.iter_mut().zip(values.iter_mut());
        for (((mask, value), &x), stack) in pixels.zip(frame.pixels()).zip(stacks) {
            let sum = self.kernel_sum_up_to(x, stack, enough);
            *mask = if sum >= self.threshold_sum {
                0
            } else {
                FOREGROUND
            };
            *value = 1.0 - (sum / (saturation * n)).min(1.0);
        }
    }

    fn reference(&self, index: usize) -> Rgi {
        // The newest sample: the slot before the one the next sample overwrites.
        let n = self.capacity;
        self.samples[index * n + (self.next_slot[index] as usize + n - 1) % n]
    }

    fn update(&mut self, frame: &RgiImage, foreground: &GrayImage) {
        debug_assert_eq!(frame.pixels().len(), self.pixel_count);
        let n = self.capacity;
        if self.is_learning() {
            let slot = self.learned;
            for (stack, &x) in self.samples.chunks_exact_mut(n).zip(frame.pixels()) {
                stack[slot] = x;
            }
            self.learned += 1;
            return;
        }
        self.frames_since_update += 1;
        if self.frames_since_update < self.update_interval {
            return;
        }
        self.frames_since_update = 0;
        let pixels = frame.pixels().iter().zip(foreground.iter());
        let stacks = self.samples.chunks_exact_mut(n).zip(&mut self.next_slot);
        for ((stack, slot), (&x, &mask)) in stacks.zip(pixels) {
            if mask == 0 {
                stack[*slot as usize] = x;
                *slot = ((*slot as usize + 1) % n) as u8;
            }
        }
    }
}
