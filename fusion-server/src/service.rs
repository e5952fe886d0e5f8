//! The live service: Zenoh wiring around the [`Engine`].
//!
//! Zenoh callbacks only decode the key and the encoding and hand the payload to a bounded
//! channel (`service/inlet.rs`; overflow is counted); the engine runs on its own thread, so slow
//! clients never stall ingest; queryables answer from a snapshot the engine refreshes; a
//! publisher task puts the latest `TrackSet` as soon as there is one (at most
//! `output.max_publish_hz` times per second; `publisher.rs`, followed by its JSON copy and its
//! place in the history that `_time` queries on the tracks queryable read, `track_output.rs`).
//! One file per concern: `subscribers.rs`, `descriptor_fetch.rs`, `status_queryable.rs`;
//! with `[server] role = "auto"`, `election.rs` decides whether this server is the site's
//! active one (`role.rs` holds the rules): a standby filters the same sets without publishing
//! or answering the site's queries (`site_answers.rs`) and keeps taking the active server's state
//! (`handover.rs`); the signals that stop it are `transport::shutdown`'s.

mod descriptor_fetch;
mod election;
mod handover;
mod inlet;
mod site_answers;
mod status_queryable;
mod subscribers;

use std::sync::atomic::AtomicU64;
use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use protocol::{keys, InstanceId, SensorId, Site};
use tokio::sync::mpsc;
use transport::wait_for_signal;
use zenoh::query::Queryable;

use crate::clock;
use crate::config::ServerConfig;
use crate::engine::Engine;
use crate::engine_thread::{engine_loop, restore_checkpoint, Inbound, Snapshot};
use crate::publisher::{self, Outbox};
use crate::track_output::{self, TrackCopies};
use election::Elected;
use inlet::Inlet;
use subscribers::Subscribers;

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
    let inlet = Inlet::new(tx, overflow.clone());
    // Subscribed first: what arrives while the election runs waits in the channel.
    let subscribers = Subscribers::declare(&session, &site, &inlet).await?;
    let elected = election::start(&session, &site, &config.server).await?;
    let snapshot = Arc::new(Mutex::new(Snapshot {
        tracks: engine.tracks().clone(),
        status: engine.status(started),
    }));
    let history = track_output::new_history(&config.output);
    let me = config.server.instance();
    let sources = site_answers::Sources {
        snapshot: snapshot.clone(),
        history: history.clone(),
    };
    let answers = Answers::declare(&session, (&site, &me), &elected, &inlet, sources).await?;
    let standby_sync = handover::spawn_standby_sync(
        &session,
        &site,
        &inlet,
        elected.role.clone(),
        Duration::from_secs_f64(config.server.standby_sync_s),
    );
    let (ask_tx, ask_rx) = mpsc::unbounded_channel::<SensorId>();
    descriptor_fetch::spawn(&session, &site, &inlet, ask_rx);

    // The publisher: the latest TrackSet as soon as there is one, rate-limited, and in JSON.
    let copies = TrackCopies::declare(&session, &site, &config.output, history).await?;
    let (outbox, publisher_task) = publisher::start(
        &session,
        &site,
        config.output.max_publish_hz,
        engine.latency(),
        copies,
        elected.role.clone(),
    )
    .await?;
    let engine_thread = spawn_engine(engine, &config, rx, snapshot, overflow, outbox, ask_tx)?;

    wait_for_signal().await;
    tracing::info!("shutting down: draining what was received");
    // The callbacks go first so nothing new arrives; then the engine drains and checkpoints.
    drop(subscribers);
    inlet.shut_down();
    join_engine(engine_thread).await?;
    // Let the publisher put the final track set before closing.
    tokio::time::sleep(Duration::from_millis(50)).await;
    publisher_task.abort();
    standby_sync.abort();
    drop(answers);
    drop(elected);
    close(session, &site).await
}

/// What the server answers: the site's queryables while active, its own status and state always.
struct Answers {
    site: tokio::task::JoinHandle<()>,
    _own_status: Queryable<()>,
    _handover: Queryable<()>,
}

impl Answers {
    async fn declare(
        session: &zenoh::Session,
        (site, me): (&Site, &InstanceId),
        elected: &Elected,
        inlet: &Inlet,
        sources: site_answers::Sources,
    ) -> anyhow::Result<Self> {
        let own_status = status_queryable::declare(
            session,
            keys::server_status_key(site, me),
            sources.snapshot.clone(),
            elected.role.clone(),
        )
        .await?;
        Ok(Self {
            site: site_answers::spawn(session, site, sources, elected.role.clone()),
            _own_status: own_status,
            _handover: handover::declare(session, site, me, inlet).await?,
        })
    }
}

impl Drop for Answers {
    fn drop(&mut self) {
        self.site.abort();
    }
}

/// Starts the engine thread.
fn spawn_engine(
    engine: Engine,
    config: &ServerConfig,
    rx: Receiver<Inbound>,
    snapshot: Arc<Mutex<Snapshot>>,
    overflow: Arc<AtomicU64>,
    outbox: Outbox,
    ask_tx: mpsc::UnboundedSender<SensorId>,
) -> anyhow::Result<JoinHandle<()>> {
    let config = config.clone();
    Ok(std::thread::Builder::new()
        .name("fusion-engine".into())
        .spawn(move || engine_loop(engine, config, rx, snapshot, overflow, outbox, ask_tx))?)
}

/// Waits for the engine thread to drain and checkpoint.
async fn join_engine(engine_thread: JoinHandle<()>) -> anyhow::Result<()> {
    let joined = tokio::task::spawn_blocking(move || engine_thread.join())
        .await
        .map_err(|e| anyhow::anyhow!("engine thread: {e}"))?;
    if joined.is_err() {
        anyhow::bail!("the engine thread panicked");
    }
    Ok(())
}

async fn close(session: zenoh::Session, site: &Site) -> anyhow::Result<()> {
    session
        .close()
        .await
        .map_err(|e| anyhow::anyhow!("closing the zenoh session: {e}"))?;
    tracing::info!(site = %site, "stopped");
    Ok(())
}
