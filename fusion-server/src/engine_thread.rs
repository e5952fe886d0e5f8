//! The engine thread of the live service: admits what the Zenoh callbacks hand over (everything
//! that arrived while it was busy, as one batch), processes it, refreshes the snapshot the
//! queryables answer from, hands track sets to the publisher and writes checkpoints.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use protocol::{SensorId, Status, TrackSet, WireFormat};
use tokio::sync::mpsc;

use crate::checkpoint::{self, Checkpoint};
use crate::clock;
use crate::config::ServerConfig;
use crate::engine::{Engine, Rejection};
use crate::publisher::Outbox;
use transport::LogLimiter;

/// What Zenoh callbacks hand to the engine thread.
pub(crate) enum Inbound {
    /// A measurement set's payload, as it arrived on a sensor's key.
    Set {
        key_sensor: SensorId,
        payload: Vec<u8>,
        format: Result<WireFormat, String>,
        arrived: f64,
    },
    /// A descriptor (published, or a reply to the server's `get`).
    Descriptor {
        payload: Vec<u8>,
        format: Result<WireFormat, String>,
    },
    /// A liveliness token appeared or went away.
    Alive { sensor: SensorId, alive: bool },
    /// The current filter state is asked for (a standby joining the site starts from it).
    Checkpoint(tokio::sync::oneshot::Sender<Checkpoint>),
    /// A standby takes the active server's filter state.
    Restore(Box<Checkpoint>),
    /// Drain, checkpoint and stop.
    Shutdown,
}

/// What queryables answer from.
#[derive(Clone)]
pub(crate) struct Snapshot {
    pub(crate) tracks: TrackSet,
    pub(crate) status: Status,
}

/// Loads the configured checkpoint into `engine` when it exists and is usable; logs why not.
pub(crate) fn restore_checkpoint(config: &ServerConfig, engine: &mut Engine, now: f64) {
    let Some(path) = &config.checkpoint.path else {
        return;
    };
    match checkpoint::load(path, &config.site.name, now, config.checkpoint.max_age_s) {
        Ok(checkpoint) => match engine.restore(checkpoint.state) {
            Ok(()) => {
                tracing::info!(path = %path.display(), "filter state restored from checkpoint")
            }
            Err(e) => {
                tracing::warn!(path = %path.display(), error = %e, "checkpoint rejected, starting empty")
            }
        },
        Err(checkpoint::LoadError::Missing(_)) => {
            tracing::info!(path = %path.display(), "no checkpoint yet, starting empty")
        }
        Err(e) => tracing::warn!(error = %e, "starting empty"),
    }
}

fn save_checkpoint(config: &ServerConfig, engine: &Engine) {
    let Some(path) = &config.checkpoint.path else {
        return;
    };
    if let Err(e) = checkpoint::save(path, &current_checkpoint(engine)) {
        tracing::error!(path = %path.display(), error = %e, "writing the checkpoint failed");
    }
}

/// The engine's state now, as a checkpoint.
fn current_checkpoint(engine: &Engine) -> Checkpoint {
    Checkpoint {
        saved_at: clock::now(),
        site: engine.site().to_string(),
        state: engine.checkpoint(),
    }
}

/// The engine thread: admits what arrives, processes what is ready, refreshes the snapshot,
/// hands track sets to the publisher and checkpoints, until told to shut down.
pub(crate) fn engine_loop(
    mut engine: Engine,
    config: ServerConfig,
    rx: Receiver<Inbound>,
    snapshot: Arc<Mutex<Snapshot>>,
    overflow: Arc<AtomicU64>,
    outbox: Outbox,
    ask_tx: mpsc::UnboundedSender<SensorId>,
) {
    let mut limiter = LogLimiter::new(Duration::from_secs(5));
    let mut last_checkpoint = clock::now();
    let mut reported_overflow = 0;
    let mut shutting_down = false;
    while !shutting_down {
        // Wake now and then without input, for the snapshot, the overflow report and checkpoints.
        let first = match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(msg) => Some(msg),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => Some(Inbound::Shutdown),
        };
        for msg in first
            .into_iter()
            .chain(std::iter::from_fn(|| rx.try_recv().ok()))
        {
            match msg {
                Inbound::Shutdown => shutting_down = true,
                other => handle(&mut engine, other, &mut limiter, &ask_tx),
            }
        }
        let now = clock::now();
        let step = if shutting_down {
            engine.flush(now)
        } else {
            engine.step(now)
        };
        if let Some(last) = step.tracks.last() {
            outbox.offer(last.clone(), &step.arrivals);
        }
        let dropped = overflow.load(Ordering::Relaxed);
        if dropped > reported_overflow {
            engine.count_overflow(dropped - reported_overflow);
            if limiter.allow("overflow").is_some() {
                tracing::warn!(dropped, "ingest queue full: sets dropped");
            }
            reported_overflow = dropped;
        }
        {
            let status = engine.status(now);
            let mut guard = snapshot.lock().unwrap_or_else(|p| p.into_inner());
            guard.tracks = engine.tracks().clone();
            guard.status = status;
        }
        if shutting_down || now - last_checkpoint >= config.checkpoint.interval_s {
            save_checkpoint(&config, &engine);
            last_checkpoint = now;
        }
    }
}

fn handle(
    engine: &mut Engine,
    msg: Inbound,
    limiter: &mut LogLimiter,
    ask_tx: &mpsc::UnboundedSender<SensorId>,
) {
    let result = match msg {
        Inbound::Set {
            key_sensor,
            payload,
            format,
            arrived,
        } => match format {
            Ok(format) => engine
                .admit_set(Some(&key_sensor), &payload, format, arrived)
                .map(|_| ()),
            Err(e) => Err(engine.reject_undecodable(Some(&key_sensor), e)),
        },
        Inbound::Descriptor { payload, format } => match format {
            Ok(format) => engine.admit_descriptor(&payload, format).map(|learned| {
                tracing::debug!(?learned, "descriptor");
            }),
            Err(e) => Err(engine.reject_undecodable(None, e)),
        },
        Inbound::Alive { sensor, alive } => {
            tracing::info!(sensor = %sensor, alive, "liveliness");
            engine.set_alive(&sensor, alive);
            if alive && !engine.is_known(&sensor) {
                let _ = ask_tx.send(sensor);
            }
            Ok(())
        }
        Inbound::Checkpoint(reply) => {
            // The asker may have given up already; nothing to do then.
            let _ = reply.send(current_checkpoint(engine));
            Ok(())
        }
        Inbound::Restore(checkpoint) => {
            if let Err(e) = engine.restore(checkpoint.state) {
                tracing::warn!(error = %e, "the active server's state was rejected");
            }
            Ok(())
        }
        Inbound::Shutdown => Ok(()),
    };
    if let Err(rejection) = result {
        if let Rejection::UnknownSensor(sensor, count) = &rejection {
            // Ask on the first set, then now and then in case the first answer was lost.
            if *count % 200 == 1 {
                let _ = ask_tx.send(sensor.clone());
            }
        }
        let key = rejection_key(&rejection);
        if let Some(suppressed) = limiter.allow(&key) {
            tracing::warn!(suppressed, "{rejection}");
        }
    }
}

fn rejection_key(rejection: &Rejection) -> String {
    match rejection {
        Rejection::Undecodable(_) => "undecodable".into(),
        Rejection::Invalid { sensor, .. } => format!("invalid/{sensor}"),
        Rejection::UnknownSensor(sensor, _) => format!("unknown/{sensor}"),
        Rejection::Late { sensor, .. } => format!("late/{sensor}"),
        Rejection::Overflow(sensor) => format!("overflow/{sensor}"),
    }
}
