//! `Status`: the fusion server's health report, answered by the queryable on `fusion/<site>/status`.

use super::model::SensorKind;
use crate::ids::{SensorId, Site};
use serde::{Deserialize, Serialize};

/// What the server knows of one sensor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorStatus {
    /// The sensor's name.
    pub sensor: SensorId,
    /// The kind of its model.
    pub kind: SensorKind,
    /// Whether the agent's liveliness token is currently held.
    pub alive: bool,
    /// Stamp of the last set received from it; `null` before the first one.
    pub last_stamp: Option<f64>,
    /// Sets received.
    pub received: u64,
    /// Sets that updated the filter.
    pub processed: u64,
    /// Sets that arrived too late to be used.
    pub late: u64,
    /// Sets rejected by validation.
    pub invalid: u64,
    /// Sets missing from gaps in `seq`.
    pub lost: u64,
    /// Times a set of this sensor arrived older than sets already processed, so the filter went
    /// back to before its stamp and processed again (0 from servers that do not report it).
    #[serde(default)]
    pub rollbacks: u64,
    /// Sets of this sensor processed again after another set's rollback.
    #[serde(default)]
    pub reprocessed: u64,
}

/// Payloads rejected, by reason, over all sensors.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rejected {
    /// Payloads that could not be decoded (bad encoding, bad bytes, wrong shape).
    pub undecodable: u64,
    /// Sets from a sensor without a descriptor.
    pub unknown_sensor: u64,
    /// Payloads that decoded but failed validation.
    pub invalid: u64,
    /// Sets too old to be used.
    pub late: u64,
}

/// Percentiles of the time from a set's arrival to the publication of the tracks it updated.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatencyMs {
    /// Median in milliseconds; `null` before the first publication.
    pub p50: Option<f64>,
    /// 99th percentile in milliseconds; `null` before the first publication.
    pub p99: Option<f64>,
}

/// The server's health report.
///
/// JSON: `{"version": 1, "site": "default", "uptime_s": 12.5, "stamp": ..., "components": 57, "tracks": 2,
/// "sensors": [...], "rejected": {...}, "latency_ms": {"p50": 0.4, "p99": 1.9}, "role": "active"}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Status {
    /// Protocol version; must be [`crate::PROTOCOL_VERSION`].
    pub version: u32,
    /// The deployment the server serves.
    pub site: Site,
    /// Seconds since the server started.
    pub uptime_s: f64,
    /// Stamp of the server's current estimate, seconds since the Unix epoch.
    pub stamp: f64,
    /// Number of Gaussian components in the intensity.
    pub components: u64,
    /// Number of tracks currently published.
    pub tracks: u64,
    /// One entry per known sensor.
    pub sensors: Vec<SensorStatus>,
    /// Rejected payloads by reason.
    pub rejected: Rejected,
    /// Arrival-to-publication latency.
    pub latency_ms: LatencyMs,
    /// Whether this server publishes the site's tracks or stands by (`active` from servers that
    /// do not report it).
    #[serde(default)]
    pub role: ServerRole,
}

/// A fusion server's part at its site: the one that publishes, or a hot standby that filters
/// the same sets and takes over when the active server goes away.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ServerRole {
    /// Publishes `fusion/<site>/tracks` and answers the site's queries.
    #[default]
    Active,
    /// Ingests and filters without publishing.
    Standby,
}

impl std::fmt::Display for ServerRole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Active => "active",
            Self::Standby => "standby",
        })
    }
}
