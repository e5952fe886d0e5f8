//! GCC-PHAT: the phase-transform weighted generalised cross-correlation of two frames (Knapp & Carter 1976;
//! Pham 2007, eq. 5.23), evaluated on a fine lag grid by zero-padding the cross-spectrum.
//!
//! Sign: the cross-spectrum is `Y2(w) · conj(Y1(w))`, so the correlation peaks at lag `D` when
//! `y2[n] = y1[n - D]`, i.e. at `D = Δ2 − Δ1` (travel time to mic 2 minus travel time to mic 1). That is the
//! protocol's `tau = (‖x − m2‖ − ‖x − m1‖)/c`: positive when the source is closer to mic 1. (Pham writes
//! `Y1 · conj(Y2)` with `e^{+jwτ}`, which peaks at `−τ`; we conjugate the other factor to avoid a sign flip later.)

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use super::coherence::AveragedSpectra;
use super::error::MicError;

/// How far beyond ±`max_lag` (in samples) the correlation is searched; peaks found there are end-fire sources.
pub const EDGE_MARGIN_SAMPLES: f64 = 0.5;

/// Parameters of a [`GccPhat`] estimator, in samples, bins and Hz of the chosen sample rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GccPhatSettings {
    /// Samples per frame.
    pub frame_len: usize,
    /// Largest lag of interest in samples (d/c · fs); frames are zero-padded by at least this much so that the
    /// circular correlation equals the linear one within ±`max_lag`.
    pub max_lag: f64,
    /// Upsampling factor of the correlation (zero-padding of the cross-spectrum), at least 1.
    pub interpolation: usize,
    /// Sample rate in Hz.
    pub sample_rate: u32,
    /// Lowest frequency in Hz that contributes to the correlation.
    pub min_frequency: f64,
    /// Highest frequency in Hz that contributes to the correlation.
    pub max_frequency: f64,
    /// Bins whose cross-spectrum magnitude is below this fraction of the frame's largest one get weight 0
    /// instead of `1/|G|` (PHAT would otherwise blow up numerical noise in near-silent bins).
    pub phat_floor: f64,
    /// Bins whose cross-spectrum magnitude is below this multiple of the band's median magnitude get weight 0.
    /// 0 disables it. See [`crate::mic::MicPairConfig::median_gate`].
    pub median_gate: f64,
    /// `None`: one PHAT-weighted cross-spectrum of the whole frame. `Some(len)`: the cross-spectra of the
    /// frame's segments of `len` samples (half overlapping) are averaged and weighted by their coherence
    /// (`coherence.rs`); the PHAT floor and the median gate are then not used.
    pub segment_len: Option<usize>,
}

/// One frame's correlation around zero lag: `values[i]` is the GCC-PHAT at lag
/// `(first_fine_lag + i) / interpolation` samples, normalised so that exactly delayed copies give 1. It covers
/// ±(`max_lag` + [`EDGE_MARGIN_SAMPLES`]) plus one grid point on each side.
#[derive(Debug, Clone, Copy)]
pub struct LagWindow<'a> {
    /// Correlation values on the fine grid.
    pub values: &'a [f64],
    /// Fine-grid lag of `values[0]` (negative).
    pub first_fine_lag: isize,
    /// Fine-grid points per sample.
    pub interpolation: usize,
    /// Mean over median of the frame's in-band power spectrum `|Y1|² + |Y2|²`: about 1.19 for white Gaussian
    /// noise, larger for spectrally sparse sounds such as speech; 0 for digital silence.
    pub spectral_contrast: f64,
}

/// A GCC-PHAT estimator with its FFT plans and every buffer allocated once, reused for each frame.
pub struct GccPhat {
    frame_len: usize,
    interpolation: usize,
    band_bins: (usize, usize),
    phat_floor: f64,
    median_gate: f64,
    window: Vec<f64>,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    padded_frame: Vec<f64>,
    spectrum1: Vec<Complex<f64>>,
    spectrum2: Vec<Complex<f64>>,
    forward_scratch: Vec<Complex<f64>>,
    cross_spectrum: Vec<Complex<f64>>,
    inverse_scratch: Vec<Complex<f64>>,
    correlation: Vec<f64>,
    band_scratch: Vec<f64>,
    lag_values: Vec<f64>,
    half_width: usize,
    /// Segment length and the segments' sums, when averaging over segments.
    segments: Option<(usize, AveragedSpectra)>,
}

impl GccPhat {
    /// Plans the transforms and allocates the buffers for frames described by `settings`.
    pub fn new(settings: GccPhatSettings) -> Result<Self, MicError> {
        let GccPhatSettings {
            frame_len,
            max_lag,
            interpolation,
            ..
        } = settings;
        if !(max_lag.is_finite() && max_lag > 0.0) {
            return Err(invalid(
                "mic_distance",
                "must give a positive, finite largest lag".into(),
            ));
        }
        if interpolation == 0 {
            return Err(invalid("interpolation", "must be at least 1".into()));
        }
        let transform_len = settings.segment_len.unwrap_or(frame_len);
        if transform_len > frame_len {
            return Err(invalid(
                "segment_duration",
                format!("gives {transform_len} samples, more than the frame's {frame_len}"),
            ));
        }
        if transform_len < 4 * (max_lag.ceil() as usize + 1) {
            let field = if settings.segment_len.is_some() {
                "segment_duration"
            } else {
                "frame_duration"
            };
            return Err(invalid(
                field,
                format!(
                    "gives {transform_len} samples, too short for lags up to {max_lag:.1} samples"
                ),
            ));
        }
        let fft_len = (transform_len + max_lag.ceil() as usize + 1).next_power_of_two();
        let band_bins = band_bins(&settings, fft_len)?;
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(fft_len);
        let inverse = planner.plan_fft_inverse(fft_len * interpolation);
        // The window reaches half a sample beyond ±max_lag, so that the peak of a source at end-fire (exactly
        // ±d/c, or a little beyond after rounding and noise) is still an interior local maximum; plus one
        // fine-grid point so that every lag in the window has two neighbours.
        let half_width =
            ((max_lag + EDGE_MARGIN_SAMPLES) * interpolation as f64).floor() as usize + 1;
        Ok(Self {
            frame_len,
            interpolation,
            band_bins,
            phat_floor: settings.phat_floor,
            median_gate: settings.median_gate,
            window: hann_window(transform_len),
            segments: settings
                .segment_len
                .map(|len| (len, AveragedSpectra::new(fft_len / 2 + 1))),
            padded_frame: forward.make_input_vec(),
            spectrum1: forward.make_output_vec(),
            spectrum2: forward.make_output_vec(),
            forward_scratch: forward.make_scratch_vec(),
            cross_spectrum: inverse.make_input_vec(),
            inverse_scratch: inverse.make_scratch_vec(),
            correlation: inverse.make_output_vec(),
            band_scratch: Vec::with_capacity(band_bins.1 + 1 - band_bins.0),
            lag_values: vec![0.0; 2 * half_width + 1],
            half_width,
            forward,
            inverse,
        })
    }

    /// Samples per frame this estimator expects.
    pub fn frame_len(&self) -> usize {
        self.frame_len
    }

    /// GCC-PHAT of one frame pair around zero lag (see [`LagWindow`]).
    pub fn correlate(&mut self, mic1: &[f64], mic2: &[f64]) -> Result<LagWindow<'_>, MicError> {
        if mic1.len() != self.frame_len || mic2.len() != self.frame_len {
            return Err(MicError::FrameLength {
                expected: self.frame_len,
                mic1: mic1.len(),
                mic2: mic2.len(),
            });
        }
        let (spectral_contrast, weight_sum) = if self.segments.is_some() {
            self.averaged_cross_spectrum(mic1, mic2)?
        } else {
            self.transform(mic1, true)?;
            self.transform(mic2, false)?;
            let (low, high) = self.band_bins;
            self.band_scratch.clear();
            self.band_scratch.extend(
                (low..=high).map(|k| self.spectrum1[k].norm_sqr() + self.spectrum2[k].norm_sqr()),
            );
            (self.spectral_contrast(), self.phat_cross_spectrum())
        };
        self.inverse
            .process_with_scratch(
                &mut self.cross_spectrum,
                &mut self.correlation,
                &mut self.inverse_scratch,
            )
            .map_err(|e| MicError::Fft(e.to_string()))?;
        let scale = if weight_sum > 0.0 {
            1.0 / weight_sum
        } else {
            0.0
        };
        let fine_len = self.correlation.len() as isize;
        let half = self.half_width as isize;
        for (slot, fine_lag) in self.lag_values.iter_mut().zip(-half..=half) {
            // Negative lags live at the end of the circular correlation.
            *slot = self.correlation[fine_lag.rem_euclid(fine_len) as usize] * scale;
        }
        Ok(LagWindow {
            values: &self.lag_values,
            first_fine_lag: -half,
            interpolation: self.interpolation,
            spectral_contrast,
        })
    }

    /// The segments' averaged cross-spectrum, coherence-weighted, in `cross_spectrum`; returns the spectral
    /// contrast of the averaged power and the weights' sum (see [`AveragedSpectra::ml_weighted`]).
    fn averaged_cross_spectrum(
        &mut self,
        mic1: &[f64],
        mic2: &[f64],
    ) -> Result<(f64, f64), MicError> {
        let Some((len, mut spectra)) = self.segments.take() else {
            return Ok((0.0, 0.0));
        };
        spectra.clear();
        let hop = (len / 2).max(1);
        let mut start = 0;
        let mut result = Ok(());
        while start + len <= mic1.len() && result.is_ok() {
            result = self
                .transform(&mic1[start..start + len], true)
                .and_then(|()| self.transform(&mic2[start..start + len], false));
            spectra.add(&self.spectrum1, &self.spectrum2, self.band_bins);
            start += hop;
        }
        self.band_scratch.clear();
        spectra.total_power(self.band_bins, &mut self.band_scratch);
        let contrast = self.spectral_contrast();
        self.cross_spectrum.fill(Complex::new(0.0, 0.0));
        let weight_sum = spectra.ml_weighted(self.band_bins, &mut self.cross_spectrum);
        self.segments = Some((len, spectra));
        result.map(|()| (contrast, weight_sum))
    }

    /// Windows and zero-pads `frame` (a whole frame, or one segment of it), then transforms it into
    /// `spectrum1` (mic 1) or `spectrum2` (mic 2).
    fn transform(&mut self, frame: &[f64], is_mic1: bool) -> Result<(), MicError> {
        for ((slot, &sample), &w) in self.padded_frame.iter_mut().zip(frame).zip(&self.window) {
            *slot = sample * w;
        }
        // realfft uses its input as scratch space, so the padding must be re-zeroed every time.
        self.padded_frame[frame.len()..].fill(0.0);
        let spectrum = if is_mic1 {
            &mut self.spectrum1
        } else {
            &mut self.spectrum2
        };
        self.forward
            .process_with_scratch(&mut self.padded_frame, spectrum, &mut self.forward_scratch)
            .map_err(|e| MicError::Fft(e.to_string()))
    }

    /// Mean over median of the band's power `|Y1|² + |Y2|²`, which the caller put in `band_scratch` (see
    /// [`LagWindow::spectral_contrast`]).
    fn spectral_contrast(&mut self) -> f64 {
        let mean = self.band_scratch.iter().sum::<f64>() / self.band_scratch.len() as f64;
        let median = median_in_place(&mut self.band_scratch);
        if mean <= 0.0 {
            0.0
        } else if median <= 0.0 {
            // Most bins exactly empty but some not: as sparse as a spectrum gets.
            f64::INFINITY
        } else {
            mean / median
        }
    }

    /// Fills `cross_spectrum` with the PHAT-weighted `Y2 · conj(Y1)` inside the band, zero elsewhere (which also
    /// zero-pads it for interpolation) and zero for gated bins. Returns the number of weighted bins counted twice
    /// (for their mirror images): the value a pure delay gives at its lag, used to normalise to 1.
    fn phat_cross_spectrum(&mut self) -> f64 {
        let (low, high) = self.band_bins;
        self.cross_spectrum.fill(Complex::new(0.0, 0.0));
        self.band_scratch.clear();
        for k in low..=high {
            let product = self.spectrum2[k] * self.spectrum1[k].conj();
            self.cross_spectrum[k] = product;
            self.band_scratch.push(product.norm());
        }
        let largest = self.band_scratch.iter().copied().fold(0.0, f64::max);
        let mut floor = (self.phat_floor * largest).max(f64::MIN_POSITIVE);
        if self.median_gate > 0.0 {
            floor = floor.max(self.median_gate * median_in_place(&mut self.band_scratch));
        }
        let mut weight_sum = 0.0;
        for bin in &mut self.cross_spectrum[low..=high] {
            let magnitude = bin.norm();
            if magnitude > floor {
                *bin /= magnitude;
                weight_sum += 2.0;
            } else {
                *bin = Complex::new(0.0, 0.0);
            }
        }
        weight_sum
    }
}

/// Median of a non-empty slice, reordering it (upper median for even lengths).
fn median_in_place(values: &mut [f64]) -> f64 {
    let middle = values.len() / 2;
    *values.select_nth_unstable_by(middle, f64::total_cmp).1
}

/// The inclusive range of FFT bins inside the configured band, never DC nor Nyquist: DC carries offsets and
/// room modes, and the Nyquist bin would need halving when the spectrum is zero-padded.
fn band_bins(settings: &GccPhatSettings, fft_len: usize) -> Result<(usize, usize), MicError> {
    let bin_width = f64::from(settings.sample_rate) / fft_len as f64;
    let low = ((settings.min_frequency / bin_width).ceil() as usize).max(1);
    let high = ((settings.max_frequency / bin_width).floor() as usize).min(fft_len / 2 - 1);
    if low > high {
        return Err(invalid(
            "min_frequency",
            format!(
                "and max_frequency leave no frequency bin ({} .. {} Hz at {} Hz sampling)",
                settings.min_frequency, settings.max_frequency, settings.sample_rate
            ),
        ));
    }
    Ok((low, high))
}

/// A periodic Hann window; tapering the frame edges keeps spectral leakage from smearing the PHAT phase.
fn hann_window(len: usize) -> Vec<f64> {
    (0..len)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / len as f64).cos())
        .collect()
}

fn invalid(field: &'static str, reason: String) -> MicError {
    MicError::InvalidConfig { field, reason }
}
