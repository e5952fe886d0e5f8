//! Cutting a signal into (possibly overlapping) analysis frames and stamping each frame.

use super::error::MicError;

/// The position of one analysis frame in a signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameSpan {
    /// Index of the first sample of the frame.
    pub start: usize,
    /// Time of the frame's centre in seconds after the first sample of the signal.
    pub centre_time: f64,
}

/// Frame length and hop, in samples, at a given sample rate.
///
/// Sample `i` is taken to represent the interval `[i/fs, (i+1)/fs)`, so a frame of `len` samples starting at
/// `start` covers `[start/fs, (start+len)/fs)` and its centre is `(start + len/2)/fs`. Only whole frames are
/// produced: a tail shorter than one frame is not analysed (it would bias the correlation towards zero lag).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameLayout {
    frame_len: usize,
    hop: usize,
    sample_rate: u32,
}

impl FrameLayout {
    /// A layout of frames of `frame_len` samples, a new one every `hop` samples.
    pub fn new(frame_len: usize, hop: usize, sample_rate: u32) -> Result<Self, MicError> {
        if sample_rate == 0 {
            return Err(MicError::InvalidSampleRate(sample_rate));
        }
        if frame_len == 0 {
            return Err(MicError::InvalidConfig {
                field: "frame_duration",
                reason: "gives frames of zero samples".into(),
            });
        }
        if hop == 0 {
            return Err(MicError::InvalidConfig {
                field: "hop_duration",
                reason: "gives a hop of zero samples".into(),
            });
        }
        Ok(Self {
            frame_len,
            hop,
            sample_rate,
        })
    }

    /// Samples per frame.
    pub fn frame_len(&self) -> usize {
        self.frame_len
    }

    /// Samples between the starts of consecutive frames.
    pub fn hop(&self) -> usize {
        self.hop
    }

    /// Number of whole frames in a signal of `signal_len` samples.
    pub fn frame_count(&self, signal_len: usize) -> usize {
        if signal_len < self.frame_len {
            0
        } else {
            (signal_len - self.frame_len) / self.hop + 1
        }
    }

    /// Where frame number `index` lies.
    pub fn span(&self, index: usize) -> FrameSpan {
        let start = index * self.hop;
        let centre = start as f64 + self.frame_len as f64 / 2.0;
        FrameSpan {
            start,
            centre_time: centre / f64::from(self.sample_rate),
        }
    }

    /// All whole frames of a signal of `signal_len` samples, in order.
    pub fn spans(&self, signal_len: usize) -> impl Iterator<Item = FrameSpan> + '_ {
        (0..self.frame_count(signal_len)).map(move |index| self.span(index))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_whole_frames_only_and_stamps_centres() {
        let layout = FrameLayout::new(4096, 2048, 16_000).unwrap();
        assert_eq!(layout.frame_count(4095), 0);
        assert_eq!(layout.frame_count(4096), 1);
        assert_eq!(layout.frame_count(4096 + 2047), 1);
        assert_eq!(layout.frame_count(4096 + 2048), 2);
        let spans: Vec<_> = layout.spans(16_000).collect();
        assert_eq!(spans.len(), 6);
        assert_eq!(spans[1].start, 2048);
        assert!((spans[0].centre_time - 0.128).abs() < 1e-12);
        assert!((spans[1].centre_time - 0.256).abs() < 1e-12);
    }

    #[test]
    fn rejects_zero_lengths() {
        assert!(FrameLayout::new(0, 1, 16_000).is_err());
        assert!(FrameLayout::new(16, 0, 16_000).is_err());
        assert!(FrameLayout::new(16, 16, 0).is_err());
    }
}
