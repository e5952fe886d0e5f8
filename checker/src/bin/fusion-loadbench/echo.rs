//! The bare Zenoh round trip the service's latency is compared with: a second session echoes
//! every payload back, over the same router-less loopback link, at the same rate.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use transport::ZenohConfig;
use zenoh::pubsub::Publisher;
use zenoh::sample::Sample;

const ECHO_KEY: &str = "fusion-loadbench/echo";
const BACK_KEY: &str = "fusion-loadbench/back";

/// An echo session and the client's side of it.
pub struct Echo {
    _echo_session: zenoh::Session,
    out: Publisher<'static>,
    /// When each numbered payload came back.
    back: Arc<Mutex<HashMap<u64, Instant>>>,
}

impl Echo {
    /// Opens the echo session on `endpoint` and subscribes `client` to the echoed payloads.
    pub async fn start(client: &zenoh::Session, endpoint: &str) -> anyhow::Result<Self> {
        let echo_session = ZenohConfig {
            connect: vec![endpoint.to_string()],
            ..ZenohConfig::default()
        }
        .open()
        .await?;
        let back_pub = echo_session
            .declare_publisher(BACK_KEY)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        echo_session
            .declare_subscriber(ECHO_KEY)
            .callback(move |sample: Sample| {
                use zenoh::Wait;
                let _ = back_pub.put(sample.payload().clone()).wait();
            })
            .background()
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let back: Arc<Mutex<HashMap<u64, Instant>>> = Arc::default();
        let sink = back.clone();
        client
            .declare_subscriber(BACK_KEY)
            .callback(move |sample: Sample| {
                let at = Instant::now();
                let bytes = sample.payload().to_bytes();
                if let Some(id) = bytes.get(..8) {
                    let id = u64::from_le_bytes(id.try_into().expect("8 bytes"));
                    sink.lock().unwrap().insert(id, at);
                }
            })
            .background()
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let out = client
            .declare_publisher(ECHO_KEY)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        tokio::time::sleep(std::time::Duration::from_millis(300)).await;
        Ok(Self {
            _echo_session: echo_session,
            out,
            back,
        })
    }

    /// Sends payload number `id` (prefixed to `payload`); returns when it was put.
    pub async fn send(&self, id: u64, payload: &[u8]) -> anyhow::Result<Instant> {
        let mut bytes = id.to_le_bytes().to_vec();
        bytes.extend_from_slice(payload);
        let at = Instant::now();
        self.out
            .put(bytes)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(at)
    }

    /// When payload `id` came back.
    pub fn returned(&self, id: u64) -> Option<Instant> {
        self.back.lock().unwrap().get(&id).copied()
    }
}
