//! Microphone-pair front end: two-channel audio → per-frame sets of time differences of arrival (TDOA).
//!
//! Following Pham (2007, §5.4), each frame's GCC-PHAT is computed and its strongest local maxima within the
//! physically possible range ±d/c are reported as the TDOA set; with several talkers and room echoes some of
//! those are clutter, which the PHD filter downstream is built to handle. Sign convention (protocol `mic_pair`):
//! `tau = (‖x − m2‖ − ‖x − m1‖)/c`, positive when the source is closer to mic 1, the first channel.
//!
//! Per frame ([`MicPairPipeline`]): Hann window, zero-padding, real FFT of both channels; a speech-presence check
//! (spectral contrast, frames as flat as white noise give an empty set); the cross-spectrum `Y2 · conj(Y1)`
//! with PHAT weighting, bins below a median-relative gate left out; inverse FFT of the cross-spectrum
//! zero-padded by the interpolation factor; optionally pooled with the earlier frames' correlations as far as a
//! talker may drift (`pooling.rs`); the K highest local maxima above the threshold and above a share of the
//! highest within ±(d/c + ½ sample), parabola-refined and clamped to ±d/c; each with its variance relative to
//! the frame's strongest peak's, from Knapp & Carter's bound at the two heights (`peak_noise.rs`), which the
//! agent turns into the covariance it sends with the TDOA. FFT plans and buffers are made once per pipeline.
//!
//! Typical use: [`read_stereo_wav`] (or [`read_mono_pair`]) → [`MicPairPipeline::process`].

#![warn(missing_docs)]

mod audio;
mod coherence;
mod config;
mod error;
mod frame_assembler;
mod framing;
mod gcc_phat;
mod peak_noise;
mod peaks;
mod pipeline;
mod pooling;
mod wav;
mod wav_stream;

pub use audio::StereoAudio;
pub use config::MicPairConfig;
pub use error::MicError;
pub use frame_assembler::FrameAssembler;
pub use framing::{FrameLayout, FrameSpan};
pub use gcc_phat::{GccPhat, GccPhatSettings, LagWindow, EDGE_MARGIN_SAMPLES};
pub use peak_noise::relative_variances;
pub use peaks::{strongest_peaks, RefinedPeak};
pub use pipeline::{MicPairPipeline, TdoaFrame, TdoaPeak, MAX_FRAME_LEN};
pub use wav::{read_mono_pair, read_stereo_wav};
pub use wav_stream::{WavStream, WavStreamFormat};
