//! Agent settings: the `[zenoh]` and `[log]` sections of a `--config` TOML file, overridden by
//! `AGENT__SECTION__KEY` environment variables, overridden by the command-line flags.
//!
//! Also here: reading a front end's own TOML configuration (`--frontend-config`).
//!
//! Read with the `config` crate exactly like the fusion server's configuration (prefix `AGENT` instead of
//! `FUSION`), so one `[zenoh]` section can be shared by both.

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Deserialize;
use transport::ZenohConfig;

use crate::cli::CommonArgs;
use crate::error::AgentError;

/// The whole agent configuration file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AgentSettings {
    /// How to join the Zenoh network.
    pub zenoh: ZenohConfig,
    /// Logging.
    pub log: LogSettings,
}

/// `[log]`: tracing output (always on stderr).
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LogSettings {
    /// A tracing filter directive, e.g. `info` or `edge_agent=debug,zenoh=warn`; `RUST_LOG` wins when set.
    pub level: String,
}

impl Default for LogSettings {
    fn default() -> Self {
        Self {
            level: "info,zenoh=warn".into(),
        }
    }
}

impl AgentSettings {
    /// Reads `path` (TOML) when given, then the `AGENT__SECTION__KEY` environment variables (lists such as
    /// `AGENT__ZENOH__CONNECT` are comma-separated), without validating.
    pub fn load(path: Option<&Path>) -> Result<Self, AgentError> {
        let mut builder = config::Config::builder();
        if let Some(path) = path {
            builder = builder.add_source(
                config::File::from(path.to_path_buf()).format(config::FileFormat::Toml),
            );
        }
        builder = builder.add_source(
            config::Environment::with_prefix("AGENT")
                .prefix_separator("__")
                .separator("__")
                .try_parsing(true)
                .list_separator(",")
                .with_list_parse_key("zenoh.connect")
                .with_list_parse_key("zenoh.listen"),
        );
        Ok(builder.build()?.try_deserialize()?)
    }

    /// Loads the settings for `common` (its `--config` file and the environment), applies its Zenoh flags on
    /// top and validates the result; the error names the offending key.
    pub fn resolve(common: &CommonArgs) -> Result<Self, AgentError> {
        let mut settings = Self::load(common.config.as_deref())?;
        if let Some(mode) = &common.mode {
            settings.zenoh.mode = mode.clone();
        }
        if !common.connect.is_empty() {
            settings.zenoh.connect = common.connect.clone();
        }
        if !common.listen.is_empty() {
            settings.zenoh.listen = common.listen.clone();
        }
        settings
            .zenoh
            .validate()
            .map_err(|(key, reason)| AgentError::invalid(format!("zenoh.{key}"), reason))?;
        Ok(settings)
    }
}

/// Reads a front end's TOML configuration file (`--frontend-config`) into its configuration type.
pub fn read_frontend_config<T: DeserializeOwned>(path: &Path) -> Result<T, AgentError> {
    let error = |reason: String| AgentError::FrontendConfig {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| error(e.to_string()))?;
    toml::from_str(&text).map_err(|e| error(e.to_string()))
}
