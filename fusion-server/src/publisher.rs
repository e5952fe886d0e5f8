//! The tracks publisher: puts the latest `TrackSet` as soon as the engine has one, at most
//! `output.max_publish_hz` times per second, and records each set's latency at that moment.
//! A standby puts nothing but keeps the history, so that it has one when it takes over.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use protocol::{keys, ServerRole, Site, TrackSet, WireFormat};
use tokio::sync::{watch, Notify};
use tokio::time::Instant;
use zenoh::bytes::Encoding;
use zenoh::qos::CongestionControl;

use crate::clock;
use crate::latency::SharedLatency;
use crate::track_output::TrackCopies;

/// What the engine thread hands to the publisher: the newest track set and the arrival times
/// of the sets processed since the last put (their latency ends with the next put).
#[derive(Debug, Default)]
struct Pending {
    latest: Option<TrackSet>,
    arrivals: Vec<f64>,
}

/// The engine thread's side of the publisher.
#[derive(Clone)]
pub(crate) struct Outbox {
    pending: Arc<Mutex<Pending>>,
    wake: Arc<Notify>,
}

impl Outbox {
    fn new() -> Self {
        Self {
            pending: Arc::new(Mutex::new(Pending::default())),
            wake: Arc::new(Notify::new()),
        }
    }

    /// Offers the newest track set (replacing one not yet put) and the arrivals it covers.
    pub(crate) fn offer(&self, latest: TrackSet, arrivals: &[f64]) {
        {
            let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
            pending.latest = Some(latest);
            pending.arrivals.extend_from_slice(arrivals);
        }
        self.wake.notify_one();
    }

    fn take(&self) -> Pending {
        std::mem::take(&mut *self.pending.lock().unwrap_or_else(|p| p.into_inner()))
    }
}

/// Declares the publisher on `fusion/<site>/tracks` and starts the task that puts what the
/// returned [`Outbox`] is offered while `role` is active.
pub(crate) async fn start(
    session: &zenoh::Session,
    site: &Site,
    max_publish_hz: f64,
    latency: SharedLatency,
    copies: TrackCopies,
    role: watch::Receiver<ServerRole>,
) -> anyhow::Result<(Outbox, tokio::task::JoinHandle<()>)> {
    let publisher = session
        .declare_publisher(keys::tracks_key(site))
        .encoding(Encoding::from(WireFormat::Postcard.encoding_str()))
        .congestion_control(CongestionControl::Block)
        .await
        .map_err(|e| anyhow::anyhow!("declaring the tracks publisher: {e}"))?;
    let outbox = Outbox::new();
    let period = Duration::from_secs_f64(1.0 / max_publish_hz);
    let task = {
        let outbox = outbox.clone();
        tokio::spawn(async move {
            let mut next_allowed = Instant::now();
            loop {
                outbox.wake.notified().await;
                // Under the rate limit the newest state goes out as soon as it is allowed.
                tokio::time::sleep_until(next_allowed).await;
                let Pending { latest, arrivals } = outbox.take();
                let Some(tracks) = latest else { continue };
                if *role.borrow() == ServerRole::Standby {
                    copies.keep(tracks);
                    continue;
                }
                put(&publisher, &tracks).await;
                latency.record_published(&arrivals, clock::now());
                copies.after_put(&tracks).await;
                next_allowed = Instant::now() + period;
            }
        })
    };
    Ok((outbox, task))
}

async fn put(publisher: &zenoh::pubsub::Publisher<'_>, tracks: &TrackSet) {
    crate::track_output::put(publisher, tracks, WireFormat::Postcard).await;
}
