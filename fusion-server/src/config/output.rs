//! `[output]`: how track sets are published and how long they are kept for history queries.

use serde::Deserialize;

use super::{non_negative, positive, ConfigError};

/// `[output]`: publication of tracks.
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutputConfig {
    /// At most this many `TrackSet` puts per second. A guard for subscribers, not a pace: the
    /// default is above any deployment's set rate, so each processed set's tracks go out at once;
    /// under a lower limit the latest state is published as soon as the limit allows.
    pub max_publish_hz: f64,
    /// Also put every `TrackSet` as `application/json` on `fusion/<site>/tracks/json`, for
    /// subscribers that cannot read postcard.
    pub json: bool,
    /// Seconds of published track sets (by stamp) kept in memory for `_time` queries on
    /// `fusion/<site>/tracks`; 0 keeps none.
    pub history_s: f64,
}

impl Default for OutputConfig {
    fn default() -> Self {
        Self {
            max_publish_hz: 1000.0,
            json: true,
            history_s: 600.0,
        }
    }
}

impl OutputConfig {
    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        positive("output.max_publish_hz", self.max_publish_hz)?;
        non_negative("output.history_s", self.history_s)?;
        Ok(())
    }
}
