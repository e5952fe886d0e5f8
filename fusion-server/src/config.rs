//! Server configuration: a TOML file read with the `config` crate, every key overridable by
//! environment variables `FUSION__SECTION__KEY` (e.g. `FUSION__FILTER__MAX_COMPONENTS=200`),
//! validated at start with an error that names the offending key.
//!
//! `fusion-server/fusion.example.toml` documents every key; its values are the defaults below.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;
pub use transport::ZenohConfig;

mod ingest;
mod output;
pub use ingest::IngestConfig;
pub use output::OutputConfig;

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
    /// The GM-PHD filter's models and thresholds.
    pub filter: FilterConfig,
    /// Track confirmation and deletion.
    pub tracks: TracksConfig,
    /// Static sensor descriptors (protocol JSON form) that override or stand in for published ones.
    pub sensors: Vec<serde_json::Value>,
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

/// Default `filter.adaptive_birth_rate`: ν_b per LIDAR set (10 Hz in the room), tuned on the
/// room replay (`tests/replay_room.rs`).
const ADAPTIVE_BIRTH_RATE: f64 = 0.05;
/// Default `filter.adaptive_birth_velocity_std`, m/s: walking pace.
const ADAPTIVE_BIRTH_VELOCITY_STD: f64 = 1.0;

/// Default `filter.birth_interval_s`: 50 additions per second, as many as sets arrive from one
/// fast camera. In the room replay (`tests/replay_room.rs`, 7 sensors) 0.02 s gives the same
/// OSPA and count as births at every set, while 0.05–0.2 s cost 1–2 % of right counts: each
/// addition then carries more mass, and its children near tracked people weigh more.
const BIRTH_INTERVAL_S: f64 = 0.02;

/// `[filter]`: motion model, birth, survival and mixture reduction.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FilterConfig {
    /// `constant_velocity` (3-D, state [x y z vx vy vz]) or `random_walk` (3-D, state [x y z]).
    pub motion: String,
    /// Continuous white-noise acceleration, m/s² (constant velocity).
    pub accel_noise_std: f64,
    /// Random-walk diffusion, m/√s (random walk).
    pub position_noise_std: f64,
    /// Probability that an object survives one second (p_S over Δt is this to the power Δt).
    pub survival_probability: f64,
    /// Objects whose predicted position lies farther than this (metres) outside the site
    /// volume do not survive. Without such a limit a component that drifts out of every
    /// sensor's view keeps its weight for ever (p_D = 0 there) and becomes a false track or
    /// spoils a real one (`gmphd::SurvivalRegion`). Set it large to track outside the volume.
    pub survival_margin_m: f64,
    /// `grid` (components over the site volume) or `mixture` (`birth_means`).
    pub birth: String,
    /// Expected number of new objects per second over the whole volume.
    pub birth_rate: f64,
    /// Grid size along x, y, z (grid birth).
    pub birth_grid: [usize; 3],
    /// Means of the birth components (mixture birth), metres.
    pub birth_means: Vec<[f64; 3]>,
    /// Standard deviation of a birth component's position, metres.
    pub birth_position_std: f64,
    /// Standard deviation of a birth component's velocity, m/s.
    pub birth_velocity_std: f64,
    /// Least time between two additions of `birth`'s components, seconds: they are added for
    /// all the time owed at once, so the birth rate is unchanged while sets arriving every
    /// few milliseconds do not each carry (and prune) a full grid of births. 0: every set.
    pub birth_interval_s: f64,
    /// Measurement-driven birth (Ristic et al. 2012) in addition to `birth`: each measurement
    /// of a sensor that can be inverted to a world point (LIDAR, position, bearing–range) and
    /// that the tracks do not explain becomes a birth of the next prediction, anywhere.
    pub adaptive_birth: bool,
    /// Expected new objects per measurement set of an invertible sensor, shared among its
    /// measurements by how poorly the tracks explain them.
    pub adaptive_birth_rate: f64,
    /// Standard deviation of an adaptive birth's velocity, m/s.
    pub adaptive_birth_velocity_std: f64,
    /// Prune components below this weight (Vo & Ma's T).
    pub prune_threshold: f64,
    /// Merge components within this Mahalanobis distance (Vo & Ma's U).
    pub merge_threshold: f64,
    /// Keep at most this many components (Vo & Ma's J_max).
    pub max_components: usize,
    /// A component (label) with weight above this is an estimate.
    pub extraction_threshold: f64,
}

impl Default for FilterConfig {
    fn default() -> Self {
        Self {
            motion: "constant_velocity".into(),
            accel_noise_std: 1.0,
            position_noise_std: 0.5,
            survival_probability: 0.99,
            survival_margin_m: 0.25,
            birth: "grid".into(),
            birth_rate: 0.2,
            birth_grid: [4, 3, 1],
            birth_means: Vec::new(),
            birth_position_std: 0.6,
            birth_velocity_std: 0.5,
            birth_interval_s: BIRTH_INTERVAL_S,
            adaptive_birth: true,
            adaptive_birth_rate: ADAPTIVE_BIRTH_RATE,
            adaptive_birth_velocity_std: ADAPTIVE_BIRTH_VELOCITY_STD,
            prune_threshold: 1e-5,
            merge_threshold: 4.0,
            max_components: 100,
            extraction_threshold: 0.5,
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
        self.ingest.validate()?;
        self.output.validate()?;
        positive("checkpoint.interval_s", self.checkpoint.interval_s)?;
        positive("checkpoint.max_age_s", self.checkpoint.max_age_s)?;
        Ok(())
    }
}

pub(crate) fn positive(key: &str, value: f64) -> Result<(), ConfigError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(key, format!("{value} must be a positive number")))
    }
}

fn probability(key: &str, value: f64) -> Result<(), ConfigError> {
    if value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(invalid(key, format!("{value} is outside (0, 1]")))
    }
}

impl FilterConfig {
    fn validate(&self) -> Result<(), ConfigError> {
        if self.motion != "constant_velocity" && self.motion != "random_walk" {
            return Err(invalid(
                "filter.motion",
                format!(
                    "{:?}: expected \"constant_velocity\" or \"random_walk\"",
                    self.motion
                ),
            ));
        }
        positive("filter.accel_noise_std", self.accel_noise_std)?;
        positive("filter.position_noise_std", self.position_noise_std)?;
        probability("filter.survival_probability", self.survival_probability)?;
        if !(self.survival_margin_m.is_finite() && self.survival_margin_m >= 0.0) {
            return Err(invalid(
                "filter.survival_margin_m",
                format!("{}: must be a finite number >= 0", self.survival_margin_m),
            ));
        }
        match self.birth.as_str() {
            "grid" => {
                if self.birth_grid.contains(&0) {
                    return Err(invalid(
                        "filter.birth_grid",
                        "every count must be at least 1",
                    ));
                }
            }
            "mixture" => {
                if self.birth_means.is_empty() {
                    return Err(invalid(
                        "filter.birth_means",
                        "mixture birth needs at least one mean",
                    ));
                }
                if self.birth_means.iter().flatten().any(|v| !v.is_finite()) {
                    return Err(invalid(
                        "filter.birth_means",
                        "contains a non-finite number",
                    ));
                }
            }
            other => {
                return Err(invalid(
                    "filter.birth",
                    format!("{other:?}: expected \"grid\" or \"mixture\""),
                ))
            }
        }
        positive("filter.birth_rate", self.birth_rate)?;
        positive("filter.birth_position_std", self.birth_position_std)?;
        positive("filter.birth_velocity_std", self.birth_velocity_std)?;
        if !(self.birth_interval_s.is_finite() && self.birth_interval_s >= 0.0) {
            return Err(invalid(
                "filter.birth_interval_s",
                format!("{}: must be a finite number >= 0", self.birth_interval_s),
            ));
        }
        positive("filter.adaptive_birth_rate", self.adaptive_birth_rate)?;
        positive(
            "filter.adaptive_birth_velocity_std",
            self.adaptive_birth_velocity_std,
        )?;
        positive("filter.prune_threshold", self.prune_threshold)?;
        positive("filter.merge_threshold", self.merge_threshold)?;
        if self.max_components == 0 {
            return Err(invalid("filter.max_components", "must be at least 1"));
        }
        positive("filter.extraction_threshold", self.extraction_threshold)
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
