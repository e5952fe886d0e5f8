//! Server configuration: a TOML file read with the `config` crate, every key overridable by
//! environment variables `FUSION__SECTION__KEY` (e.g. `FUSION__FILTER__MAX_COMPONENTS=200`),
//! validated at start with an error that names the offending key.
//!
//! `fusion-server/fusion.example.toml` documents every key; its values are the defaults below.

use std::path::{Path, PathBuf};

use protocol::SensorDescriptor;
use serde::{Deserialize, Deserializer};
use thiserror::Error;
pub use transport::ZenohConfig;

mod filter;
mod ingest;
mod output;
mod server;
pub use filter::{BirthKind, FilterConfig, MotionKind};
pub use ingest::IngestConfig;
pub use output::OutputConfig;
pub use server::{RoleMode, ServerRoleConfig};

/// Why the configuration could not be used.
#[derive(Debug, Error)]
pub enum ConfigError {
    /// The file or an environment variable could not be read or parsed.
    #[error("configuration: {0}")]
    Load(#[from] config::ConfigError),
    /// A value was read but is not acceptable.
    #[error("configuration key `{key}`: {reason}")]
    Invalid {
        /// Dotted key path, e.g. `filter.survival_probability`.
        key: String,
        /// What is wrong with its value.
        reason: String,
    },
}

pub(crate) fn invalid(key: &str, reason: impl Into<String>) -> ConfigError {
    ConfigError::Invalid {
        key: key.to_string(),
        reason: reason.into(),
    }
}

/// The whole server configuration.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ServerConfig {
    /// How to join the Zenoh network.
    pub zenoh: ZenohConfig,
    /// The deployment: site name and surveillance volume.
    pub site: SiteConfig,
    /// This server's role among the site's servers.
    pub server: ServerRoleConfig,
    /// The GM-PHD filter's models and thresholds.
    pub filter: FilterConfig,
    /// Track confirmation and deletion.
    pub tracks: TracksConfig,
    /// Static sensor descriptors that override or stand in for published ones, parsed (from the
    /// protocol's JSON form) and validated at load.
    #[serde(deserialize_with = "descriptors")]
    pub sensors: Vec<SensorDescriptor>,
    /// Admission of incoming sets and the history kept for late ones.
    pub ingest: IngestConfig,
    /// Publication of track sets.
    pub output: OutputConfig,
    /// Filter-state checkpoints.
    pub checkpoint: CheckpointConfig,
    /// Logging.
    pub log: LogConfig,
}

/// `[site]`: the deployment's name and the volume where objects are tracked.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SiteConfig {
    /// The `<site>` key chunk.
    pub name: String,
    /// Lower corner of the surveillance volume, metres.
    pub volume_min: [f64; 3],
    /// Upper corner of the surveillance volume, metres.
    pub volume_max: [f64; 3],
}

impl Default for SiteConfig {
    fn default() -> Self {
        Self {
            name: "default".into(),
            volume_min: [0.0, 0.0, 0.0],
            volume_max: [3.0, 2.0, 2.2],
        }
    }
}

/// `[tracks]`: when a label becomes a published track and when it is dropped.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TracksConfig {
    /// Weight a label must exceed to count as seen in one set.
    pub confirm_threshold: f64,
    /// A tentative track is confirmed once seen in `confirm_hits` of the last `confirm_window` sets.
    pub confirm_hits: usize,
    /// See `confirm_hits`.
    pub confirm_window: usize,
    /// One set in which a label's weight exceeds this confirms its track at once (MATLAB
    /// `trackerPHD`'s rule), except a label that split off a confirmed track's. Absent: off,
    /// `confirm_hits` only.
    pub confirm_at_once_threshold: Option<f64>,
    /// A confirmed track whose weight stays below this for `delete_after_sets` consecutive
    /// sets that could see it or for `max_coast_s` seconds is deleted (a pause in the data
    /// longer than `max_coast_s / 2` does not count; see `gmphd::tracks`).
    pub delete_threshold: f64,
    /// See `delete_threshold`.
    pub delete_after_sets: usize,
    /// See `delete_threshold`.
    pub max_coast_s: f64,
}

impl Default for TracksConfig {
    fn default() -> Self {
        Self {
            confirm_threshold: 0.5,
            confirm_hits: 3,
            confirm_window: 5,
            confirm_at_once_threshold: None,
            delete_threshold: 0.15,
            delete_after_sets: 12,
            max_coast_s: 1.0,
        }
    }
}

/// `[checkpoint]`: filter state saved atomically so that track ids survive restarts.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CheckpointConfig {
    /// File to write; no checkpoints when absent.
    pub path: Option<PathBuf>,
    /// Seconds between checkpoints (and one more at shutdown).
    pub interval_s: f64,
    /// A checkpoint older than this (by its last processed stamp vs. the clock) is not loaded.
    pub max_age_s: f64,
}

impl Default for CheckpointConfig {
    fn default() -> Self {
        Self {
            path: None,
            interval_s: 2.0,
            max_age_s: 300.0,
        }
    }
}

/// `[log]`: tracing output.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LogConfig {
    /// A tracing filter directive, e.g. `info` or `fusion_server=debug,zenoh=warn`;
    /// `RUST_LOG` wins when set.
    pub level: String,
}

impl Default for LogConfig {
    fn default() -> Self {
        Self {
            level: "info,zenoh=warn".into(),
        }
    }
}

impl ServerConfig {
    /// Reads `path` (TOML) when given, then the `FUSION__SECTION__KEY` environment variables,
    /// and validates the result.
    pub fn load(path: Option<&Path>) -> Result<Self, ConfigError> {
        let mut builder = config::Config::builder();
        if let Some(path) = path {
            builder = builder.add_source(
                config::File::from(path.to_path_buf()).format(config::FileFormat::Toml),
            );
        }
        builder = builder.add_source(
            config::Environment::with_prefix("FUSION")
                .prefix_separator("__")
                .separator("__")
                .try_parsing(true)
                .list_separator(",")
                .with_list_parse_key("zenoh.connect")
                .with_list_parse_key("zenoh.listen")
                .with_list_parse_key("site.volume_min")
                .with_list_parse_key("site.volume_max")
                .with_list_parse_key("filter.birth_grid"),
        );
        let mut config: ServerConfig = builder.build()?.try_deserialize()?;
        // An empty environment variable (`FUSION__ZENOH__LISTEN=`) means "none".
        config.zenoh.connect.retain(|e| !e.trim().is_empty());
        config.zenoh.listen.retain(|e| !e.trim().is_empty());
        config.validate()?;
        Ok(config)
    }

    /// Checks every value; the error names the first offending key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.zenoh
            .validate()
            .map_err(|(key, reason)| invalid(&format!("zenoh.{key}"), reason))?;
        protocol::Site::new(&self.site.name).map_err(|e| invalid("site.name", e.to_string()))?;
        self.server.validate()?;
        for i in 0..3 {
            let (lo, hi) = (self.site.volume_min[i], self.site.volume_max[i]);
            if !lo.is_finite() || !hi.is_finite() || lo >= hi {
                return Err(invalid(
                    "site.volume_max",
                    "every component must exceed volume_min's",
                ));
            }
        }
        self.filter.validate()?;
        self.tracks.validate()?;
        self.validate_sensors()?;
        self.ingest.validate()?;
        self.output.validate()?;
        positive("checkpoint.interval_s", self.checkpoint.interval_s)?;
        positive("checkpoint.max_age_s", self.checkpoint.max_age_s)?;
        Ok(())
    }
}

impl ServerConfig {
    /// Each static descriptor must be valid and belong to this site.
    fn validate_sensors(&self) -> Result<(), ConfigError> {
        for (i, descriptor) in self.sensors.iter().enumerate() {
            let key = format!("sensors[{i}]");
            if descriptor.site.as_str() != self.site.name {
                return Err(invalid(
                    &key,
                    format!(
                        "site {} is not site.name {}",
                        descriptor.site, self.site.name
                    ),
                ));
            }
            descriptor
                .validate()
                .map_err(|e| invalid(&key, e.to_string()))?;
        }
        Ok(())
    }
}

/// Reads `sensors` as the protocol's JSON form of each descriptor (whatever the file format),
/// so that a static descriptor is written exactly as an agent would publish it.
fn descriptors<'de, D: Deserializer<'de>>(input: D) -> Result<Vec<SensorDescriptor>, D::Error> {
    let values = Vec::<serde_json::Value>::deserialize(input)?;
    values
        .into_iter()
        .enumerate()
        .map(|(i, value)| {
            serde_json::from_value(value)
                .map_err(|e| serde::de::Error::custom(format!("sensors[{i}]: {e}")))
        })
        .collect()
}

pub(crate) fn positive(key: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(key, format!("{value} must be a positive number")))
    }
}

/// `value` is a finite number ≥ 0 (0 usually turns the feature off).
pub(crate) fn non_negative(key: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!("{value}: must be a finite number >= 0"),
        ))
    }
}

pub(crate) fn probability(key: &str, value: f64) -> Result<(), ConfigError> {
    if value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(invalid(key, format!("{value} is outside (0, 1]")))
    }
}

impl TracksConfig {
    fn validate(&self) -> Result<(), ConfigError> {
        positive("tracks.confirm_threshold", self.confirm_threshold)?;
        if self.confirm_hits == 0 || self.confirm_hits > self.confirm_window {
            return Err(invalid(
                "tracks.confirm_hits",
                "must be between 1 and tracks.confirm_window",
            ));
        }
        if let Some(at_once) = self.confirm_at_once_threshold {
            if !(at_once.is_finite() && at_once >= self.confirm_threshold) {
                return Err(invalid(
                    "tracks.confirm_at_once_threshold",
                    "must be finite and at least tracks.confirm_threshold",
                ));
            }
        }
        if !self.delete_threshold.is_finite()
            || self.delete_threshold < 0.0
            || self.delete_threshold >= self.confirm_threshold
        {
            return Err(invalid(
                "tracks.delete_threshold",
                "must be in [0, tracks.confirm_threshold)",
            ));
        }
        if self.delete_after_sets == 0 {
            return Err(invalid("tracks.delete_after_sets", "must be at least 1"));
        }
        positive("tracks.max_coast_s", self.max_coast_s)
    }
}
