//! The inlet of the engine: Zenoh callbacks hand what they receive to a bounded channel and
//! never block; what does not fit is counted.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::Arc;

use protocol::WireFormat;
use zenoh::bytes::Encoding;

use crate::engine_thread::Inbound;

/// The sending end of the engine's channel, with its overflow counter.
#[derive(Clone)]
pub struct Inlet {
    tx: SyncSender<Inbound>,
    overflow: Arc<AtomicU64>,
}

impl Inlet {
    /// An inlet on `tx`, counting what does not fit in `overflow`.
    pub fn new(tx: SyncSender<Inbound>, overflow: Arc<AtomicU64>) -> Self {
        Self { tx, overflow }
    }

    /// Hands a message to the engine without ever blocking a Zenoh thread.
    pub fn offer(&self, msg: Inbound) {
        match self.tx.try_send(msg) {
            Ok(()) | Err(TrySendError::Disconnected(_)) => {}
            Err(TrySendError::Full(_)) => {
                self.overflow.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// Tells the engine to drain and stop; waits for room in the channel, since this message
    /// must not be lost.
    pub fn shut_down(self) {
        let _ = self.tx.send(Inbound::Shutdown);
    }
}

/// The wire format an encoding names (an error for one the contract does not know).
pub fn wire_format(encoding: &Encoding) -> Result<WireFormat, String> {
    WireFormat::from_zenoh(encoding).map_err(|e| e.to_string())
}
