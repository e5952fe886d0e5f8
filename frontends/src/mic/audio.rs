//! Two-channel audio held in memory, the input of the microphone-pair pipeline.

use super::error::MicError;

/// Synchronously sampled signals of microphone 1 and microphone 2, as floating point in about [-1, 1].
///
/// Microphone 1 is the first channel of a stereo file. The two channels always have the same length and every
/// sample is finite; the constructor enforces both.
#[derive(Debug, Clone, PartialEq)]
pub struct StereoAudio {
    sample_rate: u32,
    mic1: Vec<f64>,
    mic2: Vec<f64>,
}

impl StereoAudio {
    /// Builds audio from the two channels, checking the rate, the lengths and that all samples are finite.
    pub fn new(sample_rate: u32, mic1: Vec<f64>, mic2: Vec<f64>) -> Result<Self, MicError> {
        if sample_rate == 0 {
            return Err(MicError::InvalidSampleRate(sample_rate));
        }
        if mic1.len() != mic2.len() {
            return Err(MicError::ChannelLengthMismatch {
                mic1: mic1.len(),
                mic2: mic2.len(),
            });
        }
        for (mic, channel) in [(1u8, &mic1), (2u8, &mic2)] {
            if let Some(index) = channel.iter().position(|s| !s.is_finite()) {
                return Err(MicError::NonFiniteAudio { mic, index });
            }
        }
        Ok(Self {
            sample_rate,
            mic1,
            mic2,
        })
    }

    /// Sample rate in Hz.
    pub fn sample_rate(&self) -> u32 {
        self.sample_rate
    }

    /// Samples of microphone 1 (the first channel).
    pub fn mic1(&self) -> &[f64] {
        &self.mic1
    }

    /// Samples of microphone 2 (the second channel).
    pub fn mic2(&self) -> &[f64] {
        &self.mic2
    }

    /// Number of samples per channel.
    pub fn len(&self) -> usize {
        self.mic1.len()
    }

    /// True when the channels hold no samples.
    pub fn is_empty(&self) -> bool {
        self.mic1.is_empty()
    }

    /// Length in seconds.
    pub fn duration(&self) -> f64 {
        self.len() as f64 / f64::from(self.sample_rate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_unequal_channels_zero_rate_and_nan() {
        assert!(matches!(
            StereoAudio::new(16_000, vec![0.0; 3], vec![0.0; 2]),
            Err(MicError::ChannelLengthMismatch { mic1: 3, mic2: 2 })
        ));
        assert!(matches!(
            StereoAudio::new(0, vec![], vec![]),
            Err(MicError::InvalidSampleRate(0))
        ));
        assert!(matches!(
            StereoAudio::new(8_000, vec![0.0, 1.0], vec![0.0, f64::NAN]),
            Err(MicError::NonFiniteAudio { mic: 2, index: 1 })
        ));
        let audio = StereoAudio::new(8_000, vec![0.5; 4000], vec![0.25; 4000]).unwrap();
        assert_eq!(audio.len(), 4000);
        assert!((audio.duration() - 0.5).abs() < 1e-12);
    }
}
