//! The live service's track output besides the postcard put (`publisher.rs`): the JSON copy on
//! `fusion/<site>/tracks/json` unless `output.json = false`, the history of the published sets
//! (filled by the publisher task right after their puts, so that it holds exactly what
//! subscribers were sent), and the tracks queryable, which answers with the current set or, for
//! a selector with a `_time` range, with one reply per kept set in that range.

use std::sync::{Arc, Mutex};
use std::time::SystemTime;

use protocol::{keys, Site, TrackSet, WireFormat};
use zenoh::bytes::Encoding;
use zenoh::qos::CongestionControl;
use zenoh::query::Query;
use zenoh::Wait;

use crate::config::OutputConfig;
use crate::engine_thread::Snapshot;
use crate::history::{requested_range, TrackHistory};

/// The history shared by the publisher (which fills it) and the queryable (which reads it).
pub(crate) type SharedHistory = Arc<Mutex<TrackHistory>>;

/// The empty history sized by `output.history_s` (and bounded by what `output.max_publish_hz`
/// lets the publisher put in that span).
pub(crate) fn new_history(output: &OutputConfig) -> SharedHistory {
    Arc::new(Mutex::new(TrackHistory::for_publisher(
        output.history_s,
        output.max_publish_hz,
    )))
}

/// What follows each put of the latest track set on `fusion/<site>/tracks`: the same set in
/// JSON on `fusion/<site>/tracks/json` (unless `output.json = false`), then its place in the
/// history.
pub(crate) struct TrackCopies {
    json: Option<zenoh::pubsub::Publisher<'static>>,
    history: SharedHistory,
}

impl TrackCopies {
    /// Declares the JSON publisher when `output.json` asks for it.
    pub(crate) async fn declare(
        session: &zenoh::Session,
        site: &Site,
        output: &OutputConfig,
        history: SharedHistory,
    ) -> anyhow::Result<Self> {
        let json = if output.json {
            // JSON is for outside clients: a slow one drops samples rather than stall the
            // main output.
            let publisher = session
                .declare_publisher(keys::tracks_json_key(site))
                .encoding(Encoding::APPLICATION_JSON)
                .congestion_control(CongestionControl::Drop)
                .await
                .map_err(|e| anyhow::anyhow!("declaring the JSON tracks publisher: {e}"))?;
            Some(publisher)
        } else {
            None
        };
        Ok(Self { json, history })
    }

    /// Puts `tracks` in JSON and keeps it in the history; call after its postcard put. A set
    /// stamped no later than the newest kept (the engine's corrected answer after a late set)
    /// replaces what the history held from its stamp on.
    pub(crate) async fn after_put(&self, tracks: &TrackSet) {
        if let Some(json) = &self.json {
            put(json, tracks, WireFormat::Json).await;
        }
        self.keep(tracks.clone());
    }

    /// Keeps `tracks` in the history without putting it (a standby's sets).
    pub(crate) fn keep(&self, tracks: TrackSet) {
        self.history
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .record(tracks);
    }
}

/// Puts `tracks` in `format` on `publisher`; a failure is logged, never fatal.
pub(crate) async fn put(
    publisher: &zenoh::pubsub::Publisher<'_>,
    tracks: &TrackSet,
    format: WireFormat,
) {
    match protocol::encode(tracks, format) {
        Ok(bytes) => {
            if let Err(e) = publisher.put(bytes).await {
                tracing::warn!(error = %e, ?format, "publishing tracks failed");
            }
        }
        Err(e) => tracing::error!(error = %e, ?format, "encoding tracks failed"),
    }
}

/// Declares the queryable on `fusion/<site>/tracks`: the current set from `snapshot`, or the
/// sets of `history` stamped in the selector's `_time` range (a malformed one gets an error
/// reply), in the `format` asked for.
pub(crate) async fn declare_tracks_queryable(
    session: &zenoh::Session,
    site: &Site,
    snapshot: Arc<Mutex<Snapshot>>,
    history: SharedHistory,
) -> anyhow::Result<zenoh::query::Queryable<()>> {
    let key = keys::tracks_key(site);
    let reply_key = key.clone();
    session
        .declare_queryable(key.clone())
        .callback(move |query| answer(&query, &reply_key, &snapshot, &history))
        .await
        .map_err(|e| anyhow::anyhow!("declaring the queryable on {key}: {e}"))
}

fn answer(
    query: &Query,
    reply_key: &str,
    snapshot: &Mutex<Snapshot>,
    history: &Mutex<TrackHistory>,
) {
    let parameters = query.parameters().as_str();
    let asked = WireFormat::from_query_parameters(parameters)
        .map_err(|e| e.to_string())
        .and_then(|format| Ok((format, requested_range(parameters, SystemTime::now())?)));
    let (format, range) = match asked {
        Ok(asked) => asked,
        Err(e) => {
            tracing::debug!(parameters, error = %e, "tracks query refused");
            if let Err(e) = query.reply_err(e).wait() {
                tracing::debug!(error = %e, "error reply failed");
            }
            return;
        }
    };
    let sets: Vec<TrackSet> = match range {
        None => {
            let guard = snapshot.lock().unwrap_or_else(|p| p.into_inner());
            vec![guard.tracks.clone()]
        }
        Some(range) => {
            let guard = history.lock().unwrap_or_else(|p| p.into_inner());
            guard.in_range(&range).cloned().collect()
        }
    };
    for set in &sets {
        match protocol::encode(set, format) {
            Ok(bytes) => {
                if let Err(e) = query
                    .reply(reply_key, bytes)
                    .encoding(format.to_zenoh())
                    .wait()
                {
                    tracing::debug!(error = %e, "reply failed");
                    return;
                }
            }
            Err(e) => tracing::error!(error = %e, "encoding a reply failed"),
        }
    }
}
