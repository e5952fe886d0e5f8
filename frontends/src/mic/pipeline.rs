//! The microphone-pair pipeline: audio → frames → GCC-PHAT → (optionally pooled with the earlier frames') →
//! the K strongest in-range peaks, those well below the strongest left out, as TDOAs.

use super::audio::StereoAudio;
use super::config::MicPairConfig;
use super::error::MicError;
use super::frame_assembler::FrameAssembler;
use super::framing::FrameLayout;
use super::gcc_phat::{GccPhat, GccPhatSettings};
use super::peak_noise::relative_variances;
use super::peaks::{strongest_peaks, RefinedPeak};
use super::pooling::PooledCorrelation;

/// Longest frame, in samples, a pipeline accepts (about 16 s at 16 kHz, 5.9 s at 44.1 kHz). The FFT buffers
/// grow with it (times the interpolation factor), so a corrupt sample rate or duration must not be allowed to
/// ask for gigabytes.
pub const MAX_FRAME_LEN: usize = 1 << 18;

/// The TDOA measurement set of one audio frame.
#[derive(Debug, Clone, PartialEq)]
pub struct TdoaFrame {
    /// Capture time of the frame's centre: the audio's start time plus the centre's offset, in seconds.
    pub stamp: f64,
    /// TDOAs in seconds, strongest correlation peak first; `tau = (‖x − m2‖ − ‖x − m1‖)/c`, positive when the
    /// source is closer to mic 1. Each lies in [−d/c, d/c]. Empty when the frame failed the speech-presence
    /// check or no peak passed the threshold.
    pub tdoas: Vec<f64>,
    /// Each TDOA's variance relative to the frame's strongest peak's ([`relative_variances`]).
    pub relative_variances: Vec<f64>,
}

/// One reported correlation peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TdoaPeak {
    /// The TDOA in seconds (protocol sign convention, see [`TdoaFrame::tdoas`]).
    pub tdoa: f64,
    /// Normalised GCC-PHAT height of the peak (1 for two exactly delayed copies).
    pub strength: f64,
}

/// Turns two-channel audio into TDOA measurement sets, reusing its FFT plans and buffers for every frame.
pub struct MicPairPipeline {
    config: MicPairConfig,
    sample_rate: u32,
    layout: FrameLayout,
    gcc: GccPhat,
    max_lag_samples: f64,
    refined: Vec<RefinedPeak>,
    peaks: Vec<TdoaPeak>,
    /// Earlier frames' correlation, when pooling (`MicPairConfig::pooling_time_constant`).
    pooled: Option<PooledCorrelation>,
}

impl MicPairPipeline {
    /// Builds a pipeline for audio sampled at `sample_rate` Hz, after validating `config`.
    pub fn new(config: MicPairConfig, sample_rate: u32) -> Result<Self, MicError> {
        config.validate()?;
        if sample_rate == 0 {
            return Err(MicError::InvalidSampleRate(sample_rate));
        }
        let rate = f64::from(sample_rate);
        let frame_len = (config.frame_duration * rate).round() as usize;
        let hop = config
            .hop_duration
            .map_or(frame_len, |hop| (hop * rate).round() as usize);
        if frame_len > MAX_FRAME_LEN {
            return Err(MicError::InvalidConfig {
                field: "frame_duration",
                reason: format!(
                    "gives {frame_len} samples at {sample_rate} Hz, more than the supported {MAX_FRAME_LEN}"
                ),
            });
        }
        let layout = FrameLayout::new(frame_len, hop, sample_rate)?;
        let max_lag_samples = config.max_tdoa() * rate;
        let gcc = GccPhat::new(GccPhatSettings {
            frame_len,
            max_lag: max_lag_samples,
            interpolation: config.interpolation,
            sample_rate,
            min_frequency: config.min_frequency,
            max_frequency: config.max_frequency.unwrap_or(rate / 2.0),
            phat_floor: config.phat_floor,
            median_gate: config.median_gate,
            segment_len: (config.segment_duration > 0.0)
                .then(|| (config.segment_duration * rate).round() as usize),
        })?;
        let pooled = pooled_correlation(&config, layout, sample_rate);
        Ok(Self {
            pooled,
            refined: Vec::with_capacity(config.max_peaks),
            peaks: Vec::with_capacity(config.max_peaks),
            config,
            sample_rate,
            layout,
            gcc,
            max_lag_samples,
        })
    }

    /// The configuration this pipeline runs with.
    pub fn config(&self) -> &MicPairConfig {
        &self.config
    }

    /// Sample rate in Hz the pipeline was built for.
    pub fn sample_rate(&self) -> u32 {
        self.sample_rate
    }

    /// How frames are cut from the signal (length and hop in samples).
    pub fn layout(&self) -> FrameLayout {
        self.layout
    }

    /// The strongest peaks of one frame pair (each slice exactly `layout().frame_len()` samples long), picked
    /// on its correlation pooled with the earlier frames' when pooling is on, so frames must come in order.
    ///
    /// The returned slice lives in the pipeline and is overwritten by the next call.
    pub fn frame_peaks(&mut self, mic1: &[f64], mic2: &[f64]) -> Result<&[TdoaPeak], MicError> {
        let window = self.gcc.correlate(mic1, mic2)?;
        self.peaks.clear();
        if window.spectral_contrast < self.config.min_spectral_contrast {
            // As flat as noise: no speech in this frame, so an empty set rather than noise maxima.
            if let Some(pooled) = &mut self.pooled {
                pooled.fade();
            }
            return Ok(&self.peaks);
        }
        let values = match &mut self.pooled {
            Some(pooled) => pooled.add(window.values),
            None => window.values,
        };
        strongest_peaks(
            values,
            self.config.peak_threshold,
            self.config.max_peaks,
            &mut self.refined,
        );
        // Echo peaks well below the frame's strongest are clutter the fusion would have to explain.
        if let Some(highest) = self.refined.first().map(|peak| peak.value) {
            let floor = self.config.relative_peak_threshold * highest;
            self.refined.retain(|peak| peak.value >= floor);
        }
        let fine_step = 1.0 / window.interpolation as f64;
        let rate = f64::from(self.sample_rate);
        for peak in &self.refined {
            let lag = (window.first_fine_lag as f64 + peak.position) * fine_step;
            // Peaks in the half-sample margin beyond ±d/c belong to end-fire sources: report them at ±d/c.
            let lag = lag.clamp(-self.max_lag_samples, self.max_lag_samples);
            self.peaks.push(TdoaPeak {
                tdoa: lag / rate,
                strength: peak.value,
            });
        }
        Ok(&self.peaks)
    }

    /// Every whole frame of `audio` as a TDOA set, `audio` taken as a signal of its own (earlier calls'
    /// frames are not pooled with its); `start_time` is the capture time of the first sample.
    pub fn process(
        &mut self,
        audio: &StereoAudio,
        start_time: f64,
    ) -> Result<Vec<TdoaFrame>, MicError> {
        if audio.sample_rate() != self.sample_rate {
            return Err(MicError::PipelineRateMismatch {
                expected: self.sample_rate,
                actual: audio.sample_rate(),
            });
        }
        if !start_time.is_finite() {
            return Err(MicError::NonFiniteStartTime(start_time));
        }
        // A new signal: nothing of the previous one's frames is pooled with its first frames.
        if let Some(pooled) = &mut self.pooled {
            pooled.clear();
        }
        // The same assembler live streams use, so a file and a stream of the same samples give the same sets.
        let mut assembler = FrameAssembler::new(self.layout);
        assembler.push(audio.mic1(), audio.mic2())?;
        let mut frames = Vec::with_capacity(self.layout.frame_count(audio.len()));
        while let Some((span, mic1, mic2)) = assembler.next_frame() {
            let peaks = self.frame_peaks(mic1, mic2)?;
            frames.push(TdoaFrame {
                stamp: start_time + span.centre_time,
                tdoas: peaks.iter().map(|peak| peak.tdoa).collect(),
                relative_variances: relative_variances(peaks),
            });
        }
        Ok(frames)
    }
}

/// The pool of earlier frames' correlations `config` asks for, if any: its memory per hop, and how far (in
/// points of the interpolated lag grid) a talker's peak may move in one hop.
fn pooled_correlation(
    config: &MicPairConfig,
    layout: FrameLayout,
    sample_rate: u32,
) -> Option<PooledCorrelation> {
    if config.pooling_time_constant <= 0.0 {
        return None;
    }
    let hop_s = layout.hop() as f64 / f64::from(sample_rate);
    let memory = (-hop_s / config.pooling_time_constant).exp();
    let drift_samples = config.max_tdoa_rate * hop_s * f64::from(sample_rate);
    let drift_points = (drift_samples * config.interpolation as f64).round() as usize;
    Some(PooledCorrelation::new(memory, drift_points))
}
