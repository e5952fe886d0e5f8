//! The filter state passed from the active server to its standbys: each server answers
//! `fusion/<site>/server/<instance>/checkpoint` with its current state (the engine thread makes
//! it on demand), and a standby takes the active server's state when it starts (rather than its
//! own checkpoint, older by however long it was away), when it stands down after a split brain
//! (it filtered on its own while it was active), and every `server.standby_sync_s` seconds. In
//! between, the same sets carry both in step; the syncs bound how long anything one of them saw
//! differently (a set the other missed, a late set handled at another moment) can part their
//! labels.

use std::time::Duration;

use protocol::{keys, InstanceId, ServerRole, Site};
use tokio::sync::{oneshot, watch};
use zenoh::bytes::Encoding;
use zenoh::query::{Query, Queryable};

use super::inlet::Inlet;
use crate::checkpoint::Checkpoint;
use crate::engine_thread::Inbound;

/// How long a checkpoint query (and the engine's answer to one) may take.
const HANDOVER_TIMEOUT: Duration = Duration::from_secs(3);

/// Declares the queryable that answers with this server's current filter state in JSON.
pub async fn declare(
    session: &zenoh::Session,
    site: &Site,
    me: &InstanceId,
    inlet: &Inlet,
) -> anyhow::Result<Queryable<()>> {
    let key = keys::server_checkpoint_key(site, me);
    let inlet = inlet.clone();
    let runtime = tokio::runtime::Handle::current();
    session
        .declare_queryable(key.clone())
        .callback(move |query| {
            // The engine answers on its own thread: wait for it off Zenoh's threads.
            let (tx, rx) = oneshot::channel();
            inlet.offer(Inbound::Checkpoint(tx));
            runtime.spawn(reply(query, rx));
        })
        .await
        .map_err(|e| anyhow::anyhow!("declaring the queryable on {key}: {e}"))
}

async fn reply(query: Query, state: oneshot::Receiver<Checkpoint>) {
    let answer = match tokio::time::timeout(HANDOVER_TIMEOUT, state).await {
        Ok(Ok(checkpoint)) => serde_json::to_vec(&checkpoint).map_err(|e| e.to_string()),
        Ok(Err(_)) => Err("the engine is shutting down".to_string()),
        Err(_) => Err("the engine did not answer in time".to_string()),
    };
    let sent = match answer {
        Ok(bytes) => {
            query
                .reply(query.key_expr().clone(), bytes)
                .encoding(Encoding::APPLICATION_JSON)
                .await
        }
        Err(reason) => query.reply_err(reason).await,
    };
    if let Err(e) = sent {
        tracing::debug!(error = %e, "checkpoint reply failed");
    }
}

/// The current filter state of the active server `from`, or `None` (logged) when it does not
/// answer usably.
async fn fetch(session: &zenoh::Session, site: &Site, from: &InstanceId) -> Option<Checkpoint> {
    let key = keys::server_checkpoint_key(site, from);
    let replies = match session.get(&key).timeout(HANDOVER_TIMEOUT).await {
        Ok(replies) => replies,
        Err(e) => {
            tracing::warn!(%key, error = %e, "asking the active server for its state failed");
            return None;
        }
    };
    while let Ok(reply) = replies.recv_async().await {
        match reply.result() {
            Ok(sample) => {
                match serde_json::from_slice::<Checkpoint>(&sample.payload().to_bytes()) {
                    Ok(checkpoint) if checkpoint.site == site.as_str() => return Some(checkpoint),
                    Ok(checkpoint) => {
                        tracing::warn!(%key, site = checkpoint.site, "the active server's state is for another site")
                    }
                    Err(e) => {
                        tracing::warn!(%key, error = %e, "the active server's state is unreadable")
                    }
                }
            }
            Err(e) => tracing::warn!(%key, error = ?e, "the active server refused its state"),
        }
    }
    tracing::warn!(%key, "no usable state from the active server");
    None
}

/// Starts the task that keeps a standby on the active server's state; aborting it stops that.
pub fn spawn_standby_sync(
    session: &zenoh::Session,
    site: &Site,
    inlet: &Inlet,
    mut role: watch::Receiver<ServerRole>,
    every: Duration,
) -> tokio::task::JoinHandle<()> {
    let (session, site, inlet) = (session.clone(), site.clone(), inlet.clone());
    tokio::spawn(async move {
        let mut synced_once = false;
        loop {
            if *role.borrow_and_update() == ServerRole::Standby {
                if let Some((from, checkpoint)) = active_state(&session, &site).await {
                    if synced_once {
                        tracing::debug!(%from, "took the active server's filter state");
                    } else {
                        tracing::info!(%from, "standing by from the active server's filter state");
                    }
                    synced_once = true;
                    inlet.offer(Inbound::Restore(Box::new(checkpoint)));
                }
            }
            tokio::select! {
                _ = tokio::time::sleep(every) => {}
                changed = role.changed() => if changed.is_err() { return },
            }
        }
    })
}

/// The state of the site's active server, with its instance id.
async fn active_state(session: &zenoh::Session, site: &Site) -> Option<(InstanceId, Checkpoint)> {
    for active in super::election::probe(session, site).await {
        if let Some(checkpoint) = fetch(session, site, &active).await {
            return Some((active, checkpoint));
        }
    }
    None
}
