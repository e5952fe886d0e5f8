//! Everything an agent does on Zenoh: the session, and per sensor the liveliness token, the descriptor (put at
//! start, put again every few seconds, and answered to queries) and the measurement-set publisher.
//!
//! Sets, descriptors and truth are published with `CongestionControl::Block`: under a burst (a replay at high
//! speed, a slow link) the agent waits rather than letting Zenoh drop sets silently — a lost set must show up
//! as a `seq` gap, never vanish. A failed put never stops the agent: it is logged (rate-limited) and the
//! next frame is published as usual; in client mode Zenoh reconnects by itself when the router returns.

use std::sync::{Arc, RwLock};
use std::time::Duration;

use protocol::{keys, MeasurementSet, SensorDescriptor, Site, TruthSet, WireFormat};
use serde::Serialize;
use tokio::sync::watch;
use transport::ZenohConfig;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::Publisher;
use zenoh::qos::CongestionControl;
use zenoh::query::{Query, Queryable};
use zenoh::{Session, Wait};

use crate::error::AgentError;
use transport::LogLimiter;
use transport::Shutdown;

/// How often a descriptor is put again, so that a server that restarted learns it without asking.
pub const DESCRIPTOR_REFRESH: Duration = Duration::from_secs(3);

/// At most one warning per this interval for repeated put failures of one publisher.
const FAILURE_LOG_INTERVAL: Duration = Duration::from_secs(5);

/// How often [`await_subscribers`] looks again.
const SUBSCRIBER_POLL: Duration = Duration::from_millis(20);

/// How long the last puts are given to leave the queues before the session closes.
const LINGER: Duration = Duration::from_millis(100);

/// An open Zenoh session and the payload form this agent publishes in.
pub struct Publishing {
    session: Session,
    format: WireFormat,
}

impl Publishing {
    /// Opens the session. A client whose router is unreachable keeps trying (with a growing pause, logged)
    /// until it succeeds or shutdown is requested, then returns `None`; configuration errors fail at once.
    pub async fn open(
        zenoh: &ZenohConfig,
        format: WireFormat,
        shutdown: &Shutdown,
    ) -> Result<Option<Self>, AgentError> {
        let mut stop = shutdown.clone();
        let Some(session) = zenoh.open_retrying(stop.requested()).await? else {
            return Ok(None);
        };
        tracing::info!(mode = %zenoh.mode, connect = ?zenoh.connect, listen = ?zenoh.listen, "zenoh session open");
        Ok(Some(Self { session, format }))
    }

    /// Declares everything one sensor needs, in this order: descriptor queryable, descriptor put (now and every
    /// [`DESCRIPTOR_REFRESH`]), measurement-set publisher, liveliness token. The descriptor must be valid.
    pub async fn sensor(
        &self,
        descriptor: &SensorDescriptor,
    ) -> Result<SensorPublisher, AgentError> {
        let (site, sensor) = (&descriptor.site, &descriptor.sensor);
        let descriptor_key = keys::descriptor_key(site, sensor);
        let forms = Arc::new(RwLock::new(DescriptorForms::new(descriptor)?));
        let queryable = self
            .declare_descriptor_queryable(&descriptor_key, Arc::clone(&forms))
            .await?;
        let mut descriptor_publisher = TypedPublisher::declare(
            &self.session,
            descriptor_key.clone(),
            self.format,
            "descriptor",
        )
        .await?;
        // The first put is awaited so that the descriptor precedes the first set.
        descriptor_publisher.put(descriptor).await;
        let (current, mut changed) = watch::channel(descriptor.clone());
        let refresh = tokio::spawn(async move {
            loop {
                // A changed descriptor is put at once, and then again every DESCRIPTOR_REFRESH.
                if let Ok(Err(_)) =
                    tokio::time::timeout(DESCRIPTOR_REFRESH, changed.changed()).await
                {
                    break; // the sensor was withdrawn
                }
                let descriptor = changed.borrow_and_update().clone();
                descriptor_publisher.put(&descriptor).await;
            }
        });
        let sets = TypedPublisher::declare(
            &self.session,
            keys::measurements_key(site, sensor),
            self.format,
            "measurement set",
        )
        .await?;
        // The token comes last: whoever sees the sensor come alive can query its descriptor at once.
        let alive_key = keys::alive_key(site, sensor);
        let token = self
            .session
            .liveliness()
            .declare_token(alive_key.clone())
            .await
            .map_err(|e| declare_error(&format!("liveliness token {alive_key}"), e))?;
        tracing::info!(sensor = %sensor, kind = descriptor.model.kind_name(), key = %descriptor_key, "sensor announced");
        Ok(SensorPublisher {
            sets,
            current,
            forms,
            _token: token,
            _queryable: queryable,
            refresh,
        })
    }

    /// The publisher of `fusion/<site>/truth`.
    pub async fn truth(&self, site: &Site) -> Result<TruthPublisher, AgentError> {
        let publisher = TypedPublisher::declare(
            &self.session,
            keys::truth_key(site),
            self.format,
            "truth set",
        )
        .await?;
        Ok(TruthPublisher { publisher })
    }

    /// Gives the last puts a moment to leave, then closes the session (undeclaring everything left).
    pub async fn close(self) {
        tokio::time::sleep(LINGER).await;
        if let Err(e) = self.session.close().await {
            tracing::warn!(error = %e, "closing the zenoh session failed");
        }
    }

    /// Declares the queryable answering `descriptor_key` with the descriptor in the form the query asks for.
    async fn declare_descriptor_queryable(
        &self,
        descriptor_key: &str,
        forms: Arc<RwLock<DescriptorForms>>,
    ) -> Result<Queryable<()>, AgentError> {
        let reply_key = descriptor_key.to_owned();
        self.session
            .declare_queryable(descriptor_key.to_owned())
            .callback(move |query| match forms.read() {
                Ok(forms) => forms.answer(&query, &reply_key),
                Err(poisoned) => poisoned.get_ref().answer(&query, &reply_key),
            })
            .await
            .map_err(|e| declare_error(&format!("queryable {descriptor_key}"), e))
    }
}

/// What one sensor holds on Zenoh for as long as it runs; dropping it withdraws the sensor.
pub struct SensorPublisher {
    sets: TypedPublisher,
    /// The descriptor the refresh task puts.
    current: watch::Sender<SensorDescriptor>,
    /// The descriptor in both forms, as the queryable answers it.
    forms: Arc<RwLock<DescriptorForms>>,
    /// Held, not used: dropping it undeclares the token and tells the server the sensor left.
    _token: LivelinessToken,
    /// Held, not used: answers descriptor queries from Zenoh's threads.
    _queryable: Queryable<()>,
    /// The task putting the descriptor again every [`DESCRIPTOR_REFRESH`].
    refresh: tokio::task::JoinHandle<()>,
}

impl SensorPublisher {
    /// Publishes one set; a failure is logged (rate-limited), never returned.
    pub async fn put_set(&mut self, set: &MeasurementSet) {
        self.sets.put(set).await;
    }

    /// Announces a changed descriptor (the same sensor, refined figures): the queryable answers with it at
    /// once and it is put now and on every refresh. The descriptor must be valid.
    pub fn update_descriptor(&mut self, descriptor: &SensorDescriptor) -> Result<(), AgentError> {
        let forms = DescriptorForms::new(descriptor)?;
        match self.forms.write() {
            Ok(mut current) => *current = forms,
            Err(poisoned) => *poisoned.into_inner() = forms,
        }
        self.current.send_replace(descriptor.clone());
        Ok(())
    }

    /// Whether Zenoh knows a subscriber for this sensor's sets (a session drops puts nobody subscribes to).
    pub async fn has_subscribers(&self) -> bool {
        self.sets
            .publisher
            .matching_status()
            .await
            .map(|status| status.matching())
            .unwrap_or(false)
    }
}

/// Waits until every publisher has a subscriber, or `patience` has passed (returning false).
///
/// Right after a session opens, the routes to existing subscribers are still being learned and puts made
/// then are dropped; a short wait at start keeps the first sets from vanishing when a server is already
/// listening, and costs only `patience` when none is.
pub async fn await_subscribers(publishers: &[&SensorPublisher], patience: Duration) -> bool {
    let deadline = tokio::time::Instant::now() + patience;
    for publisher in publishers {
        while !publisher.has_subscribers().await {
            if tokio::time::Instant::now() >= deadline {
                return false;
            }
            tokio::time::sleep(SUBSCRIBER_POLL).await;
        }
    }
    true
}

impl Drop for SensorPublisher {
    fn drop(&mut self) {
        self.refresh.abort();
    }
}

/// The truth publisher of a simulating agent.
pub struct TruthPublisher {
    publisher: TypedPublisher,
}

impl TruthPublisher {
    /// Publishes one truth set; a failure is logged (rate-limited), never returned.
    pub async fn put_truth(&mut self, truth: &TruthSet) {
        self.publisher.put(truth).await;
    }
}

/// A publisher of one message type on one key, in one wire form, that logs its failures rate-limited.
struct TypedPublisher {
    publisher: Publisher<'static>,
    format: WireFormat,
    /// What is published, for log messages.
    what: &'static str,
    failures: LogLimiter,
}

impl TypedPublisher {
    /// Declares the publisher on `key`, with the encoding of `format` and congestion control `Block`.
    async fn declare(
        session: &Session,
        key: String,
        format: WireFormat,
        what: &'static str,
    ) -> Result<Self, AgentError> {
        let publisher = session
            .declare_publisher(key.clone())
            .encoding(format.to_zenoh())
            .congestion_control(CongestionControl::Block)
            .await
            .map_err(|e| declare_error(&format!("{what} publisher {key}"), e))?;
        Ok(Self {
            publisher,
            format,
            what,
            failures: LogLimiter::new(FAILURE_LOG_INTERVAL),
        })
    }

    /// Encodes and puts `message`; a failure is logged (rate-limited), never returned.
    async fn put<T: Serialize>(&mut self, message: &T) {
        let result = match protocol::encode(message, self.format) {
            Ok(bytes) => self.publisher.put(bytes).await.map_err(|e| e.to_string()),
            Err(e) => Err(format!("encoding failed: {e}")),
        };
        if let Err(error) = result {
            if let Some(suppressed) = self.failures.allow("put") {
                let key = self.publisher.key_expr();
                tracing::warn!(what = self.what, %key, %error, suppressed, "put failed; going on");
            }
        }
    }
}

/// A descriptor encoded once in both wire forms, for the queryable.
struct DescriptorForms {
    json: Vec<u8>,
    postcard: Vec<u8>,
}

impl DescriptorForms {
    /// Encodes `descriptor` in both forms.
    fn new(descriptor: &SensorDescriptor) -> Result<Self, AgentError> {
        let invalid = |source| AgentError::InvalidDescriptor {
            sensor: descriptor.sensor.to_string(),
            source,
        };
        Ok(Self {
            json: protocol::encode(descriptor, WireFormat::Json).map_err(invalid)?,
            postcard: protocol::encode(descriptor, WireFormat::Postcard).map_err(invalid)?,
        })
    }

    /// Replies to one query (on a Zenoh thread: nothing here blocks beyond handing the reply over).
    fn answer(&self, query: &Query, reply_key: &str) {
        let result = match WireFormat::from_query_parameters(query.parameters().as_str()) {
            Ok(format) => {
                let bytes = match format {
                    WireFormat::Json => self.json.clone(),
                    WireFormat::Postcard => self.postcard.clone(),
                };
                query
                    .reply(reply_key.to_owned(), bytes)
                    .encoding(format.to_zenoh())
                    .wait()
            }
            Err(e) => query.reply_err(e.to_string()).wait(),
        };
        if let Err(e) = result {
            tracing::debug!(error = %e, key = reply_key, "descriptor reply failed");
        }
    }
}

/// The error for a declaration Zenoh refused.
fn declare_error(what: &str, error: zenoh::Error) -> AgentError {
    AgentError::Declare {
        what: what.to_owned(),
        reason: error.to_string(),
    }
}
