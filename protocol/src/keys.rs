//! Key expressions of the contract: builders for every key and parsers for the ones a subscriber receives.
//!
//! Everything of one deployment lives under `fusion/<site>`:
//! - `fusion/<site>/sensors/<sensor>/descriptor|measurements|alive` (edge agents),
//! - `fusion/<site>/tracks`, `fusion/<site>/tracks/json`, `fusion/<site>/status` (fusion server),
//! - `fusion/<site>/truth` (simulators only),
//! - `fusion/<site>/server/active/<instance>` and `fusion/<site>/server/<instance>/status|checkpoint`
//!   (between the fusion servers of one site: the active server's liveliness token, each
//!   server's own status and the filter state a joining standby starts from).

use crate::error::ProtocolError;
use crate::ids::{InstanceId, SensorId, Site};
use std::fmt;

/// First chunk of every key of the contract.
pub const ROOT: &str = "fusion";

/// The three keys an edge agent writes under `fusion/<site>/sensors/<sensor>/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SensorKeyKind {
    /// `.../descriptor`: the `SensorDescriptor` (put and queryable).
    Descriptor,
    /// `.../measurements`: one `MeasurementSet` per scan or frame.
    Measurements,
    /// `.../alive`: the agent's liveliness token.
    Alive,
}

impl SensorKeyKind {
    /// Every sensor key kind, in contract order.
    pub const ALL: [SensorKeyKind; 3] = [Self::Descriptor, Self::Measurements, Self::Alive];

    /// The last chunk of the key.
    pub fn suffix(self) -> &'static str {
        match self {
            Self::Descriptor => "descriptor",
            Self::Measurements => "measurements",
            Self::Alive => "alive",
        }
    }

    fn from_suffix(suffix: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|kind| kind.suffix() == suffix)
    }
}

impl fmt::Display for SensorKeyKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.suffix())
    }
}

/// The three keys the server or a simulator writes directly under `fusion/<site>/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SiteKeyKind {
    /// `fusion/<site>/tracks`: the `TrackSet` (put and queryable).
    Tracks,
    /// `fusion/<site>/status`: the `Status` (queryable).
    Status,
    /// `fusion/<site>/truth`: a `TruthSet` (simulators only).
    Truth,
}

impl SiteKeyKind {
    /// Every site key kind, in contract order.
    pub const ALL: [SiteKeyKind; 3] = [Self::Tracks, Self::Status, Self::Truth];

    /// The last chunk of the key.
    pub fn suffix(self) -> &'static str {
        match self {
            Self::Tracks => "tracks",
            Self::Status => "status",
            Self::Truth => "truth",
        }
    }

    fn from_suffix(suffix: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|kind| kind.suffix() == suffix)
    }
}

impl fmt::Display for SiteKeyKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.suffix())
    }
}

/// `fusion/<site>/sensors/<sensor>/<kind>`.
pub fn sensor_key(site: &Site, sensor: &SensorId, kind: SensorKeyKind) -> String {
    format!("{ROOT}/{site}/sensors/{sensor}/{kind}")
}

/// `fusion/<site>/sensors/<sensor>/descriptor`.
pub fn descriptor_key(site: &Site, sensor: &SensorId) -> String {
    sensor_key(site, sensor, SensorKeyKind::Descriptor)
}

/// `fusion/<site>/sensors/<sensor>/measurements`.
pub fn measurements_key(site: &Site, sensor: &SensorId) -> String {
    sensor_key(site, sensor, SensorKeyKind::Measurements)
}

/// `fusion/<site>/sensors/<sensor>/alive`.
pub fn alive_key(site: &Site, sensor: &SensorId) -> String {
    sensor_key(site, sensor, SensorKeyKind::Alive)
}

/// `fusion/<site>/sensors/*/<kind>`: subscribes to that key of every sensor of the site.
pub fn all_sensors_key(site: &Site, kind: SensorKeyKind) -> String {
    format!("{ROOT}/{site}/sensors/*/{kind}")
}

/// `fusion/<site>/sensors/*/descriptor`.
pub fn all_descriptors_key(site: &Site) -> String {
    all_sensors_key(site, SensorKeyKind::Descriptor)
}

/// `fusion/<site>/sensors/*/measurements`.
pub fn all_measurements_key(site: &Site) -> String {
    all_sensors_key(site, SensorKeyKind::Measurements)
}

/// `fusion/<site>/sensors/*/alive`.
pub fn all_alive_key(site: &Site) -> String {
    all_sensors_key(site, SensorKeyKind::Alive)
}

/// `fusion/<site>/<kind>` for the server's and simulators' keys.
pub fn site_key(site: &Site, kind: SiteKeyKind) -> String {
    format!("{ROOT}/{site}/{kind}")
}

/// `fusion/<site>/tracks`.
pub fn tracks_key(site: &Site) -> String {
    site_key(site, SiteKeyKind::Tracks)
}

/// `fusion/<site>/tracks/json`: the same track sets as `fusion/<site>/tracks`, always in JSON.
pub fn tracks_json_key(site: &Site) -> String {
    format!("{}/json", tracks_key(site))
}

/// `fusion/<site>/status`.
pub fn status_key(site: &Site) -> String {
    site_key(site, SiteKeyKind::Status)
}

/// `fusion/<site>/truth`.
pub fn truth_key(site: &Site) -> String {
    site_key(site, SiteKeyKind::Truth)
}

/// `fusion/<site>/server/active/<instance>`: the liveliness token of the site's active server.
pub fn server_active_token(site: &Site, instance: &InstanceId) -> String {
    format!("{ROOT}/{site}/server/active/{instance}")
}

/// `fusion/<site>/server/active/*`: every active server's token (a liveliness subscriber's key).
pub fn all_server_active_tokens(site: &Site) -> String {
    format!("{ROOT}/{site}/server/active/*")
}

/// The `<instance>` of a key built by [`server_active_token`].
pub fn parse_server_active_token(key: &str) -> Result<(Site, InstanceId), ProtocolError> {
    const SHAPE: &str = "fusion/<site>/server/active/<instance>";
    let chunks: Vec<&str> = key.split('/').collect();
    match chunks.as_slice() {
        [ROOT, site, "server", "active", instance] => {
            Ok((Site::new(*site)?, InstanceId::new(*instance)?))
        }
        _ => Err(malformed(key, SHAPE, "not a server's active token")),
    }
}

/// `fusion/<site>/server/<instance>/status`: one server's own `Status`, active or standby.
pub fn server_status_key(site: &Site, instance: &InstanceId) -> String {
    format!("{ROOT}/{site}/server/{instance}/status")
}

/// `fusion/<site>/server/<instance>/checkpoint`: one server's current filter state (JSON), which
/// a standby joining the site starts from.
pub fn server_checkpoint_key(site: &Site, instance: &InstanceId) -> String {
    format!("{ROOT}/{site}/server/{instance}/checkpoint")
}

/// Builds the error for a key that does not have the expected shape.
fn malformed(key: &str, expected: &'static str, reason: impl Into<String>) -> ProtocolError {
    ProtocolError::MalformedKey {
        key: key.to_owned(),
        expected,
        reason: reason.into(),
    }
}

/// Splits `fusion/<site>/<rest...>` into the site and the remaining chunks.
fn split_root<'k>(
    key: &'k str,
    expected: &'static str,
) -> Result<(Site, Vec<&'k str>), ProtocolError> {
    let mut chunks = key.split('/');
    match chunks.next() {
        Some(ROOT) => {}
        _ => {
            return Err(malformed(
                key,
                expected,
                format!("it does not start with \"{ROOT}/\""),
            ))
        }
    }
    let site = Site::new(chunks.next().unwrap_or(""))?;
    Ok((site, chunks.collect()))
}

/// Parses `fusion/<site>/sensors/<sensor>/descriptor|measurements|alive` (as delivered by a wildcard subscription).
pub fn parse_sensor_key(key: &str) -> Result<(Site, SensorId, SensorKeyKind), ProtocolError> {
    const EXPECTED: &str = "sensor";
    let (site, rest) = split_root(key, EXPECTED)?;
    let [sensors, sensor, suffix] = rest.as_slice() else {
        return Err(malformed(
            key,
            EXPECTED,
            format!("it has {} chunks after the site, expected 3", rest.len()),
        ));
    };
    if *sensors != "sensors" {
        return Err(malformed(
            key,
            EXPECTED,
            format!("chunk {sensors:?} should be \"sensors\""),
        ));
    }
    let sensor = SensorId::new(*sensor)?;
    let kind = SensorKeyKind::from_suffix(suffix).ok_or_else(|| {
        malformed(
            key,
            EXPECTED,
            format!("last chunk {suffix:?} is not descriptor, measurements or alive"),
        )
    })?;
    Ok((site, sensor, kind))
}

/// Parses `fusion/<site>/tracks|status|truth`.
pub fn parse_site_key(key: &str) -> Result<(Site, SiteKeyKind), ProtocolError> {
    const EXPECTED: &str = "site";
    let (site, rest) = split_root(key, EXPECTED)?;
    let [suffix] = rest.as_slice() else {
        return Err(malformed(
            key,
            EXPECTED,
            format!("it has {} chunks after the site, expected 1", rest.len()),
        ));
    };
    let kind = SiteKeyKind::from_suffix(suffix).ok_or_else(|| {
        malformed(
            key,
            EXPECTED,
            format!("last chunk {suffix:?} is not tracks, status or truth"),
        )
    })?;
    Ok((site, kind))
}
