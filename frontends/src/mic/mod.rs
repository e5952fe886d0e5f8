//! Microphone-pair front end: two-channel audio → per-frame sets of time differences of arrival (TDOA).
//!
//! Following Pham (2007, §5.4), each frame's GCC-PHAT is computed and its strongest local maxima within the
//! physically possible range ±d/c are reported as the TDOA set; with several talkers and room echoes some of
//! those are clutter, which the PHD filter downstream is built to handle. Sign convention (protocol `mic_pair`):
//! `tau = (‖x − m2‖ − ‖x − m1‖)/c`, positive when the source is closer to mic 1, the first channel.
//!
//! Typical use: [`read_stereo_wav`] (or [`read_mono_pair`]) → [`MicPairPipeline::process`].

mod audio;
mod config;
mod error;
mod framing;
mod gcc_phat;
mod peaks;
mod pipeline;
mod wav;

pub use audio::StereoAudio;
pub use config::MicPairConfig;
pub use error::MicError;
pub use framing::{FrameLayout, FrameSpan};
pub use gcc_phat::{GccPhat, GccPhatSettings, LagWindow, EDGE_MARGIN_SAMPLES};
pub use peaks::{strongest_peaks, RefinedPeak};
pub use pipeline::{MicPairPipeline, TdoaFrame, TdoaPeak, MAX_FRAME_LEN};
pub use wav::{read_mono_pair, read_stereo_wav};
