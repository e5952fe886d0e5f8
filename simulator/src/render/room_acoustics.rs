//! Room acoustics: the image-source model of a shoebox room (Allen & Berkley, JASA 65(4), 1979)
//! with fractional-delay (windowed-sinc) impulse responses, FFT convolution, and the Schroeder
//! estimate of a response's reverberation time that checks them.

use realfft::RealFftPlanner;

/// Half-width in samples of the windowed-sinc fractional-delay kernel.
pub const SINC_HALF_WIDTH: usize = 32;

/// A rectangular room `[0, size[0]] × [0, size[1]] × [0, size[2]]` whose six walls share one pressure
/// reflection coefficient.
#[derive(Debug, Clone, Copy)]
pub struct ShoeboxRoom {
    /// Room dimensions in metres.
    pub size: [f64; 3],
    /// Wall pressure reflection coefficient β in [0, 1); 0 gives the free field (direct path only).
    pub reflection: f64,
}

impl ShoeboxRoom {
    /// A room whose reflection coefficient gives reverberation time `t60` by Sabine's formula
    /// `T60 = 0.161 V / (S α)` with energy absorption `α = 1 − β²`, i.e. `β = √(1 − 0.161 V / (S T60))`.
    ///
    /// Sabine rather than Eyring: the image-source field of a shoebox is not diffuse (grazing paths meet few
    /// walls), so its decay is slower than Eyring predicts. For the 3 × 3 × 2.5 m room and 0.15 s, Eyring's
    /// β ≈ 0.78 gives a measured (Schroeder) T60 ≈ 0.22 s, Sabine's β ≈ 0.70 gives ≈ 0.15 s.
    pub fn with_sabine_t60(size: [f64; 3], t60: f64) -> Self {
        let probe = Self::anechoic(size);
        let absorption = (0.161 * probe.volume() / (probe.surface() * t60)).min(1.0);
        Self {
            size,
            reflection: (1.0 - absorption).sqrt(),
        }
    }

    /// A room without reflections: the anechoic (free-field) case.
    pub fn anechoic(size: [f64; 3]) -> Self {
        Self {
            size,
            reflection: 0.0,
        }
    }

    /// Volume in m³.
    pub fn volume(&self) -> f64 {
        self.size.iter().product()
    }

    /// Total wall area in m².
    pub fn surface(&self) -> f64 {
        let [x, y, z] = self.size;
        2.0 * (x * y + x * z + y * z)
    }

    /// Impulse response from `source` to `mic`, `length` samples at `sample_rate` Hz, sound speed `c` m/s.
    ///
    /// Every image source `((1 − 2q)·s + 2nL)` per axis (q ∈ {0, 1}, n ∈ ℤ) with delay inside the response
    /// contributes `β^(|n − q| + |n|) / (4π r)` per axis product, placed at the fractional delay `r/c·fs`.
    pub fn impulse_response(
        &self,
        source: [f64; 3],
        mic: [f64; 3],
        sample_rate: f64,
        c: f64,
        length: usize,
    ) -> Vec<f64> {
        self.impulse_response_part(source, mic, sample_rate, c, 0..length, SINC_HALF_WIDTH)
    }

    /// The part of [`ShoeboxRoom::impulse_response`] made by the images whose delay (in samples) lies in
    /// `delays`, each a windowed sinc of `half_width` samples either side: with [`SINC_HALF_WIDTH`], the sum of
    /// the parts over adjacent ranges is the whole response, each image's kernel placed in full. A renderer of moving sources updates the early part (direct path and first reflections,
    /// which carry the direction) more often than the diffuse tail.
    pub fn impulse_response_part(
        &self,
        source: [f64; 3],
        mic: [f64; 3],
        sample_rate: f64,
        c: f64,
        delays: std::ops::Range<usize>,
        half_width: usize,
    ) -> Vec<f64> {
        let mut response = vec![0.0; delays.end];
        let min_distance = delays.start as f64 / sample_rate * c;
        let max_distance = delays.end as f64 / sample_rate * c;
        let images: Vec<Vec<(f64, i32)>> = (0..3)
            .map(|axis| self.axis_images(axis, source[axis], mic[axis], max_distance))
            .collect();
        for &(dx, rx) in &images[0] {
            for &(dy, ry) in &images[1] {
                for &(dz, rz) in &images[2] {
                    let distance = (dx * dx + dy * dy + dz * dz).sqrt();
                    if distance < min_distance || distance >= max_distance {
                        continue;
                    }
                    let gain = self.reflection.powi(rx + ry + rz)
                        / (4.0 * std::f64::consts::PI * distance);
                    add_windowed_sinc(&mut response, distance / c * sample_rate, gain, half_width);
                }
            }
        }
        response
    }

    /// Per axis: (mic coordinate − image coordinate, number of reflections) for every image within reach.
    fn axis_images(
        &self,
        axis: usize,
        source: f64,
        mic: f64,
        max_distance: f64,
    ) -> Vec<(f64, i32)> {
        let length = self.size[axis];
        let max_order = (max_distance / (2.0 * length)).ceil() as i32 + 1;
        let mut images = Vec::new();
        for n in -max_order..=max_order {
            for q in 0..=1 {
                let image = (1 - 2 * q) as f64 * source + 2.0 * n as f64 * length;
                let offset = mic - image;
                if offset.abs() <= max_distance {
                    images.push((offset, (n - q).abs() + n.abs()));
                }
            }
        }
        images
    }
}

/// Adds `gain` times a Hann-windowed sinc centred at the fractional sample `delay` to `buffer`
/// ([`SINC_HALF_WIDTH`] samples either side).
pub fn add_fractional_impulse(buffer: &mut [f64], delay: f64, gain: f64) {
    add_windowed_sinc(buffer, delay, gain, SINC_HALF_WIDTH);
}

/// Adds `gain` times a Hann-windowed sinc of `half_width` samples either side, centred at the
/// fractional sample `delay`, to `buffer`.
///
/// Two sines per call instead of two per sample: sin(π(n − d)) only changes sign from one sample
/// to the next, and the window's cosine advances by a fixed angle (a rotation).
pub fn add_windowed_sinc(buffer: &mut [f64], delay: f64, gain: f64, half_width: usize) {
    use std::f64::consts::PI;
    let half = half_width as f64;
    let first = (delay - half).ceil().max(0.0) as usize;
    let last = ((delay + half).floor() as usize).min(buffer.len().saturating_sub(1));
    if first > last || buffer.is_empty() {
        return;
    }
    let t0 = first as f64 - delay;
    // sin(π t) at t0, then alternating in sign.
    let mut sine = (PI * t0).sin();
    let step = PI / half;
    let (step_sin, step_cos) = step.sin_cos();
    let (mut win_sin, mut win_cos) = (step * t0).sin_cos();
    for (k, slot) in buffer[first..=last].iter_mut().enumerate() {
        let t = t0 + k as f64;
        let sinc = if t.abs() < 1e-12 {
            1.0
        } else {
            sine / (PI * t)
        };
        *slot += gain * sinc * 0.5 * (1.0 + win_cos);
        sine = -sine;
        (win_sin, win_cos) = (
            win_sin * step_cos + win_cos * step_sin,
            win_cos * step_cos - win_sin * step_sin,
        );
    }
}

/// Linear convolution of `signal` with `filter`, truncated to the signal's length (causal filtering).
pub fn convolve(signal: &[f64], filter: &[f64]) -> Vec<f64> {
    let fft_len = (signal.len() + filter.len()).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let forward = planner.plan_fft_forward(fft_len);
    let inverse = planner.plan_fft_inverse(fft_len);
    let spectrum_of = |x: &[f64]| {
        let mut input = forward.make_input_vec();
        input[..x.len()].copy_from_slice(x);
        let mut spectrum = forward.make_output_vec();
        forward
            .process(&mut input, &mut spectrum)
            .expect("buffers sized by the plan");
        spectrum
    };
    let mut product: Vec<_> = spectrum_of(signal)
        .iter()
        .zip(spectrum_of(filter))
        .map(|(a, b)| a * b / fft_len as f64)
        .collect();
    let mut output = inverse.make_output_vec();
    inverse
        .process(&mut product, &mut output)
        .expect("buffers sized by the plan");
    output.truncate(signal.len());
    output
}

/// Reverberation time estimated from an impulse response by Schroeder backward integration: the −5 to −25 dB
/// slope of the energy decay curve, extrapolated to −60 dB (T20).
pub fn schroeder_t60(response: &[f64], sample_rate: f64) -> f64 {
    let mut decay: Vec<f64> = response
        .iter()
        .rev()
        .scan(0.0, |sum, h| {
            *sum += h * h;
            Some(*sum)
        })
        .collect();
    decay.reverse();
    let total = decay[0];
    let level = |i: usize| 10.0 * (decay[i] / total).log10();
    let time_at = |db: f64| {
        (0..decay.len())
            .find(|&i| level(i) <= db)
            .unwrap_or(decay.len() - 1)
    };
    let (t5, t25) = (time_at(-5.0), time_at(-25.0));
    3.0 * (t25 - t5) as f64 / sample_rate
}

/// Euclidean distance between two points.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The protocol's TDOA of a source at `x` for mics `m1`, `m2`: (‖x − m2‖ − ‖x − m1‖)/c.
pub fn true_tdoa(x: [f64; 3], m1: [f64; 3], m2: [f64; 3], c: f64) -> f64 {
    (distance(x, m2) - distance(x, m1)) / c
}
