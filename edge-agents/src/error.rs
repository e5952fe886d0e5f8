//! The agent's error type: every way a run can fail before or while it produces data.
//!
//! A failed `put` is not among them: publishing failures are logged (rate-limited) and the agent goes on,
//! because a sensor must keep running while its router is away.

use std::path::PathBuf;

use frontends::camera::CameraError;
use frontends::lidar::{CloudFileError, LidarConfigError};
use frontends::mic::MicError;
use protocol::ProtocolError;
use simulator::ScenarioError;
use thiserror::Error;
use transport::SessionError;

/// Why the agent could not start or had to stop.
#[derive(Debug, Error)]
pub enum AgentError {
    /// The `--config` file or an `AGENT__...` environment variable could not be read.
    #[error("configuration: {0}")]
    ConfigLoad(#[from] config::ConfigError),
    /// A configuration value or flag was read but cannot be used.
    #[error("configuration `{key}`: {reason}")]
    InvalidConfig {
        /// The flag or dotted configuration key, e.g. `zenoh.mode` or `--speed`.
        key: String,
        /// What is wrong with its value.
        reason: String,
    },
    /// A flag combination that does not describe one input.
    #[error("{0}")]
    Usage(String),
    /// A descriptor file could not be read or does not have the descriptor's shape.
    #[error("descriptor file {path}: {reason}")]
    DescriptorFile {
        /// The file given with `--descriptor`.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// A descriptor was read but fails the protocol's validation.
    #[error("descriptor of sensor `{sensor}` is invalid: {source}")]
    InvalidDescriptor {
        /// The sensor the descriptor names.
        sensor: String,
        /// The rule it breaks.
        source: ProtocolError,
    },
    /// A front-end configuration file (`--frontend-config`) could not be read or parsed.
    #[error("front-end configuration {path}: {reason}")]
    FrontendConfig {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// The scenario could not be read or simulated.
    #[error("scenario: {0}")]
    Scenario(#[from] ScenarioError),
    /// The Zenoh session could not be configured.
    #[error("zenoh: {0}")]
    Session(#[from] SessionError),
    /// Zenoh refused to declare a publisher, queryable or liveliness token.
    #[error("zenoh: declaring {what}: {reason}")]
    Declare {
        /// What was being declared, with its key.
        what: String,
        /// Zenoh's own words.
        reason: String,
    },
    /// The replay output could not be written.
    #[error("writing replay output to {target}: {source}")]
    Output {
        /// The file name, or `stdout`.
        target: String,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The camera front end failed (bad frames, stamps or detections).
    #[error("camera: {0}")]
    Camera(#[from] CameraError),
    /// The microphone front end failed (bad WAV files or configuration).
    #[error("mic pair: {0}")]
    Mic(#[from] MicError),
    /// A LIDAR scan file could not be read.
    #[error("lidar: {0}")]
    LidarFile(#[from] CloudFileError),
    /// The LIDAR front end's configuration is unusable.
    #[error("lidar: {0}")]
    LidarConfig(#[from] LidarConfigError),
    /// The camera's single-view tracker could not be built or updated.
    #[error("camera tracker: {0}")]
    Tracker(#[from] gmphd::FilterError),
    /// The async runtime could not be started.
    #[error("starting the async runtime: {0}")]
    Runtime(std::io::Error),
    /// A `--video` source could not be decoded (ffmpeg missing, the source unreadable).
    #[error("video: {0}")]
    Video(String),
    /// A directory or file of input data could not be listed or read.
    #[error("reading {path}: {source}")]
    Input {
        /// The file or directory.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
}

impl AgentError {
    /// Shorthand for [`AgentError::InvalidConfig`].
    pub fn invalid(key: impl Into<String>, reason: impl Into<String>) -> Self {
        AgentError::InvalidConfig {
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// True when the error is a closed pipe on the replay output (e.g. `edge-agent sim --output - | head`),
    /// which ends the run quietly rather than as a failure.
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, AgentError::Output { source, .. } if source.kind() == std::io::ErrorKind::BrokenPipe)
    }
}
