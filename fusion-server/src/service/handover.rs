//! The filter state passed from the active server to a standby that joins later: each server
//! answers `fusion/<site>/server/<instance>/checkpoint` with its current state (the engine thread
//! makes it on demand), and a standby that finds an active server at start begins from its
//! state rather than from its own checkpoint, which is older by however long it was away. The
//! sets it then receives carry it on in step with the active server, so their labels agree.

use std::time::Duration;

use protocol::{keys, InstanceId, Site};
use tokio::sync::oneshot;
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
pub async fn fetch(session: &zenoh::Session, site: &Site, from: &InstanceId) -> Option<Checkpoint> {
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
