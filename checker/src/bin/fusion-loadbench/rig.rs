//! The server under test and the client that feeds it: a real `fusion-server` on a loopback
//! port, a Zenoh session with one publisher per sensor, and the receipt time of every TrackSet.

use std::collections::HashMap;
use std::process::Command;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use checker::processes::{binary, free_port, Managed};
use protocol::{
    keys, MeasurementSet, SensorDescriptor, SensorId, Site, Status, TrackSet, WireFormat,
};
use transport::ZenohConfig;
use zenoh::bytes::Encoding;
use zenoh::pubsub::Publisher;
use zenoh::qos::CongestionControl;
use zenoh::sample::Sample;

/// One TrackSet as the client received it.
#[derive(Debug, Clone, Copy)]
pub struct Receipt {
    /// When it arrived.
    pub at: Instant,
    /// Its stamp.
    pub stamp: f64,
}

/// A running server with a connected client.
pub struct Rig {
    server: Managed,
    /// The client's session (also used for the bare round trip).
    pub session: zenoh::Session,
    /// The loopback endpoint the server listens on.
    pub endpoint: String,
    site: Site,
    publishers: HashMap<SensorId, Publisher<'static>>,
    /// Every TrackSet received, in order of receipt.
    pub receipts: Arc<Mutex<Vec<Receipt>>>,
}

/// Server settings for the dense scenario's volume; `extra` adds `FUSION__…` overrides.
fn server_command(
    endpoint: &str,
    site: &Site,
    max_components: usize,
    extra: &[(&str, String)],
) -> anyhow::Result<Command> {
    let mut cmd = Command::new(binary("fusion-server")?);
    cmd.arg("run")
        .env("FUSION__ZENOH__LISTEN", endpoint)
        .env("FUSION__SITE__NAME", site.as_str())
        .env("FUSION__SITE__VOLUME_MIN", "0,0,0")
        .env("FUSION__SITE__VOLUME_MAX", "40,40,10")
        .env("FUSION__FILTER__BIRTH_GRID", "8,8,2")
        .env("FUSION__FILTER__MAX_COMPONENTS", max_components.to_string())
        .env("FUSION__LOG__LEVEL", "warn");
    for (key, value) in extra {
        cmd.env(key, value);
    }
    Ok(cmd)
}

impl Rig {
    /// Starts a server for `site` and connects a client that knows `descriptors`.
    pub async fn start(
        site: &Site,
        descriptors: &[SensorDescriptor],
        max_components: usize,
        extra: &[(&str, String)],
        log: &std::path::Path,
    ) -> anyhow::Result<Self> {
        let endpoint = format!("tcp/127.0.0.1:{}", free_port()?);
        let cmd = server_command(&endpoint, site, max_components, extra)?;
        let server = Managed::spawn("fusion-server", cmd, Some(log))?;
        let session = ZenohConfig {
            connect: vec![endpoint.clone()],
            ..ZenohConfig::default()
        }
        .open()
        .await?;
        let receipts: Arc<Mutex<Vec<Receipt>>> = Arc::default();
        let sink = receipts.clone();
        session
            .declare_subscriber(keys::tracks_key(site))
            .callback(move |sample: Sample| {
                let at = Instant::now();
                let bytes = sample.payload().to_bytes();
                if let Ok(set) = protocol::decode::<TrackSet>(&bytes, WireFormat::Postcard) {
                    sink.lock().unwrap().push(Receipt {
                        at,
                        stamp: set.stamp,
                    });
                }
            })
            .background()
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        tokio::time::sleep(Duration::from_millis(800)).await;
        let mut rig = Self {
            server,
            session,
            endpoint,
            site: site.clone(),
            publishers: HashMap::new(),
            receipts,
        };
        rig.announce(descriptors).await?;
        Ok(rig)
    }

    /// Puts the descriptors and declares a publisher per sensor.
    async fn announce(&mut self, descriptors: &[SensorDescriptor]) -> anyhow::Result<()> {
        let postcard = Encoding::from(WireFormat::Postcard.encoding_str());
        for d in descriptors {
            self.session
                .put(
                    keys::descriptor_key(&self.site, &d.sensor),
                    protocol::encode(d, WireFormat::Postcard)?,
                )
                .encoding(postcard.clone())
                .await
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            let publisher = self
                .session
                .declare_publisher(keys::measurements_key(&self.site, &d.sensor))
                .encoding(postcard.clone())
                .congestion_control(CongestionControl::Block)
                .await
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            self.publishers.insert(d.sensor.clone(), publisher);
        }
        tokio::time::sleep(Duration::from_millis(500)).await;
        Ok(())
    }

    /// Publishes one set on its sensor's key; returns when it was put.
    pub async fn put(&self, set: &MeasurementSet) -> anyhow::Result<Instant> {
        let payload = protocol::encode(set, WireFormat::Postcard)?;
        let publisher = self
            .publishers
            .get(&set.sensor)
            .ok_or_else(|| anyhow::anyhow!("no descriptor for {}", set.sensor))?;
        let at = Instant::now();
        publisher
            .put(payload)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(at)
    }

    /// True once a TrackSet stamped at or after `stamp` has been received.
    pub fn has_covered(&self, stamp: f64) -> bool {
        self.receipts
            .lock()
            .unwrap()
            .iter()
            .any(|r| r.stamp >= stamp)
    }

    /// The server's status report.
    pub async fn status(&self) -> anyhow::Result<Status> {
        checker::query_status(&self.session, &self.site, WireFormat::Postcard).await
    }

    /// The server's peak resident memory in KiB (VmHWM), when the platform reports it.
    pub fn peak_memory_kib(&self) -> Option<u64> {
        let pid = self.server.id()?;
        let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
        status
            .lines()
            .find(|l| l.starts_with("VmHWM:"))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse().ok())
    }

    /// Stops the server.
    pub fn stop(mut self) {
        self.server.stop(Duration::from_secs(5));
    }
}
