//! Stamps of live input: the host clock at the moment data arrived, less the known delay of the capture
//! pipeline in front of the agent (camera exposure, encoder, network, decoder).
//!
//! The clock is the Unix wall clock read once and then advanced by a monotonic clock, so a stamp never goes
//! back when the host's clock is stepped while the agent runs (the run loop needs stamps in order).

use std::time::{Duration, Instant};

use crate::error::AgentError;
use crate::pacing::wall_clock;

/// Default of `--pipeline-delay-ms`: nothing is subtracted unless the camera's delay has been measured.
pub const DEFAULT_PIPELINE_DELAY_MS: f64 = 0.0;

/// The host clock of live sources, corrected by the pipeline delay.
#[derive(Debug, Clone, Copy)]
pub struct CaptureClock {
    wall_at_origin: f64,
    origin: Instant,
    delay_s: f64,
}

impl CaptureClock {
    /// A clock starting now, subtracting `delay_ms` milliseconds (finite, at least 0) from every stamp.
    pub fn new(delay_ms: f64) -> Result<Self, AgentError> {
        if !(delay_ms.is_finite() && delay_ms >= 0.0) {
            return Err(AgentError::invalid(
                "--pipeline-delay-ms",
                format!("{delay_ms} is not a number of milliseconds >= 0"),
            ));
        }
        Ok(Self {
            wall_at_origin: wall_clock(),
            origin: Instant::now(),
            delay_s: delay_ms / 1e3,
        })
    }

    /// The capture stamp of data arriving now.
    pub fn now(&self) -> f64 {
        self.stamp_at(Instant::now())
    }

    /// The capture stamp of data that arrived at `instant`.
    pub fn stamp_at(&self, instant: Instant) -> f64 {
        let since = instant
            .checked_duration_since(self.origin)
            .unwrap_or(Duration::ZERO);
        self.wall_at_origin + since.as_secs_f64() - self.delay_s
    }

    /// The host's Unix time at which the run started (the pacing origin of live runs).
    pub fn origin_wall(&self) -> f64 {
        self.wall_at_origin
    }

    /// Seconds since data stamped `stamp` by this clock arrived: the agent's own delay, on top of the
    /// pipeline's.
    pub fn lag(&self, stamp: f64) -> f64 {
        self.now() - stamp
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamps_are_the_host_clock_less_the_delay_and_never_go_back() {
        let clock = CaptureClock::new(120.0).unwrap();
        let first = clock.now();
        assert!((wall_clock() - 0.120 - first).abs() < 0.05);
        let later = clock.stamp_at(Instant::now() + Duration::from_millis(500));
        assert!(later - first >= 0.5);
        assert!(CaptureClock::new(-1.0).is_err());
        assert!(CaptureClock::new(f64::NAN).is_err());
    }
}
