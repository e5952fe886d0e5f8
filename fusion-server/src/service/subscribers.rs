//! The server's subscriptions: measurement sets, descriptors and the agents' liveliness, each
//! handed to the engine through the [`Inlet`].

use protocol::{keys, SensorKeyKind, Site};
use zenoh::pubsub::Subscriber;
use zenoh::sample::{Sample, SampleKind};

use super::inlet::{wire_format, Inlet};
use crate::clock;
use crate::engine_thread::Inbound;

/// The three subscriptions; dropping them stops the callbacks.
pub struct Subscribers {
    _sets: Subscriber<()>,
    _descriptors: Subscriber<()>,
    _alive: Subscriber<()>,
}

impl Subscribers {
    /// Subscribes to everything `site`'s agents publish.
    pub async fn declare(
        session: &zenoh::Session,
        site: &Site,
        inlet: &Inlet,
    ) -> anyhow::Result<Self> {
        Ok(Self {
            _sets: sets(session, site, inlet.clone()).await?,
            _descriptors: descriptors(session, site, inlet.clone()).await?,
            _alive: alive(session, site, inlet.clone()).await?,
        })
    }
}

async fn sets(
    session: &zenoh::Session,
    site: &Site,
    inlet: Inlet,
) -> anyhow::Result<Subscriber<()>> {
    session
        .declare_subscriber(keys::all_measurements_key(site))
        .callback(move |sample: Sample| {
            let Ok((_, sensor, _)) = keys::parse_sensor_key(sample.key_expr().as_str()) else {
                return;
            };
            inlet.offer(Inbound::Set {
                key_sensor: sensor,
                payload: sample.payload().to_bytes().into_owned(),
                format: wire_format(sample.encoding()),
                arrived: clock::now(),
            });
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing to measurements: {e}"))
}

async fn descriptors(
    session: &zenoh::Session,
    site: &Site,
    inlet: Inlet,
) -> anyhow::Result<Subscriber<()>> {
    session
        .declare_subscriber(keys::all_descriptors_key(site))
        .callback(move |sample: Sample| {
            inlet.offer(Inbound::Descriptor {
                payload: sample.payload().to_bytes().into_owned(),
                format: wire_format(sample.encoding()),
            });
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing to descriptors: {e}"))
}

/// Liveliness of the agents, with history: tokens that already exist are reported too.
async fn alive(
    session: &zenoh::Session,
    site: &Site,
    inlet: Inlet,
) -> anyhow::Result<Subscriber<()>> {
    session
        .liveliness()
        .declare_subscriber(keys::all_alive_key(site))
        .history(true)
        .callback(move |sample: Sample| {
            if let Ok((_, sensor, SensorKeyKind::Alive)) =
                keys::parse_sensor_key(sample.key_expr().as_str())
            {
                let alive = sample.kind() == SampleKind::Put;
                inlet.offer(Inbound::Alive { sensor, alive });
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("subscribing to liveliness: {e}"))
}
