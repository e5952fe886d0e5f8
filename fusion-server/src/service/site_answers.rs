//! The site's queryables, `fusion/<site>/tracks` and `fusion/<site>/status`: declared while this
//! server is active, withdrawn while it stands by, so that a query is answered by the server
//! that publishes and by it alone.

use std::sync::{Arc, Mutex};

use protocol::{keys, ServerRole, Site};
use tokio::sync::watch;
use zenoh::query::Queryable;

use super::status_queryable;
use crate::engine_thread::Snapshot;
use crate::track_output::{self, SharedHistory};

/// What the site's queryables answer from.
pub struct Sources {
    /// The engine's latest tracks and status.
    pub snapshot: Arc<Mutex<Snapshot>>,
    /// The published track sets, for `_time` queries.
    pub history: SharedHistory,
}

/// Starts the task that follows `role`; aborting it withdraws the queryables.
pub fn spawn(
    session: &zenoh::Session,
    site: &Site,
    sources: Sources,
    mut role: watch::Receiver<ServerRole>,
) -> tokio::task::JoinHandle<()> {
    let (session, site) = (session.clone(), site.clone());
    tokio::spawn(async move {
        loop {
            let active = *role.borrow_and_update() == ServerRole::Active;
            let _answering = if active {
                declare(&session, &site, &sources, &role).await
            } else {
                None
            };
            if role.changed().await.is_err() {
                return;
            }
        }
    })
}

async fn declare(
    session: &zenoh::Session,
    site: &Site,
    sources: &Sources,
    role: &watch::Receiver<ServerRole>,
) -> Option<(Queryable<()>, Queryable<()>)> {
    let declared = async {
        let tracks = track_output::declare_tracks_queryable(
            session,
            site,
            sources.snapshot.clone(),
            sources.history.clone(),
        )
        .await?;
        let status = status_queryable::declare(
            session,
            keys::status_key(site),
            sources.snapshot.clone(),
            role.clone(),
        )
        .await?;
        anyhow::Ok((tracks, status))
    };
    match declared.await {
        Ok(queryables) => Some(queryables),
        Err(e) => {
            tracing::error!(error = %e, "the site's queryables could not be declared");
            None
        }
    }
}
