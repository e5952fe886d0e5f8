//! `mic-pair --sound-card [DEVICE]` (cargo feature `sound-card`, off by default): live capture of a
//! stereo input with `cpal` (ALSA on Linux, so building with the feature needs `libasound2-dev`).
//!
//! The captured samples are served as a WAV stream (a 32-bit float stereo header with the streaming
//! size 0xFFFFFFFF, then the samples) to [`LiveMic`], the very path of `--wav -`: the same framing,
//! stamping on arrival, bounded queue and frame dropping, and no second copy of any of it.

use std::io::Read;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::Duration;

use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
use frontends::mic::MicPairConfig;

use crate::error::AgentError;
use crate::mic_stream::LiveMic;
use transport::shutdown::signalled;

/// Callback buffers waiting to be read before the newest are dropped (whole buffers, counted).
const QUEUE_BUFFERS: usize = 256;

/// How often the capture thread looks whether the agent still wants samples.
const POLL: Duration = Duration::from_millis(200);

/// Opens `device` (by name; the default input device when `None`) at 2 channels and `sample_rate`
/// and starts analysing what it captures. The capture lives on a thread of its own (a cpal stream
/// may not move between threads), until the agent stops reading or is signalled to stop.
pub fn start(
    device: Option<&str>,
    sample_rate: u32,
    config: MicPairConfig,
    delay_ms: f64,
) -> Result<LiveMic, AgentError> {
    let (sender, buffers) = sync_channel::<Vec<f32>>(QUEUE_BUFFERS);
    let dropped = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let device = device.map(str::to_owned);
    let (counter, stopping) = (Arc::clone(&dropped), Arc::clone(&stop));
    std::thread::Builder::new()
        .name("sound-card".into())
        .spawn(
            move || match open_capture(device.as_deref(), sample_rate, sender, counter) {
                Ok(stream) => {
                    let _ = ready_tx.send(Ok(()));
                    while !stopping.load(Ordering::Relaxed) && !signalled() {
                        std::thread::sleep(POLL);
                    }
                    drop(stream);
                }
                Err(error) => {
                    let _ = ready_tx.send(Err(error));
                }
            },
        )
        .map_err(|e| AgentError::Usage(format!("cannot start the capture thread: {e}")))?;
    ready_rx.recv().map_err(|_| {
        AgentError::Usage("the capture thread ended before the capture started".into())
    })??;
    let input = CapturedWav::new(sample_rate, buffers, dropped, stop);
    LiveMic::start(input, config, delay_ms)
}

/// Builds and starts the capture stream, each buffer handed to `sender`.
fn open_capture(
    device: Option<&str>,
    sample_rate: u32,
    sender: SyncSender<Vec<f32>>,
    dropped: Arc<AtomicU64>,
) -> Result<cpal::Stream, AgentError> {
    let device = find_device(device)?;
    let name = device.name().unwrap_or_else(|_| "?".into());
    let stream_config = cpal::StreamConfig {
        channels: 2,
        sample_rate: cpal::SampleRate(sample_rate),
        buffer_size: cpal::BufferSize::Default,
    };
    let stream = device
        .build_input_stream(
            &stream_config,
            capture_callback(sender, dropped),
            |error| tracing::error!(%error, "sound card capture failed"),
            None,
        )
        .map_err(|e| {
            card_error(
                &name,
                &format!("cannot capture stereo at {sample_rate} Hz: {e}"),
            )
        })?;
    stream
        .play()
        .map_err(|e| card_error(&name, &format!("cannot start the capture: {e}")))?;
    tracing::info!(device = %name, sample_rate, "capturing from the sound card");
    Ok(stream)
}

fn card_error(name: &str, what: &str) -> AgentError {
    AgentError::Usage(format!("sound card {name:?}: {what}"))
}

/// The named input device, or the host's default one.
fn find_device(name: Option<&str>) -> Result<cpal::Device, AgentError> {
    let host = cpal::default_host();
    match name {
        None => host
            .default_input_device()
            .ok_or_else(|| AgentError::Usage("no default sound input device".into())),
        Some(wanted) => host
            .input_devices()
            .map_err(|e| AgentError::Usage(format!("cannot list sound input devices: {e}")))?
            .find(|d| d.name().is_ok_and(|n| n == wanted))
            .ok_or_else(|| AgentError::Usage(format!("no sound input device named {wanted:?}"))),
    }
}

/// The capture callback: hands each buffer over without ever blocking the audio thread.
fn capture_callback(
    sender: SyncSender<Vec<f32>>,
    dropped: Arc<AtomicU64>,
) -> impl FnMut(&[f32], &cpal::InputCallbackInfo) + Send + 'static {
    move |data, _| {
        if let Err(TrySendError::Full(_)) = sender.try_send(data.to_vec()) {
            dropped.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// The captured samples as a streaming WAV file: its header first, then little-endian `f32` pairs.
struct CapturedWav {
    pending: Vec<u8>,
    offset: usize,
    buffers: Receiver<Vec<f32>>,
    dropped: Arc<AtomicU64>,
    reported: u64,
    /// Tells the capture thread to stop once nobody reads.
    stop: Arc<AtomicBool>,
}

impl CapturedWav {
    fn new(
        sample_rate: u32,
        buffers: Receiver<Vec<f32>>,
        dropped: Arc<AtomicU64>,
        stop: Arc<AtomicBool>,
    ) -> Self {
        Self {
            pending: wav_header(sample_rate),
            offset: 0,
            buffers,
            dropped,
            reported: 0,
            stop,
        }
    }
}

impl Drop for CapturedWav {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

impl Read for CapturedWav {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        if self.offset == self.pending.len() {
            // The stream ends when the capture does (the sender dropped with the cpal stream).
            let Ok(buffer) = self.buffers.recv() else {
                return Ok(0);
            };
            let dropped = self.dropped.load(Ordering::Relaxed);
            if dropped > self.reported {
                tracing::warn!(
                    dropped_buffers = dropped,
                    "sound card buffers dropped: the reader fell behind"
                );
                self.reported = dropped;
            }
            self.pending = buffer.iter().flat_map(|x| x.to_le_bytes()).collect();
            self.offset = 0;
        }
        let n = out.len().min(self.pending.len() - self.offset);
        out[..n].copy_from_slice(&self.pending[self.offset..self.offset + n]);
        self.offset += n;
        Ok(n)
    }
}

/// A WAV header for an endless stream of 32-bit float stereo samples.
fn wav_header(sample_rate: u32) -> Vec<u8> {
    const CHANNELS: u16 = 2;
    const BITS: u16 = 32;
    const IEEE_FLOAT: u16 = 3;
    let block_align = CHANNELS * BITS / 8;
    let mut header = Vec::with_capacity(44);
    header.extend_from_slice(b"RIFF");
    header.extend_from_slice(&u32::MAX.to_le_bytes());
    header.extend_from_slice(b"WAVEfmt ");
    header.extend_from_slice(&16u32.to_le_bytes());
    header.extend_from_slice(&IEEE_FLOAT.to_le_bytes());
    header.extend_from_slice(&CHANNELS.to_le_bytes());
    header.extend_from_slice(&sample_rate.to_le_bytes());
    header.extend_from_slice(&(sample_rate * u32::from(block_align)).to_le_bytes());
    header.extend_from_slice(&block_align.to_le_bytes());
    header.extend_from_slice(&BITS.to_le_bytes());
    header.extend_from_slice(b"data");
    header.extend_from_slice(&u32::MAX.to_le_bytes());
    header
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_served_stream_is_a_wav_stream_of_the_captured_samples() {
        let (sender, buffers) = sync_channel(4);
        sender.send(vec![0.5f32, -0.25, 1.0, 0.0]).unwrap();
        drop(sender);
        let stop = Arc::new(AtomicBool::new(false));
        let mut input = CapturedWav::new(16_000, buffers, Arc::new(AtomicU64::new(0)), stop);
        let mut stream = frontends::mic::WavStream::open(&mut input).unwrap();
        let (mut mic1, mut mic2) = (Vec::new(), Vec::new());
        while stream.read_pairs(&mut mic1, &mut mic2).unwrap() > 0 {}
        assert_eq!(stream.format().sample_rate, 16_000);
        assert_eq!(mic1, vec![0.5, 1.0]);
        assert_eq!(mic2, vec![-0.25, 0.0]);
    }
}
