//! When a frame is published: the (scaled) wall clock must have reached its stamp.
//!
//! Stamp `s` is due at wall time `origin_wall + (s − origin_stamp) / speed`. For a simulation both origins are
//! the scenario's start, so every process given the same `--start` publishes frame k at the same moment; a
//! frame already due at launch (a `--start` in the past) is published at once, never skipped, so that `seq`
//! stays gap-free. With `--output` alone there is no pacer and frames are written as fast as possible.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::error::AgentError;

/// Maps stamps to the wall-clock instants at which they are published.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pacer {
    origin_stamp: f64,
    origin_wall: f64,
    speed: f64,
}

impl Pacer {
    /// A pacer publishing stamp `origin_stamp` at wall time `origin_wall` and later stamps `speed` times
    /// faster than real time.
    pub fn new(origin_stamp: f64, origin_wall: f64, speed: f64) -> Result<Self, AgentError> {
        check_speed(speed)?;
        if !(origin_stamp.is_finite() && origin_wall.is_finite()) {
            return Err(AgentError::invalid("--start", "must be a finite Unix time"));
        }
        Ok(Self {
            origin_stamp,
            origin_wall,
            speed,
        })
    }

    /// Wall time (Unix seconds) at which `stamp` is due.
    pub fn due(&self, stamp: f64) -> f64 {
        self.origin_wall + (stamp - self.origin_stamp) / self.speed
    }

    /// How long to wait, from wall time `now`, before publishing `stamp` (zero when already due).
    pub fn wait_from(&self, stamp: f64, now: f64) -> Duration {
        let wait = self.due(stamp) - now;
        if wait > 0.0 {
            Duration::from_secs_f64(wait)
        } else {
            Duration::ZERO
        }
    }

    /// Sleeps until `stamp` is due.
    pub async fn wait_for(&self, stamp: f64) {
        let wait = self.wait_from(stamp, wall_clock());
        if !wait.is_zero() {
            tokio::time::sleep(wait).await;
        }
    }
}

/// Rejects a `--speed` that is not a finite positive number.
pub fn check_speed(speed: f64) -> Result<(), AgentError> {
    if speed.is_finite() && speed > 0.0 {
        Ok(())
    } else {
        Err(AgentError::invalid(
            "--speed",
            format!("{speed} is not a positive number"),
        ))
    }
}

/// The shared clock: seconds since the Unix epoch.
pub fn wall_clock() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stamps_are_due_at_scaled_offsets_from_the_origin() {
        let pacer = Pacer::new(1000.0, 1000.0, 2.0).unwrap();
        assert_eq!(pacer.due(1000.0), 1000.0);
        assert_eq!(pacer.due(1010.0), 1005.0);
        assert_eq!(pacer.wait_from(1010.0, 1004.0), Duration::from_secs(1));
        assert_eq!(pacer.wait_from(1010.0, 1006.0), Duration::ZERO);
    }

    #[test]
    fn bad_speed_is_refused() {
        assert!(Pacer::new(0.0, 0.0, 0.0).is_err());
        assert!(Pacer::new(0.0, 0.0, f64::NAN).is_err());
        assert!(Pacer::new(f64::INFINITY, 0.0, 1.0).is_err());
    }
}
