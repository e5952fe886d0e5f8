//! The election of `role.rs` over Zenoh: the active server's liveliness token, a liveliness
//! subscriber on every server's token, and a watch channel that tells the rest of the service
//! which role this server has now.

use std::time::Duration;

use protocol::{keys, InstanceId, ServerRole, Site};
use tokio::sync::{mpsc, watch};
use zenoh::liveliness::LivelinessToken;
use zenoh::sample::SampleKind;

use crate::config::ServerRoleConfig;
use crate::role::Election;

/// How long the first look for an active server waits for the router's answer.
const PROBE_TIMEOUT: Duration = Duration::from_secs(2);

/// The running election.
pub struct Elected {
    /// This server's role, updated as the election goes.
    pub role: watch::Receiver<ServerRole>,
    task: tokio::task::JoinHandle<()>,
}

impl Drop for Elected {
    fn drop(&mut self) {
        // The task holds the token: aborting it withdraws the token.
        self.task.abort();
    }
}

/// A token appeared (`true`) or went away.
type TokenEvent = (InstanceId, bool);

/// Looks for the site's active servers, takes the role that follows and keeps watching.
pub async fn start(
    session: &zenoh::Session,
    site: &Site,
    config: &ServerRoleConfig,
) -> anyhow::Result<Elected> {
    let mut election = Election::new(config.instance(), config.role);
    let (events_tx, events) = mpsc::unbounded_channel::<TokenEvent>();
    // Subscribed before the probe, so that nothing between the two is missed.
    let subscriber = session
        .liveliness()
        .declare_subscriber(keys::all_server_active_tokens(site))
        .callback(move |sample| {
            if let Ok((_, who)) = keys::parse_server_active_token(sample.key_expr().as_str()) {
                let _ = events_tx.send((who, sample.kind() == SampleKind::Put));
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing to the servers' active tokens: {e}"))?;
    let actives_at_start = probe(session, site).await;
    for who in &actives_at_start {
        election.token_appeared(who.clone());
    }
    let role = election.decide();
    let token = hold_token_if_active(session, site, &election, None).await;
    tracing::info!(
        instance = %election.me(),
        %role,
        others_active = ?actives_at_start,
        "server role at start"
    );
    let (role_tx, role_rx) = watch::channel(role);
    let session = session.clone();
    let site = site.clone();
    let task = tokio::spawn(async move {
        let _subscriber = subscriber;
        watch_tokens(&session, &site, election, events, token, role_tx).await;
    });
    Ok(Elected {
        role: role_rx,
        task,
    })
}

/// The active servers' tokens held now, as the router knows them.
pub async fn probe(session: &zenoh::Session, site: &Site) -> Vec<InstanceId> {
    let key = keys::all_server_active_tokens(site);
    let replies = match session.liveliness().get(&key).timeout(PROBE_TIMEOUT).await {
        Ok(replies) => replies,
        Err(e) => {
            tracing::warn!(%key, error = %e, "looking for an active server failed");
            return Vec::new();
        }
    };
    let mut found = Vec::new();
    while let Ok(reply) = replies.recv_async().await {
        if let Ok(sample) = reply.result() {
            if let Ok((_, who)) = keys::parse_server_active_token(sample.key_expr().as_str()) {
                found.push(who);
            }
        }
    }
    found.sort();
    found.dedup();
    found
}

/// Follows the tokens until the session closes: each change of role is applied (token held or
/// dropped) and sent to the service.
async fn watch_tokens(
    session: &zenoh::Session,
    site: &Site,
    mut election: Election,
    mut events: mpsc::UnboundedReceiver<TokenEvent>,
    mut token: Option<LivelinessToken>,
    role_tx: watch::Sender<ServerRole>,
) {
    let mut warned_split = false;
    while let Some((who, appeared)) = events.recv().await {
        let before = election.role();
        let after = if appeared {
            election.token_appeared(who.clone())
        } else {
            election.token_vanished(&who)
        };
        if after != before {
            log_change(&election, &who, appeared);
            token = hold_token_if_active(session, site, &election, token).await;
            role_tx.send_replace(after);
        }
        if election.split_brain() != warned_split {
            warned_split = election.split_brain();
            if warned_split {
                let others: Vec<&InstanceId> = election.other_actives().collect();
                tracing::warn!(?others, "another server of this site is active too and this one does not yield to it (both role = \"active\"?)");
            }
        }
    }
}

fn log_change(election: &Election, who: &InstanceId, appeared: bool) {
    match election.role() {
        ServerRole::Active => tracing::warn!(
            instance = %election.me(),
            previous = %who,
            "taking over as the active server: no other server of the site is active"
        ),
        ServerRole::Standby => tracing::warn!(
            instance = %election.me(),
            other = %who,
            appeared,
            "standing down to standby: another active server has the smaller instance id"
        ),
    }
}

/// Holds the token while active, drops it while standby (`current` is the one held now).
async fn hold_token_if_active(
    session: &zenoh::Session,
    site: &Site,
    election: &Election,
    current: Option<LivelinessToken>,
) -> Option<LivelinessToken> {
    match (election.role(), current) {
        (ServerRole::Active, Some(token)) => Some(token),
        (ServerRole::Active, None) => {
            let key = keys::server_active_token(site, election.me());
            match session.liveliness().declare_token(&key).await {
                Ok(token) => Some(token),
                Err(e) => {
                    tracing::error!(%key, error = %e, "declaring the active token failed: a standby may take over as well");
                    None
                }
            }
        }
        (ServerRole::Standby, _) => None,
    }
}
