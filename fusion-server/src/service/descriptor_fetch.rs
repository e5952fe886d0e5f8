//! Asking for descriptors: every one already out there at start, then that of each sensor whose
//! sets arrive before its descriptor (the engine asks through a channel).

use std::time::Duration;

use protocol::{keys, SensorId, Site};
use tokio::sync::mpsc::UnboundedReceiver;

use super::inlet::{wire_format, Inlet};
use crate::engine_thread::Inbound;

/// How long one descriptor query waits for replies.
const QUERY_TIMEOUT: Duration = Duration::from_secs(2);

/// Starts the task that fetches descriptors for `site` into the engine.
pub fn spawn(
    session: &zenoh::Session,
    site: &Site,
    inlet: &Inlet,
    mut asked: UnboundedReceiver<SensorId>,
) {
    let (session, site, inlet) = (session.clone(), site.clone(), inlet.clone());
    tokio::spawn(async move {
        fetch(&session, &keys::all_descriptors_key(&site), &inlet).await;
        while let Some(sensor) = asked.recv().await {
            fetch(&session, &keys::descriptor_key(&site, &sensor), &inlet).await;
        }
    });
}

async fn fetch(session: &zenoh::Session, selector: &str, inlet: &Inlet) {
    let replies = match session.get(selector).timeout(QUERY_TIMEOUT).await {
        Ok(replies) => replies,
        Err(e) => {
            tracing::warn!(selector, error = %e, "asking for descriptors failed");
            return;
        }
    };
    while let Ok(reply) = replies.recv_async().await {
        if let Ok(sample) = reply.result() {
            inlet.offer(Inbound::Descriptor {
                payload: sample.payload().to_bytes().into_owned(),
                format: wire_format(sample.encoding()),
            });
        }
    }
}
