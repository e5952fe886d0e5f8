//! The status queryables (the site's, while active, and the server's own): answer from the
//! snapshot the engine refreshes, with the server's current role, in the encoding the query
//! asks for.

use std::sync::{Arc, Mutex};

use protocol::{ServerRole, Status, WireFormat};
use tokio::sync::watch;
use zenoh::bytes::Encoding;
use zenoh::query::{Query, Queryable};
use zenoh::Wait;

use crate::engine_thread::Snapshot;

/// Declares the queryable on `key`.
pub async fn declare(
    session: &zenoh::Session,
    key: String,
    snapshot: Arc<Mutex<Snapshot>>,
    role: watch::Receiver<ServerRole>,
) -> anyhow::Result<Queryable<()>> {
    let reply_key = key.clone();
    session
        .declare_queryable(key.clone())
        .callback(move |query| answer(&query, &reply_key, &snapshot, *role.borrow()))
        .await
        .map_err(|e| anyhow::anyhow!("declaring the queryable on {key}: {e}"))
}

fn answer(query: &Query, reply_key: &str, snapshot: &Mutex<Snapshot>, role: ServerRole) {
    let format = match WireFormat::from_query_parameters(query.parameters().as_str()) {
        Ok(format) => format,
        Err(e) => {
            let _ = query.reply_err(e.to_string()).wait();
            return;
        }
    };
    let status = Status {
        role,
        ..snapshot
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .status
            .clone()
    };
    match protocol::encode(&status, format) {
        Ok(bytes) => {
            if let Err(e) = query
                .reply(reply_key, bytes)
                .encoding(Encoding::from(format.encoding_str()))
                .wait()
            {
                tracing::debug!(error = %e, "reply failed");
            }
        }
        Err(e) => tracing::error!(error = %e, "encoding a reply failed"),
    }
}
