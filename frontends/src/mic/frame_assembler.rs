//! Cutting audio that arrives piece by piece into the analysis frames of a [`FrameLayout`].
//!
//! Both the whole-file path ([`super::MicPairPipeline::process`]) and live streams push samples here and take
//! frames out, so the same samples give the same frames — and the same TDOAs — however they were delivered.

use super::error::MicError;
use super::framing::{FrameLayout, FrameSpan};

/// Buffers two channels and hands out each whole frame of a layout as soon as its last sample is in.
///
/// Samples no later frame needs are discarded, so memory stays at about one frame whatever the stream's length.
#[derive(Debug, Clone)]
pub struct FrameAssembler {
    layout: FrameLayout,
    mic1: Vec<f64>,
    mic2: Vec<f64>,
    /// Absolute index (since the stream's first sample) of `mic1[0]`.
    offset: usize,
    /// Index of the next frame to hand out.
    next_frame: usize,
    /// Samples per channel pushed so far.
    pushed: usize,
}

impl FrameAssembler {
    /// An empty assembler for frames of `layout`.
    pub fn new(layout: FrameLayout) -> Self {
        Self {
            layout,
            mic1: Vec::with_capacity(2 * layout.frame_len()),
            mic2: Vec::with_capacity(2 * layout.frame_len()),
            offset: 0,
            next_frame: 0,
            pushed: 0,
        }
    }

    /// Appends samples of both channels (equal lengths, finite values).
    pub fn push(&mut self, mic1: &[f64], mic2: &[f64]) -> Result<(), MicError> {
        if mic1.len() != mic2.len() {
            return Err(MicError::ChannelLengthMismatch {
                mic1: mic1.len(),
                mic2: mic2.len(),
            });
        }
        for (mic, channel) in [(1u8, mic1), (2u8, mic2)] {
            if let Some(index) = channel.iter().position(|s| !s.is_finite()) {
                return Err(MicError::NonFiniteAudio {
                    mic,
                    index: self.pushed + index,
                });
            }
        }
        self.mic1.extend_from_slice(mic1);
        self.mic2.extend_from_slice(mic2);
        self.pushed += mic1.len();
        Ok(())
    }

    /// Samples per channel pushed so far.
    pub fn pushed(&self) -> usize {
        self.pushed
    }

    /// Samples pushed after the last whole frame handed out that belong to no frame yet (a partial frame).
    pub fn pending(&self) -> usize {
        let next_start = self.layout.span(self.next_frame).start;
        self.pushed.saturating_sub(next_start)
    }

    /// The next whole frame, with its position and the two channels' samples, or `None` until enough samples
    /// are in. Frames come in order, each exactly once.
    pub fn next_frame(&mut self) -> Option<(FrameSpan, &[f64], &[f64])> {
        let span = self.layout.span(self.next_frame);
        // Drop what lies before this frame: earlier frames are done and a hop longer than a frame skips samples.
        let discard = span.start.saturating_sub(self.offset).min(self.mic1.len());
        self.mic1.drain(..discard);
        self.mic2.drain(..discard);
        self.offset += discard;
        let frame_len = self.layout.frame_len();
        if self.offset < span.start || self.mic1.len() < frame_len {
            return None;
        }
        self.next_frame += 1;
        Some((span, &self.mic1[..frame_len], &self.mic2[..frame_len]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(range: std::ops::Range<usize>) -> Vec<f64> {
        range.map(|i| i as f64).collect()
    }

    #[test]
    fn pieces_of_any_size_give_the_frames_of_the_whole_signal() {
        let layout = FrameLayout::new(8, 3, 1000).unwrap();
        let signal = ramp(0..40);
        let mut whole = FrameAssembler::new(layout);
        whole.push(&signal, &signal).unwrap();
        let mut expected = Vec::new();
        while let Some((span, a, _)) = whole.next_frame() {
            expected.push((span, a.to_vec()));
        }
        assert_eq!(expected.len(), layout.frame_count(40));
        let mut pieces = FrameAssembler::new(layout);
        let mut got = Vec::new();
        for chunk in signal.chunks(5) {
            pieces.push(chunk, chunk).unwrap();
            while let Some((span, a, b)) = pieces.next_frame() {
                assert_eq!(a, b);
                got.push((span, a.to_vec()));
            }
        }
        assert_eq!(got, expected);
        assert_eq!(expected[2].1, ramp(6..14));
    }

    #[test]
    fn a_hop_longer_than_a_frame_skips_samples() {
        let layout = FrameLayout::new(4, 10, 1000).unwrap();
        let mut assembler = FrameAssembler::new(layout);
        assembler.push(&ramp(0..12), &ramp(0..12)).unwrap();
        assert_eq!(assembler.next_frame().unwrap().1, &ramp(0..4)[..]);
        assert!(assembler.next_frame().is_none());
        assembler.push(&ramp(12..14), &ramp(12..14)).unwrap();
        assert_eq!(assembler.next_frame().unwrap().1, &ramp(10..14)[..]);
    }

    #[test]
    fn unequal_or_non_finite_pieces_are_refused() {
        let layout = FrameLayout::new(4, 4, 1000).unwrap();
        let mut assembler = FrameAssembler::new(layout);
        assert!(assembler.push(&[0.0; 3], &[0.0; 2]).is_err());
        assert!(assembler.push(&[0.0, f64::NAN], &[0.0; 2]).is_err());
        assembler.push(&[0.0; 6], &[0.0; 6]).unwrap();
        assert!(assembler.next_frame().is_some());
        assert_eq!(assembler.pending(), 2);
    }
}
