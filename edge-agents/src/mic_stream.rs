//! `mic-pair --wav -`: a live WAV stream on stdin, one TDOA set per frame as soon as the frame's audio is in.
//!
//! A reader thread decodes the stream ([`frontends::mic::WavStream`]), cuts it into frames with the same
//! [`FrameAssembler`] as the whole-file path (so the same audio gives the same sets) and hands each frame to a
//! bounded queue. When the analysis cannot keep up the reader drops whole frames rather than waiting: the
//! capture never blocks, and the drops are counted and logged (at most every 5 s).
//!
//! Stamps: a frame's centre on the host clock. Samples that arrive in one read are taken to end at the read's
//! host time, so media time `m` maps to `arrival − (pushed / fs − m)`; `--pipeline-delay-ms` (the sound card's
//! buffer and the pipe in front of the agent) is subtracted.

use std::io::Read;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::Duration;

use frontends::mic::{
    relative_variances, FrameAssembler, MicError, MicPairConfig, MicPairPipeline, WavStream,
};

use crate::capture_clock::CaptureClock;
use crate::drop_report::DropReport;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::run::{Event, EventSource};
use crate::tdoa_noise::TdoaNoise;
use transport::Shutdown;

/// Frames waiting for analysis before the reader drops new ones (at the default 256 ms, 4 s of audio).
const QUEUE_FRAMES: usize = 16;
/// How long one wait for a frame lasts before the shutdown flag is looked at again.
const POLL: Duration = Duration::from_millis(100);

/// What the reader thread hands over.
enum Captured {
    /// One whole frame with its capture stamp.
    Frame {
        stamp: f64,
        mic1: Vec<f64>,
        mic2: Vec<f64>,
    },
    /// The stream ended cleanly; `partial` samples of an unfinished frame were left unanalysed.
    End {
        partial: usize,
        leftover_bytes: usize,
    },
    /// Reading or decoding failed.
    Failed(MicError),
}

/// TDOA sets of a live stream, analysed on the run loop's side of the queue.
pub struct LiveMic {
    frames: Receiver<Captured>,
    pipeline: MicPairPipeline,
    clock: CaptureClock,
    drops: DropReport,
    analysed: u64,
    shutdown: Option<Shutdown>,
    /// The covariances its TDOAs are sent with (`None`: the descriptor's noise for every one).
    noise: Option<TdoaNoise>,
}

impl LiveMic {
    /// Reads the stream's header from `input` (errors here stop the agent before anything is published) and
    /// starts the reader thread.
    pub fn start(
        input: impl Read + Send + 'static,
        config: MicPairConfig,
        delay_ms: f64,
    ) -> Result<Self, AgentError> {
        let clock = CaptureClock::new(delay_ms)?;
        let stream = WavStream::open(input)?;
        let format = stream.format();
        let pipeline = MicPairPipeline::new(config, format.sample_rate)?;
        let (sender, frames) = sync_channel(QUEUE_FRAMES);
        let (drops, dropped) = DropReport::new();
        let reader = Reader {
            stream,
            assembler: FrameAssembler::new(pipeline.layout()),
            rate: f64::from(format.sample_rate),
            clock,
            sender,
            dropped: Arc::clone(&dropped),
            last_stamp: f64::NEG_INFINITY,
        };
        std::thread::Builder::new()
            .name("wav-stdin".into())
            .spawn(move || reader.run())
            .map_err(|e| AgentError::Usage(format!("cannot start the audio reader thread: {e}")))?;
        tracing::info!(
            sample_rate = format.sample_rate,
            bits = format.bits_per_sample,
            float = format.float,
            frame_samples = pipeline.layout().frame_len(),
            pipeline_delay_ms = delay_ms,
            "live WAV stream on stdin: sets stamped on arrival on the host clock, less the pipeline delay"
        );
        Ok(Self {
            frames,
            pipeline,
            clock,
            drops,
            analysed: 0,
            shutdown: None,
            noise: None,
        })
    }

    /// Sends each TDOA with the covariance `noise` gives it.
    pub fn with_noise(mut self, noise: TdoaNoise) -> Self {
        self.noise = Some(noise);
        self
    }

    /// The host's Unix time at which the stream was opened (the run's pacing origin).
    pub fn origin_wall(&self) -> f64 {
        self.clock.origin_wall()
    }

    /// Logs frames dropped since the last report, with how far behind the analysis runs.
    fn report_drops(&mut self, stamp: f64) {
        if let Some((total, new)) = self.drops.due() {
            tracing::warn!(
                dropped_total = total,
                dropped_now = new,
                lag_ms = self.clock.lag(stamp) * 1e3,
                "the analysis cannot keep up with the audio: whole frames dropped"
            );
        }
    }
}

impl EventSource for LiveMic {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        let message = loop {
            if self.shutdown.as_ref().is_some_and(Shutdown::is_requested) {
                return Ok(None);
            }
            match self.frames.recv_timeout(POLL) {
                Ok(message) => break message,
                Err(RecvTimeoutError::Timeout) => continue,
                // A closed queue without an `End` means the reader thread died: the stream's end.
                Err(RecvTimeoutError::Disconnected) => {
                    break Captured::End {
                        partial: 0,
                        leftover_bytes: 0,
                    }
                }
            }
        };
        match message {
            Captured::Frame { stamp, mic1, mic2 } => {
                let peaks = self.pipeline.frame_peaks(&mic1, &mic2)?;
                let measurements = peaks.iter().map(|peak| vec![peak.tdoa]).collect();
                let covariances = self
                    .noise
                    .and_then(|noise| noise.covariances(&relative_variances(peaks)));
                self.analysed += 1;
                self.report_drops(stamp);
                Ok(Some(Event::Set {
                    stream: 0,
                    frame: Frame {
                        stamp,
                        measurements,
                        covariances,
                    },
                }))
            }
            Captured::End {
                partial,
                leftover_bytes,
            } => {
                tracing::info!(
                    frames = self.analysed,
                    dropped = self.drops.total(),
                    unanalysed_samples = partial,
                    leftover_bytes,
                    "the audio stream ended (stdin closed)"
                );
                Ok(None)
            }
            Captured::Failed(error) => Err(error.into()),
        }
    }

    fn is_live(&self) -> bool {
        true
    }

    fn attach_shutdown(&mut self, shutdown: &Shutdown) {
        self.shutdown = Some(shutdown.clone());
    }
}

/// The reader thread's state.
struct Reader<R> {
    stream: WavStream<R>,
    assembler: FrameAssembler,
    rate: f64,
    clock: CaptureClock,
    sender: SyncSender<Captured>,
    dropped: Arc<AtomicU64>,
    last_stamp: f64,
}

impl<R: Read> Reader<R> {
    /// Reads until the stream ends or the run loop is gone, then says how it ended.
    fn run(mut self) {
        let end = match self.pump() {
            Ok(()) => Captured::End {
                partial: self.assembler.pending(),
                leftover_bytes: self.stream.leftover_bytes(),
            },
            Err(error) => Captured::Failed(error),
        };
        // Blocking is right here: the end must not be dropped, and nothing is being captured any more.
        let _ = self.sender.send(end);
    }

    /// Decodes pieces as they arrive and queues every frame they complete.
    fn pump(&mut self) -> Result<(), MicError> {
        let (mut mic1, mut mic2) = (Vec::new(), Vec::new());
        loop {
            mic1.clear();
            mic2.clear();
            if self.stream.read_pairs(&mut mic1, &mut mic2)? == 0 {
                return Ok(());
            }
            let arrival = self.clock.now();
            self.assembler.push(&mic1, &mic2)?;
            let pushed = self.assembler.pushed() as f64;
            while let Some((span, a, b)) = self.assembler.next_frame() {
                let stamp = arrival - (pushed / self.rate - span.centre_time);
                // Arrival jitter must not reorder stamps.
                let stamp = stamp.max(self.last_stamp + 1e-6);
                self.last_stamp = stamp;
                let frame = Captured::Frame {
                    stamp,
                    mic1: a.to_vec(),
                    mic2: b.to_vec(),
                };
                match self.sender.try_send(frame) {
                    Ok(()) => {}
                    Err(TrySendError::Full(_)) => {
                        self.dropped.fetch_add(1, Ordering::Relaxed);
                    }
                    Err(TrySendError::Disconnected(_)) => return Ok(()),
                }
            }
        }
    }
}
