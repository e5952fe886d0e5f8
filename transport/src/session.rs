//! Opening a Zenoh session from the `[zenoh]` section shared by the server and the agents.

use std::future::Future;
use std::path::PathBuf;
use std::time::Duration;

use serde::Deserialize;
use thiserror::Error;

/// Why a session could not be configured or opened.
#[derive(Debug, Error)]
pub enum SessionError {
    /// A configuration value was refused by Zenoh.
    #[error("zenoh configuration `{key}` = {value}: {reason}")]
    Config {
        /// The Zenoh configuration key.
        key: String,
        /// The value that was refused.
        value: String,
        /// Zenoh's own words.
        reason: String,
    },
    /// The Zenoh configuration file could not be read.
    #[error("zenoh configuration file {path}: {reason}")]
    File {
        /// The file.
        path: PathBuf,
        /// Zenoh's own words.
        reason: String,
    },
    /// Zenoh refused to open the session (e.g. a client with no reachable router).
    #[error("opening the zenoh session failed: {0}")]
    Open(String),
}

/// `[zenoh]`: how a program joins the Zenoh network.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct ZenohConfig {
    /// `peer` or `client` (a client needs a router in `connect`).
    pub mode: String,
    /// Endpoints to connect to, e.g. `tcp/127.0.0.1:7447`.
    pub connect: Vec<String>,
    /// Endpoints to listen on (peer mode), e.g. `tcp/127.0.0.1:7447`.
    pub listen: Vec<String>,
    /// Multicast scouting; off by default so that deployments are explicit.
    pub scouting: bool,
    /// Optional Zenoh JSON5 configuration file (TLS, user/password, access control); the keys
    /// above are applied on top of it.
    pub config_file: Option<PathBuf>,
}

impl Default for ZenohConfig {
    fn default() -> Self {
        Self {
            mode: "peer".into(),
            connect: Vec::new(),
            listen: Vec::new(),
            scouting: false,
            config_file: None,
        }
    }
}

impl ZenohConfig {
    /// Checks the values Zenoh would only refuse late (at open); the error says which key.
    pub fn validate(&self) -> Result<(), (String, String)> {
        if self.mode != "peer" && self.mode != "client" {
            return Err((
                "mode".into(),
                format!("{:?} is neither \"peer\" nor \"client\"", self.mode),
            ));
        }
        if self.mode == "client" && self.connect.is_empty() && self.config_file.is_none() {
            return Err((
                "connect".into(),
                "client mode needs a router endpoint".into(),
            ));
        }
        for (key, list) in [("connect", &self.connect), ("listen", &self.listen)] {
            if let Some(bad) = list.iter().find(|e| {
                !e.contains('/') || !e.rsplit('/').next().is_some_and(|a| a.contains(':'))
            }) {
                return Err((
                    key.into(),
                    format!("{bad:?} is not an endpoint like tcp/127.0.0.1:7447"),
                ));
            }
        }
        Ok(())
    }

    /// The Zenoh configuration these settings describe.
    pub fn to_zenoh(&self) -> Result<zenoh::Config, SessionError> {
        let mut config = match &self.config_file {
            Some(path) => zenoh::Config::from_file(path).map_err(|e| SessionError::File {
                path: path.clone(),
                reason: e.to_string(),
            })?,
            None => zenoh::Config::default(),
        };
        let json = |items: &[String]| {
            let quoted: Vec<String> = items.iter().map(|s| format!("{s:?}")).collect();
            format!("[{}]", quoted.join(","))
        };
        let mut set = |key: &str, value: String| {
            config
                .insert_json5(key, &value)
                .map_err(|e| SessionError::Config {
                    key: key.into(),
                    value: value.clone(),
                    reason: e.to_string(),
                })
        };
        set("mode", format!("{:?}", self.mode))?;
        if !self.connect.is_empty() {
            set("connect/endpoints", json(&self.connect))?;
        }
        if !self.listen.is_empty() {
            set("listen/endpoints", json(&self.listen))?;
        }
        set("scouting/multicast/enabled", self.scouting.to_string())?;
        Ok(config)
    }

    /// Opens a session with these settings.
    pub async fn open(&self) -> Result<zenoh::Session, SessionError> {
        let config = self.to_zenoh()?;
        zenoh::open(config)
            .await
            .map_err(|e| SessionError::Open(e.to_string()))
    }

    /// Opens a session, waiting for the network: while Zenoh cannot open it (a client whose
    /// router is not up yet), tries again after a pause that doubles from 250 ms up to 5 s,
    /// logging each failure, until it succeeds or `stop` completes (then `Ok(None)`).
    /// Configuration errors fail at once, since retrying cannot fix them.
    pub async fn open_retrying(
        &self,
        stop: impl Future<Output = ()>,
    ) -> Result<Option<zenoh::Session>, SessionError> {
        let config = self.to_zenoh()?;
        let mut stop = std::pin::pin!(stop);
        let mut pause = FIRST_RETRY;
        loop {
            match zenoh::open(config.clone()).await {
                Ok(session) => return Ok(Some(session)),
                Err(e) => {
                    let error = SessionError::Open(e.to_string());
                    tracing::warn!(%error, connect = ?self.connect, retry_in = ?pause, "zenoh session not open yet; retrying");
                }
            }
            tokio::select! {
                _ = tokio::time::sleep(pause) => {}
                _ = &mut stop => return Ok(None),
            }
            pause = (pause * 2).min(MAX_RETRY);
        }
    }
}

/// First pause of [`ZenohConfig::open_retrying`].
const FIRST_RETRY: Duration = Duration::from_millis(250);
/// Longest pause of [`ZenohConfig::open_retrying`].
const MAX_RETRY: Duration = Duration::from_secs(5);
