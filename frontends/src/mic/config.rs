//! Configuration of the microphone-pair front end.

use serde::Deserialize;

use super::error::MicError;

/// How a microphone pair's audio is turned into TDOA measurement sets.
///
/// Only `mic_distance` is required; every other field has the default documented on it (the defaults were
/// chosen on simulated two-talker speech in a 3 × 3 × 2.5 m room, T60 ≈ 0.15 s, SNR 20 dB, mics 0.5 m apart,
/// 16 kHz). Unknown fields are rejected so that a misspelt key is not silently ignored. Example (TOML):
///
/// ```toml
/// mic_distance = 0.5
/// frame_duration = 0.256
/// max_peaks = 3
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MicPairConfig {
    /// Distance between the two microphones in metres; bounds the search to |tau| ≤ d/c. Required.
    pub mic_distance: f64,
    /// Speed of sound in m/s. Default 343.0 (air at 20 °C), as in the protocol's `mic_pair` descriptor.
    #[serde(default = "default_speed_of_sound")]
    pub speed_of_sound: f64,
    /// Analysis frame length in seconds. Default 0.256 (4096 samples at 16 kHz): several pitch periods and
    /// syllable parts, while a talker moves only centimetres.
    #[serde(default = "default_frame_duration")]
    pub frame_duration: f64,
    /// Time between consecutive frame starts in seconds. Default `None`: equal to `frame_duration`, i.e. no
    /// overlap. A smaller value gives overlapping frames.
    #[serde(default)]
    pub hop_duration: Option<f64>,
    /// Upsampling factor of the correlation before peak picking (zero-padding the cross-spectrum), followed by
    /// parabolic refinement of each peak. Default 8: a grid of 1/8 sample, on which the parabola's bias is
    /// negligible (well under 0.05 sample).
    #[serde(default = "default_interpolation")]
    pub interpolation: usize,
    /// K: at most this many TDOAs per frame, the highest correlation peaks. Default 3: two talkers and one
    /// echo or ripple; `relative_peak_threshold` keeps most frames down to one or two, so that K matters
    /// little at its default. With a relative threshold of 0.6 it mattered; measured so on speech
    /// synthesized elsewhere (`tools/speech_scene/`): 3 gives the
    /// count right in 71 % of the talking frames and OSPA(x, y) 0.41 m on the fifteen scenes, 70 % and
    /// 0.47 m on ten more (seeds 31–40); 4 gives 63 % and 0.44 m, 56 % and 0.50 m; 2 gives 70 % and 61 %.
    /// On the simulator's rendered room 4 does better (seeds 1–5: 53 against 49 %; seeds 6–10: 58 against
    /// 46 %): its talkers' direct paths are weaker peaks, more often the fourth. The default follows the
    /// speech made outside the project, as `noise_by_peak_height` does.
    #[serde(default = "default_max_peaks")]
    pub max_peaks: usize,
    /// Smallest normalised GCC-PHAT peak height that is reported (1 = the channels are exact delayed copies).
    /// Default 0.07: drops the weakest ripples; direct-path peaks of talkers in a reverberant room at 20 dB SNR
    /// are typically 0.1–0.5. Frames without speech are handled by `min_spectral_contrast`, not by this.
    #[serde(default = "default_peak_threshold")]
    pub peak_threshold: f64,
    /// Peaks lower than this fraction of the frame's highest are not reported; 0 reports every peak above
    /// `peak_threshold` (up to `max_peaks`). Default 0.9: a frame sends its highest peak and only those
    /// nearly as high (two talkers of about the same loudness). Why: a reverberant frame has one to three
    /// echo and sidelobe peaks beside each talker's direct path, mostly below the strongest, and a spare
    /// peak that four pairs agree on by chance becomes a ghost track; the fusion, which keeps a talker's
    /// track through the frames that miss it (`filter.speech_activity`, each label a Bernoulli), gains more
    /// from sure TDOAs than from found ones. Measured with the talker configuration of the README
    /// (`random_walk` at 0.1 m/√s) on speech synthesized by espeak-ng through pyroomacoustics' image-source
    /// rooms (`tools/speech_scene/`: 25 scenes, T60 0.3 s, SNR 20 dB): OSPA(x, y) 0.243 m and the count
    /// right in 85.1 % of the talking frames, against 0.244 m and 81.2 % with 0.8 and 0.340 m and 55.0 %
    /// with 0.6 (more ghosts). On the rendered default room, whose talkers walk (0.15 m/√s; seeds 1–10),
    /// 0.438 m and 56.7 %, against 0.451 m and 59.4 % with 0.8 and 0.450 m and 63.3 % with 0.6: its
    /// direct paths are weaker peaks. With the talkers' fewer births (`filter.birth_rate` 0.05), on the
    /// same 25 scenes: 0.187 m and 93.3 % at 0.9, 0.203 m and 85.7 % at 0.8, 0.270 m and 67.6 % at 0.6;
    /// on the rendered room 0.444 m and 62.1 %, 0.416 m and 72.0 %, 0.420 m and 67.5 %. The default
    /// follows the speech made outside the project.
    #[serde(default = "default_relative_peak_threshold")]
    pub relative_peak_threshold: f64,
    /// Lowest frequency in Hz used in the correlation. Default 100: below it speech has little energy and
    /// rooms have strong modes.
    #[serde(default = "default_min_frequency")]
    pub min_frequency: f64,
    /// Highest frequency in Hz used in the correlation. Default `None`: up to just below the Nyquist frequency.
    #[serde(default)]
    pub max_frequency: Option<f64>,
    /// Relative magnitude floor of the PHAT weighting: cross-spectrum bins weaker than this fraction of the
    /// frame's strongest bin get weight 0 rather than 1/|G|. Default 1e-9: only numerically empty bins, such as
    /// those of digital silence, are dropped.
    #[serde(default = "default_phat_floor")]
    pub phat_floor: f64,
    /// Bins whose cross-spectrum magnitude is below this multiple of the band's median magnitude get weight 0;
    /// 0 disables the gate. Default 2.0. Why: speech is sparse in frequency (harmonics, formants), so in a frame
    /// the median bin is mostly noise; pure PHAT gives each noise-only bin the same say as a speech bin, and at
    /// 20 dB SNR the noise bins flatten the talkers' peaks into the noise (mean direct-path peak ≈ 0.08, about
    /// the height of noise maxima). With the gate the peaks stand at ≈ 0.2–0.25.
    #[serde(default = "default_median_gate")]
    pub median_gate: f64,
    /// Frames whose in-band power spectrum `|Y1|² + |Y2|²` has a mean-to-median ratio below this give an empty
    /// TDOA set; 0 disables the check. Default 1.25. Why: white Gaussian noise gives ≈ 1.19 (1.15–1.23 over
    /// 4096-sample frames), frames with speech 1.3 to above 20, so this is a cheap, stateless speech-presence
    /// test that keeps noise-only frames from producing clutter. Coloured background noise raises the ratio
    /// (the check then lets more noise frames through, it does not drop speech). A broadband noise source (fan,
    /// white-noise test signal) looks like background noise to it: set 0 to localise such sources.
    #[serde(default = "default_min_spectral_contrast")]
    pub min_spectral_contrast: f64,
    /// Length in seconds of the segments (half overlapping) over which each frame's cross-spectrum is
    /// averaged and weighted by the channels' coherence (the maximum-likelihood GCC of Knapp & Carter; see
    /// `coherence.rs`); 0 correlates the whole frame at once with PHAT weighting (`phat_floor` and
    /// `median_gate` apply only then). Default 0.064 (1024 samples at 16 kHz, seven segments per 256 ms
    /// frame). Why: in a reverberant room the coherence tells the bins the direct path dominates from those
    /// of the diffuse field and the noise; on the rendered default room (T60 0.3 s, SNR 20 dB) the talkers'
    /// direct paths are among the two strongest peaks half as often again as with PHAT.
    #[serde(default = "default_segment_duration")]
    pub segment_duration: f64,
    /// Time constant in seconds over which each frame's correlation is pooled with the earlier frames'
    /// (`pooling.rs`): a frame's correlation is added to the earlier frames' sum, which keeps `exp(−hop /
    /// pooling_time_constant)` of its weight at each frame; the peaks are picked on the pooled correlation.
    /// 0 picks them on each frame alone, the default. Why: the direct path persists from frame to frame, but
    /// so do a standing talker's echoes, and the pool also keeps a talker who has stopped for a second. With
    /// today's other defaults a pool of 0.6 s gives the count right in 60 % against 63 % without on speech
    /// synthesized elsewhere (`tools/speech_scene/`, 15 scenes), and 51 against 53 % on the rendered default
    /// room (seeds 1–5), where a single frame's highest peak is a talker's direct path in only a quarter of
    /// the frames (over half on the synthesized speech).
    #[serde(default = "default_pooling_time_constant")]
    pub pooling_time_constant: f64,
    /// Fastest change of a talker's TDOA the pooling follows (when `pooling_time_constant` is set), in seconds
    /// of TDOA per second. Default 2.5e-4
    /// (one sample per 256 ms frame at 16 kHz): a talker 1.5 m in front of a 0.5 m pair who walks across at
    /// 0.3 m/s. On the rendered room half as much follows the talkers too slowly (46 % count right, against
    /// 59 %), one and a half times as much spreads each peak over too many lags (52 %).
    #[serde(default = "default_max_tdoa_rate")]
    pub max_tdoa_rate: f64,
    /// Whether each TDOA is sent with a variance of its own: the descriptor's `noise_std`² for the frame's
    /// strongest peak, more for a weaker one, by Knapp & Carter's bound at the two peak heights
    /// (`peak_noise.rs`). Default true. Why: a frame's weaker peaks are more often an echo, a sidelobe
    /// of the louder talker or two paths merged, and a wider likelihood lets the fusion take them for
    /// clutter more readily and pulls its tracks less towards them. False sends every TDOA with the
    /// descriptor's noise. With three peaks a frame it takes the count right of the talking frames from
    /// 67.7 to 71.2 % on speech synthesized by espeak-ng through pyroomacoustics' rooms
    /// (`tools/speech_scene/`, 15 scenes), from 62.0 to 70.3 % on ten more, and from 42.6 to 48.6 % on the
    /// simulator's rendered room (seeds 1–5). With four it cost the rendered room (53 % instead of 63 %),
    /// where a frame's strongest peak is a talker's direct path in only a quarter of the frames, so that
    /// the weaker peaks it discounts are often the talkers. The bound has no setting to tune (its square
    /// root or its power 1.5 do no better).
    #[serde(default = "default_noise_by_peak_height")]
    pub noise_by_peak_height: bool,
}

fn default_speed_of_sound() -> f64 {
    343.0
}
fn default_frame_duration() -> f64 {
    0.256
}
fn default_interpolation() -> usize {
    8
}
fn default_max_peaks() -> usize {
    3
}
fn default_relative_peak_threshold() -> f64 {
    0.9
}
fn default_peak_threshold() -> f64 {
    0.07
}
fn default_min_frequency() -> f64 {
    100.0
}
fn default_phat_floor() -> f64 {
    1e-9
}
fn default_median_gate() -> f64 {
    2.0
}
fn default_min_spectral_contrast() -> f64 {
    1.25
}
fn default_segment_duration() -> f64 {
    0.064
}

fn default_pooling_time_constant() -> f64 {
    0.0
}

fn default_noise_by_peak_height() -> bool {
    true
}
fn default_max_tdoa_rate() -> f64 {
    2.5e-4
}

impl MicPairConfig {
    /// The documented defaults for a pair of microphones `mic_distance` metres apart.
    pub fn new(mic_distance: f64) -> Self {
        Self {
            mic_distance,
            speed_of_sound: default_speed_of_sound(),
            frame_duration: default_frame_duration(),
            hop_duration: None,
            interpolation: default_interpolation(),
            max_peaks: default_max_peaks(),
            peak_threshold: default_peak_threshold(),
            relative_peak_threshold: default_relative_peak_threshold(),
            min_frequency: default_min_frequency(),
            max_frequency: None,
            phat_floor: default_phat_floor(),
            median_gate: default_median_gate(),
            min_spectral_contrast: default_min_spectral_contrast(),
            segment_duration: default_segment_duration(),
            pooling_time_constant: default_pooling_time_constant(),
            max_tdoa_rate: default_max_tdoa_rate(),
            noise_by_peak_height: default_noise_by_peak_height(),
        }
    }

    /// Largest physically possible |tau| in seconds: d/c.
    pub fn max_tdoa(&self) -> f64 {
        self.mic_distance / self.speed_of_sound
    }

    /// Checks every field's range (those that do not depend on the sample rate).
    pub fn validate(&self) -> Result<(), MicError> {
        positive("mic_distance", self.mic_distance)?;
        positive("speed_of_sound", self.speed_of_sound)?;
        positive("frame_duration", self.frame_duration)?;
        if let Some(hop) = self.hop_duration {
            positive("hop_duration", hop)?;
        }
        if !(1..=64).contains(&self.interpolation) {
            return Err(invalid(
                "interpolation",
                format!("must be in 1..=64, got {}", self.interpolation),
            ));
        }
        if self.max_peaks == 0 {
            return Err(invalid("max_peaks", "must be at least 1".into()));
        }
        non_negative("peak_threshold", self.peak_threshold)?;
        if !(0.0..=1.0).contains(&self.relative_peak_threshold) {
            return Err(invalid(
                "relative_peak_threshold",
                format!("must be in [0, 1], got {}", self.relative_peak_threshold),
            ));
        }
        non_negative("min_frequency", self.min_frequency)?;
        if let Some(max) = self.max_frequency {
            positive("max_frequency", max)?;
        }
        if !(self.phat_floor.is_finite() && (0.0..1.0).contains(&self.phat_floor)) {
            return Err(invalid(
                "phat_floor",
                format!("must be in [0, 1), got {}", self.phat_floor),
            ));
        }
        non_negative("median_gate", self.median_gate)?;
        non_negative("min_spectral_contrast", self.min_spectral_contrast)?;
        non_negative("segment_duration", self.segment_duration)?;
        non_negative("pooling_time_constant", self.pooling_time_constant)?;
        non_negative("max_tdoa_rate", self.max_tdoa_rate)?;
        if self.segment_duration > self.frame_duration {
            return Err(invalid(
                "segment_duration",
                format!(
                    "{} s is longer than the frame ({} s)",
                    self.segment_duration, self.frame_duration
                ),
            ));
        }
        Ok(())
    }
}

fn positive(field: &'static str, value: f64) -> Result<(), MicError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be positive and finite, got {value}"),
        ))
    }
}

fn non_negative(field: &'static str, value: f64) -> Result<(), MicError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be finite and ≥ 0, got {value}"),
        ))
    }
}

fn invalid(field: &'static str, reason: String) -> MicError {
    MicError::InvalidConfig { field, reason }
}
