//! The simulator's error type.

use std::path::PathBuf;

use thiserror::Error;

/// Everything that can go wrong when reading a scenario or preparing a simulation.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// The scenario file could not be read.
    #[error("cannot read scenario file {path}: {source}")]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The text is not valid TOML or does not have the scenario's shape (a missing or
    /// unknown key, a value of the wrong type); the message names the key and its line.
    #[error("scenario is not well-formed: {message}")]
    Syntax {
        /// The TOML parser's message, with the offending key and its position.
        message: String,
    },
    /// A key has a value the simulator cannot use.
    #[error("scenario key `{key}`: {reason}")]
    InvalidValue {
        /// The key's path in the file, e.g. `targets[2].motion.std`.
        key: String,
        /// Why the value is rejected.
        reason: String,
    },
    /// A sensor's descriptor breaks the wire contract's validation rules (the fusion
    /// server would reject it).
    #[error("scenario key `{key}`: {source}")]
    Descriptor {
        /// The sensor's path in the file, e.g. `sensors[1]`.
        key: String,
        /// The protocol's description of the problem.
        source: protocol::ProtocolError,
    },
    /// A sensor's descriptor does not make a usable measurement model.
    #[error("scenario key `{key}`: {source}")]
    SensorModel {
        /// The sensor's path in the file, e.g. `sensors[1].model`.
        key: String,
        /// Why the model was rejected.
        source: sensor_models::Error,
    },
    /// A sensor name was asked for that the scenario does not have.
    #[error("the scenario has no sensor named `{sensor}`")]
    UnknownSensor {
        /// The requested name.
        sensor: String,
    },
}

/// Shorthand for [`ScenarioError::InvalidValue`].
pub(crate) fn invalid(key: impl Into<String>, reason: impl Into<String>) -> ScenarioError {
    ScenarioError::InvalidValue {
        key: key.into(),
        reason: reason.into(),
    }
}
