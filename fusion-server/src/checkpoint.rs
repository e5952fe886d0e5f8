//! Filter-state checkpoints: written atomically (write to a temporary file, then rename) so a
//! crash never leaves a torn file, and loaded at start when present and not stale.

use std::fs;
use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::tracker::TrackerState;

/// What is written to the checkpoint file.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Wall-clock time of writing, seconds since the Unix epoch.
    pub saved_at: f64,
    /// The site the state belongs to.
    pub site: String,
    /// The filter and track state.
    pub state: TrackerState,
}

/// Writes `checkpoint` to `path` atomically.
pub fn save(path: &Path, checkpoint: &Checkpoint) -> std::io::Result<()> {
    let bytes = serde_json::to_vec(checkpoint).map_err(std::io::Error::other)?;
    let tmp = path.with_extension("tmp");
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir)?;
    }
    let mut file = fs::File::create(&tmp)?;
    file.write_all(&bytes)?;
    file.sync_all()?;
    drop(file);
    fs::rename(&tmp, path)
}

/// Why a checkpoint was not loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// There is no checkpoint file.
    #[error("no checkpoint at {0}")]
    Missing(String),
    /// The file could not be read or parsed.
    #[error("checkpoint {path} unreadable: {reason}")]
    Unreadable {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The checkpoint is older than allowed or belongs to another site.
    #[error("checkpoint {path} not used: {reason}")]
    NotApplicable {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
}

/// Loads the checkpoint at `path` if it exists, belongs to `site` and was saved at most
/// `max_age_s` before `now`.
pub fn load(path: &Path, site: &str, now: f64, max_age_s: f64) -> Result<Checkpoint, LoadError> {
    let shown = path.display().to_string();
    let bytes = match fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(LoadError::Missing(shown))
        }
        Err(e) => {
            return Err(LoadError::Unreadable {
                path: shown,
                reason: e.to_string(),
            })
        }
    };
    let checkpoint: Checkpoint =
        serde_json::from_slice(&bytes).map_err(|e| LoadError::Unreadable {
            path: shown.clone(),
            reason: e.to_string(),
        })?;
    if checkpoint.site != site {
        return Err(LoadError::NotApplicable {
            path: shown,
            reason: format!("it is for site {:?}, not {site:?}", checkpoint.site),
        });
    }
    let age = now - checkpoint.saved_at;
    if age > max_age_s {
        return Err(LoadError::NotApplicable {
            path: shown,
            reason: format!("saved {age:.0} s ago, more than checkpoint.max_age_s = {max_age_s}"),
        });
    }
    Ok(checkpoint)
}
