//! Live LIDAR scans (`--velodyne`, `--scans DIR --follow`): a reader thread hands whole scans to a bounded
//! queue and the run loop segments them.
//!
//! When the segmentation cannot keep up the reader drops whole scans rather than waiting (the capture never
//! blocks); drops are counted and logged at most every 5 s, with how far behind the processing runs.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::Duration;

use frontends::lidar::PointCloud;
use transport::Shutdown;

use crate::capture_clock::CaptureClock;
use crate::drop_report::DropReport;
use crate::error::AgentError;
use crate::lidar::ScanSegmenter;
use crate::run::{Event, EventSource};

/// Scans waiting for segmentation before the reader drops new ones.
pub const QUEUE_SCANS: usize = 4;
/// How long one wait for a scan lasts before the shutdown flag is looked at again.
const POLL: Duration = Duration::from_millis(100);

/// What a reader thread hands over.
pub enum Captured {
    /// One scan with its capture stamp.
    Scan {
        /// Host time of its first packet (or of its file), less the pipeline delay.
        stamp: f64,
        /// Its points.
        cloud: PointCloud,
    },
    /// The source ended; the reason is logged.
    End(String),
}

/// The reader side's hand-off: queues a scan unless the queue is full, counting drops.
pub struct ScanQueue {
    sender: SyncSender<Captured>,
    dropped: Arc<AtomicU64>,
}

impl ScanQueue {
    /// Queues `scan`; false when the run loop is gone (the reader should stop).
    pub fn offer(&self, scan: Captured) -> bool {
        match self.sender.try_send(scan) {
            Ok(()) => true,
            Err(TrySendError::Full(_)) => {
                self.dropped.fetch_add(1, Ordering::Relaxed);
                true
            }
            Err(TrySendError::Disconnected(_)) => false,
        }
    }

    /// Says the source ended (waiting for room: nothing is captured any more).
    pub fn end(&self, reason: String) {
        let _ = self.sender.send(Captured::End(reason));
    }
}

/// Segmented live scans.
pub struct LiveLidar {
    scans: Receiver<Captured>,
    segmenter: ScanSegmenter,
    clock: CaptureClock,
    drops: DropReport,
    shutdown: Option<Shutdown>,
    what: &'static str,
}

impl LiveLidar {
    /// A queue for a reader thread and the source that empties it; `what` names the input in logs.
    pub fn new(
        segmenter: ScanSegmenter,
        clock: CaptureClock,
        what: &'static str,
    ) -> (ScanQueue, Self) {
        let (sender, scans) = std::sync::mpsc::sync_channel(QUEUE_SCANS);
        let (drops, dropped) = DropReport::new();
        let queue = ScanQueue {
            sender,
            dropped: Arc::clone(&dropped),
        };
        let source = Self {
            scans,
            segmenter,
            clock,
            drops,
            shutdown: None,
            what,
        };
        (queue, source)
    }

    /// Logs scans dropped since the last report.
    fn report_drops(&mut self, stamp: f64) {
        if let Some((total, new)) = self.drops.due() {
            tracing::warn!(
                input = self.what,
                dropped_total = total,
                dropped_now = new,
                lag_ms = self.clock.lag(stamp) * 1e3,
                "the segmentation cannot keep up: whole scans dropped"
            );
        }
    }
}

impl EventSource for LiveLidar {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        loop {
            if self.shutdown.as_ref().is_some_and(Shutdown::is_requested) {
                return Ok(None);
            }
            let message = match self.scans.recv_timeout(POLL) {
                Ok(message) => message,
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => Captured::End("the reader stopped".into()),
            };
            return Ok(match message {
                Captured::Scan { stamp, cloud } => {
                    self.report_drops(stamp);
                    Some(Event::Set {
                        stream: 0,
                        frame: self.segmenter.frame(&cloud, stamp),
                    })
                }
                Captured::End(reason) => {
                    tracing::info!(
                        input = self.what,
                        dropped = self.drops.total(),
                        %reason,
                        "the LIDAR input ended"
                    );
                    None
                }
            });
        }
    }

    fn is_live(&self) -> bool {
        true
    }

    fn attach_shutdown(&mut self, shutdown: &Shutdown) {
        self.shutdown = Some(shutdown.clone());
    }
}
