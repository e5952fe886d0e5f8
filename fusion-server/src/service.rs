//! The live service: Zenoh wiring around the [`Engine`].
//!
//! Zenoh callbacks only decode the key and the encoding and hand the payload to a bounded
//! channel (overflow is counted); the engine runs on its own thread, so slow clients never stall
//! ingest; queryables answer from a snapshot the engine refreshes; a publisher task puts the
//! latest `TrackSet` as soon as there is one (at most `output.max_publish_hz` times per second;
//! `publisher.rs`, followed by its JSON copy and its place in the history that `_time` queries
//! on the tracks queryable read, `track_output.rs`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, SyncSender, TrySendError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use protocol::{keys, SensorId, SensorKeyKind, Status, WireFormat};
use tokio::sync::mpsc;
use zenoh::bytes::Encoding;
use zenoh::sample::{Sample, SampleKind};
use zenoh::Wait;

use crate::clock;
use crate::config::ServerConfig;
use crate::engine::Engine;
use crate::engine_thread::{engine_loop, restore_checkpoint, Inbound, Snapshot};
use crate::publisher;
use crate::track_output::{self, TrackCopies};

/// Runs the service until SIGINT or SIGTERM.
pub async fn run(config: ServerConfig) -> anyhow::Result<()> {
    let started = clock::now();
    let mut engine = Engine::new(config.clone(), started, true)?;
    restore_checkpoint(&config, &mut engine, started);
    let site = engine.site().clone();

    // Started before its router (systemd, a laptop), the server waits for it as the agents do.
    let Some(session) = config.zenoh.open_retrying(wait_for_signal()).await? else {
        tracing::info!("stopped before the zenoh session opened");
        return Ok(());
    };
    tracing::info!(site = %site, zid = %session.zid(), mode = %config.zenoh.mode, "zenoh session open");

    let (tx, rx) = sync_channel::<Inbound>(config.ingest.queue_capacity);
    let overflow = Arc::new(AtomicU64::new(0));
    let snapshot = Arc::new(Mutex::new(Snapshot {
        tracks: engine.tracks().clone(),
        status: engine.status(started),
    }));
    let (ask_tx, mut ask_rx) = mpsc::unbounded_channel::<SensorId>();

    // Measurement sets.
    let sets_sub = {
        let tx = tx.clone();
        let overflow = overflow.clone();
        session
            .declare_subscriber(keys::all_measurements_key(&site))
            .callback(move |sample: Sample| {
                let Ok((_, sensor, _)) = keys::parse_sensor_key(sample.key_expr().as_str()) else {
                    return;
                };
                let msg = Inbound::Set {
                    key_sensor: sensor,
                    payload: sample.payload().to_bytes().into_owned(),
                    format: wire_format(sample.encoding()),
                    arrived: clock::now(),
                };
                offer(&tx, &overflow, msg);
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to measurements: {e}"))?
    };
    // Descriptors.
    let descriptors_sub = {
        let tx = tx.clone();
        let overflow = overflow.clone();
        session
            .declare_subscriber(keys::all_descriptors_key(&site))
            .callback(move |sample: Sample| {
                let msg = Inbound::Descriptor {
                    payload: sample.payload().to_bytes().into_owned(),
                    format: wire_format(sample.encoding()),
                };
                offer(&tx, &overflow, msg);
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to descriptors: {e}"))?
    };
    // Liveliness of the agents (history: tokens that already exist are reported too).
    let alive_sub = {
        let tx = tx.clone();
        let overflow = overflow.clone();
        session
            .liveliness()
            .declare_subscriber(keys::all_alive_key(&site))
            .history(true)
            .callback(move |sample: Sample| {
                if let Ok((_, sensor, SensorKeyKind::Alive)) =
                    keys::parse_sensor_key(sample.key_expr().as_str())
                {
                    let alive = sample.kind() == SampleKind::Put;
                    offer(&tx, &overflow, Inbound::Alive { sensor, alive });
                }
            })
            .await
            .map_err(|e| anyhow::anyhow!("subscribing to liveliness: {e}"))?
    };
    // Queryables for tracks (current or history) and status.
    let history = track_output::new_history(&config.output);
    let tracks_queryable =
        track_output::declare_tracks_queryable(&session, &site, snapshot.clone(), history.clone())
            .await?;
    let status_queryable =
        declare_status_queryable(&session, keys::status_key(&site), snapshot.clone()).await?;

    // Ask for every descriptor already out there, and for those of sensors that speak unannounced.
    {
        let session = session.clone();
        let tx = tx.clone();
        let overflow = overflow.clone();
        let all = keys::all_descriptors_key(&site);
        let site = site.clone();
        tokio::spawn(async move {
            fetch_descriptors(&session, &all, &tx, &overflow).await;
            while let Some(sensor) = ask_rx.recv().await {
                fetch_descriptors(
                    &session,
                    &keys::descriptor_key(&site, &sensor),
                    &tx,
                    &overflow,
                )
                .await;
            }
        });
    }

    // The publisher: the latest TrackSet as soon as there is one, rate-limited, and in JSON.
    let copies = TrackCopies::declare(&session, &site, &config.output, history).await?;
    let (outbox, publisher_task) = publisher::start(
        &session,
        &site,
        config.output.max_publish_hz,
        engine.latency(),
        copies,
    )
    .await?;

    // The engine thread.
    let engine_thread = {
        let config = config.clone();
        let snapshot = snapshot.clone();
        let overflow = overflow.clone();
        std::thread::Builder::new()
            .name("fusion-engine".into())
            .spawn(move || engine_loop(engine, config, rx, snapshot, overflow, outbox, ask_tx))?
    };

    wait_for_signal().await;
    tracing::info!("shutting down: draining what was received");
    // The callbacks go first so nothing new arrives; then the engine drains and checkpoints.
    drop(sets_sub);
    drop(descriptors_sub);
    drop(alive_sub);
    let _ = tx.send(Inbound::Shutdown);
    drop(tx);
    let engine_result = tokio::task::spawn_blocking(move || engine_thread.join())
        .await
        .map_err(|e| anyhow::anyhow!("engine thread: {e}"))?;
    if engine_result.is_err() {
        anyhow::bail!("the engine thread panicked");
    }
    // Let the publisher put the final track set before closing.
    tokio::time::sleep(Duration::from_millis(50)).await;
    publisher_task.abort();
    drop(tracks_queryable);
    drop(status_queryable);
    session
        .close()
        .await
        .map_err(|e| anyhow::anyhow!("closing the zenoh session: {e}"))?;
    tracing::info!("stopped");
    Ok(())
}

fn wire_format(encoding: &Encoding) -> Result<WireFormat, String> {
    WireFormat::from_zenoh(encoding).map_err(|e| e.to_string())
}

/// Hands a message to the engine without ever blocking a Zenoh thread.
fn offer(tx: &SyncSender<Inbound>, overflow: &AtomicU64, msg: Inbound) {
    match tx.try_send(msg) {
        Ok(()) | Err(TrySendError::Disconnected(_)) => {}
        Err(TrySendError::Full(_)) => {
            overflow.fetch_add(1, Ordering::Relaxed);
        }
    }
}

async fn declare_status_queryable(
    session: &zenoh::Session,
    key: String,
    snapshot: Arc<Mutex<Snapshot>>,
) -> anyhow::Result<zenoh::query::Queryable<()>> {
    let reply_key = key.clone();
    session
        .declare_queryable(key.clone())
        .callback(move |query| {
            let format = match WireFormat::from_query_parameters(query.parameters().as_str()) {
                Ok(format) => format,
                Err(e) => {
                    let _ = query.reply_err(e.to_string()).wait();
                    return;
                }
            };
            let status: Status = {
                let guard = snapshot.lock().unwrap_or_else(|p| p.into_inner());
                guard.status.clone()
            };
            match protocol::encode(&status, format) {
                Ok(bytes) => {
                    if let Err(e) = query
                        .reply(reply_key.clone(), bytes)
                        .encoding(Encoding::from(format.encoding_str()))
                        .wait()
                    {
                        tracing::debug!(error = %e, "reply failed");
                    }
                }
                Err(e) => tracing::error!(error = %e, "encoding a reply failed"),
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("declaring the queryable on {key}: {e}"))
}

async fn fetch_descriptors(
    session: &zenoh::Session,
    selector: &str,
    tx: &SyncSender<Inbound>,
    overflow: &AtomicU64,
) {
    let replies = match session.get(selector).timeout(Duration::from_secs(2)).await {
        Ok(replies) => replies,
        Err(e) => {
            tracing::warn!(selector, error = %e, "asking for descriptors failed");
            return;
        }
    };
    while let Ok(reply) = replies.recv_async().await {
        if let Ok(sample) = reply.result() {
            let msg = Inbound::Descriptor {
                payload: sample.payload().to_bytes().into_owned(),
                format: wire_format(sample.encoding()),
            };
            offer(tx, overflow, msg);
        }
    }
}

async fn wait_for_signal() {
    let ctrl_c = tokio::signal::ctrl_c();
    #[cfg(unix)]
    {
        let mut term =
            match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
                Ok(term) => term,
                Err(e) => {
                    tracing::warn!(error = %e, "cannot listen for SIGTERM");
                    let _ = ctrl_c.await;
                    return;
                }
            };
        tokio::select! {
            _ = ctrl_c => {}
            _ = term.recv() => {}
        }
    }
    #[cfg(not(unix))]
    let _ = ctrl_c.await;
}
