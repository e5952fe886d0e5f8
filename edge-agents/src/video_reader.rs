//! The reader thread of `--video`: it runs ffmpeg on the source, pulls the decoded frames from its stdout
//! continuously and hands them over through a slot the processing side takes them from.
//!
//! A file is read no faster than it is processed (the slot holds two frames and the reader waits), so every
//! frame is used and the output is deterministic. A live source is never held back: its slot holds one
//! frame, and a frame that arrives before the last one was taken replaces it and is counted as dropped, so
//! the processing side always gets the newest frame and ffmpeg's pipe never fills. A network source that
//! ends or breaks is reported down (the sensor leaves Zenoh until its next frame) and opened again after a
//! pause growing from 250 ms to 5 s (logged each time).

use std::io::{BufRead, BufReader, Read};
use std::process::ChildStdout;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crossbeam_channel::{Receiver, RecvTimeoutError, SendTimeoutError, Sender, TrySendError};
use image::codecs::pnm::PnmDecoder;
use image::{ImageDecoder, RgbImage};

use crate::error::AgentError;
use crate::ffmpeg::{spawn_decoder, Decoder, SourceKind, VideoSpec};

/// First pause before a network source is opened again.
const FIRST_BACKOFF: Duration = Duration::from_millis(250);
/// Longest pause between two attempts.
const MAX_BACKOFF: Duration = Duration::from_secs(5);
/// How often a blocked hand-off looks at the stop flag.
const POLL: Duration = Duration::from_millis(100);
/// How long dropping the reader waits for its thread to stop.
const STOP_PATIENCE: Duration = Duration::from_secs(2);
/// Frames larger than this many pixels are refused (a corrupt header must not allocate gigabytes).
const MAX_PIXELS: u64 = 8192 * 8192;

/// One decoded frame.
pub struct VideoFrame {
    /// Its position among every frame the source delivered (dropped ones included), from 0.
    pub index: u64,
    /// When its first bytes arrived from ffmpeg.
    pub arrived: Instant,
    /// The pixels.
    pub image: RgbImage,
}

/// What the reader hands over: frames, then one end.
pub enum VideoMessage {
    /// A frame.
    Frame(VideoFrame),
    /// A network source ended or broke and is being opened again.
    Down,
    /// The source is over: `Ok` with what happened when it delivered frames, `Err` when it never did.
    End(Result<String, String>),
}

/// The processing side's handle on the reader thread and its ffmpeg; dropping it kills and reaps ffmpeg.
pub struct VideoReader {
    messages: Receiver<VideoMessage>,
    dropped: Arc<AtomicU64>,
    shared: Arc<Shared>,
    /// The reader thread, waited for on drop so that an ffmpeg it was just starting is stopped too.
    worker: Option<std::thread::JoinHandle<()>>,
}

/// What the reader thread and its handle share.
struct Shared {
    stop: AtomicBool,
    /// The running ffmpeg, so that the handle can kill it while the thread is blocked reading its output.
    decoder: Mutex<Option<Decoder>>,
}

impl VideoReader {
    /// Starts ffmpeg on `spec` (an error at once if it cannot be started) and the reader thread.
    pub fn start(spec: VideoSpec) -> Result<Self, AgentError> {
        let kind = spec.kind();
        let first = spawn_decoder(&spec)?;
        let (sender, messages) =
            crossbeam_channel::bounded(if kind == SourceKind::File { 2 } else { 1 });
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            decoder: Mutex::new(None),
        });
        let dropped = Arc::new(AtomicU64::new(0));
        let mut worker = Worker {
            spec,
            kind,
            slot: Slot {
                sender,
                receiver: messages.clone(),
                dropped: Arc::clone(&dropped),
            },
            shared: Arc::clone(&shared),
            frames: 0,
            up: true,
        };
        let worker = std::thread::Builder::new()
            .name("video-reader".into())
            .spawn(move || worker.run(first))
            .map_err(|e| AgentError::Video(format!("cannot start the video reader thread: {e}")))?;
        Ok(Self {
            messages,
            dropped,
            shared,
            worker: Some(worker),
        })
    }

    /// The next message, or `None` if nothing came within `timeout`.
    pub fn next(&self, timeout: Duration) -> Option<VideoMessage> {
        match self.messages.recv_timeout(timeout) {
            Ok(message) => Some(message),
            Err(RecvTimeoutError::Timeout) => None,
            // The thread only leaves after sending its end, or when told to stop.
            Err(RecvTimeoutError::Disconnected) => {
                Some(VideoMessage::End(Ok("the video reader stopped".into())))
            }
        }
    }

    /// Frames of a live source replaced by a newer one before they were taken, since the start.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

impl Drop for VideoReader {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(decoder) = self.shared.decoder.lock().ok().and_then(|mut d| d.take()) {
            tracing::debug!("{}", decoder.stop());
        }
        // The thread sees the flag within one poll; the deadline only guards against the unforeseen.
        let deadline = Instant::now() + STOP_PATIENCE;
        if let Some(worker) = self.worker.take() {
            while !worker.is_finished() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(10));
            }
            if worker.is_finished() {
                let _ = worker.join();
            }
        }
    }
}

/// The sending side of the hand-off.
struct Slot {
    sender: Sender<VideoMessage>,
    /// Lets a live source take the waiting frame out to put a newer one in.
    receiver: Receiver<VideoMessage>,
    dropped: Arc<AtomicU64>,
}

impl Slot {
    /// Hands a live frame over at once, replacing (and counting) a frame still waiting.
    fn replace(&self, message: VideoMessage) {
        if let Err(TrySendError::Full(message)) = self.sender.try_send(message) {
            if self.receiver.try_recv().is_ok() {
                self.dropped.fetch_add(1, Ordering::Relaxed);
            }
            // This thread is the only sender, so the slot it just emptied is free.
            let _ = self.sender.try_send(message);
        }
    }

    /// Hands a message over, waiting for room; false if `stop` was set meanwhile.
    fn wait_send(&self, mut message: VideoMessage, stop: &AtomicBool) -> bool {
        loop {
            match self.sender.send_timeout(message, POLL) {
                Ok(()) => return true,
                Err(SendTimeoutError::Timeout(back)) if !stop.load(Ordering::Relaxed) => {
                    message = back
                }
                Err(_) => return false,
            }
        }
    }
}

/// The reader thread's state.
struct Worker {
    spec: VideoSpec,
    kind: SourceKind,
    slot: Slot,
    shared: Arc<Shared>,
    /// Frames delivered so far, over every opening of the source.
    frames: u64,
    /// False from the moment a network source was reported down until its next frame.
    up: bool,
}

impl Worker {
    /// Reads `first` to its end, then (network sources) opens the source again and again until stopped.
    fn run(&mut self, first: (Decoder, ChildStdout)) {
        let mut decoder = Some(first);
        let mut backoff = FIRST_BACKOFF;
        loop {
            if let Some((running, frames)) = decoder.take() {
                let before = self.frames;
                let frames = BufReader::new(frames);
                *self.lock() = Some(running);
                if self.shared.stop.load(Ordering::Relaxed) {
                    // The handle was dropped before this ffmpeg was in reach: stop it here.
                    if let Some(running) = self.lock().take() {
                        running.stop();
                    }
                    return;
                }
                let outcome = self.read_frames(frames);
                let Some(running) = self.lock().take() else {
                    return; // The handle stopped ffmpeg: the run is over.
                };
                let ending = format!("{outcome}; {}", running.stop());
                if self.kind != SourceKind::Network {
                    self.finish(ending);
                    return;
                }
                if self.frames > before {
                    backoff = FIRST_BACKOFF;
                }
                if std::mem::replace(&mut self.up, false) {
                    self.slot.replace(VideoMessage::Down);
                }
                tracing::warn!(source = %self.spec.source, frames = self.frames, "video source ended ({ending}); opening it again in {} ms", backoff.as_millis());
            }
            if !self.pause(backoff) {
                return;
            }
            backoff = (backoff * 2).min(MAX_BACKOFF);
            match spawn_decoder(&self.spec) {
                Ok(next) => decoder = Some(next),
                Err(e) => {
                    self.finish_err(e.to_string());
                    return;
                }
            }
        }
    }

    /// Sends the end of a source that does not come back.
    fn finish(&self, ending: String) {
        let message = if self.frames == 0 {
            Err(format!("no frame from {}: {ending}", self.spec.source))
        } else {
            Ok(format!("{} frames, then {ending}", self.frames))
        };
        self.slot
            .wait_send(VideoMessage::End(message), &self.shared.stop);
    }

    /// Sends an error end.
    fn finish_err(&self, error: String) {
        self.slot
            .wait_send(VideoMessage::End(Err(error)), &self.shared.stop);
    }

    /// Sleeps `pause` in short steps; false if stopped meanwhile.
    fn pause(&self, pause: Duration) -> bool {
        let until = Instant::now() + pause;
        while Instant::now() < until {
            if self.shared.stop.load(Ordering::Relaxed) {
                return false;
            }
            std::thread::sleep(POLL.min(until.saturating_duration_since(Instant::now())));
        }
        !self.shared.stop.load(Ordering::Relaxed)
    }

    /// Hands over every frame ffmpeg writes until its output ends; says how it ended.
    fn read_frames(&mut self, mut frames: BufReader<impl Read>) -> String {
        loop {
            if self.shared.stop.load(Ordering::Relaxed) {
                return "stopped".into();
            }
            match read_ppm(&mut frames) {
                Ok(None) => return "end of stream".into(),
                Ok(Some((image, arrived))) => {
                    let frame = VideoFrame {
                        index: self.frames,
                        arrived,
                        image,
                    };
                    self.frames += 1;
                    self.up = true;
                    if self.kind == SourceKind::File {
                        if !self
                            .slot
                            .wait_send(VideoMessage::Frame(frame), &self.shared.stop)
                        {
                            return "stopped".into();
                        }
                    } else {
                        self.slot.replace(VideoMessage::Frame(frame));
                    }
                }
                Err(problem) => {
                    return format!("unreadable output after {} frames: {problem}", self.frames)
                }
            }
        }
    }

    /// The slot of the running ffmpeg (a poisoned lock only means a panic elsewhere; its data is still fine).
    fn lock(&self) -> std::sync::MutexGuard<'_, Option<Decoder>> {
        self.shared
            .decoder
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// Reads one PPM image; `None` at a clean end of the stream (between two images).
fn read_ppm(reader: &mut BufReader<impl Read>) -> Result<Option<(RgbImage, Instant)>, String> {
    let available = reader.fill_buf().map_err(|e| e.to_string())?;
    if available.is_empty() {
        return Ok(None);
    }
    let arrived = Instant::now();
    let decoder = PnmDecoder::new(&mut *reader).map_err(|e| format!("frame header: {e}"))?;
    let (width, height) = decoder.dimensions();
    if u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(format!("a frame of {width}x{height} pixels is too large"));
    }
    if decoder.color_type() != image::ColorType::Rgb8 {
        return Err(format!(
            "frames are {:?}, not 8-bit RGB",
            decoder.color_type()
        ));
    }
    let mut pixels = vec![0; decoder.total_bytes() as usize];
    decoder
        .read_image(&mut pixels)
        .map_err(|e| format!("frame data: {e}"))?;
    let image = RgbImage::from_raw(width, height, pixels)
        .ok_or_else(|| format!("a frame of {width}x{height} pixels has the wrong length"))?;
    Ok(Some((image, arrived)))
}
