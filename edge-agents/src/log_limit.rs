//! Rate limiting of repeated warnings, so a router that is away for minutes costs a few log lines, not one
//! per frame.

use std::time::{Duration, Instant};

/// Lets one message through per `interval` and counts the ones it held back.
#[derive(Debug)]
pub struct LogLimiter {
    interval: Duration,
    last: Option<Instant>,
    suppressed: u64,
}

impl LogLimiter {
    /// A limiter letting at most one message through per `interval`.
    pub fn new(interval: Duration) -> Self {
        Self {
            interval,
            last: None,
            suppressed: 0,
        }
    }

    /// `Some(n)` when this occurrence should be logged, `n` being the occurrences held back since the last
    /// one logged; `None` when it should be dropped (and counted).
    pub fn allow(&mut self) -> Option<u64> {
        self.allow_at(Instant::now())
    }

    /// [`LogLimiter::allow`] at a given instant (the clock is a parameter so that tests need no sleeping).
    pub fn allow_at(&mut self, now: Instant) -> Option<u64> {
        let due = self
            .last
            .is_none_or(|last| now.duration_since(last) >= self.interval);
        if due {
            self.last = Some(now);
            Some(std::mem::take(&mut self.suppressed))
        } else {
            self.suppressed += 1;
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lets_one_through_per_interval_and_counts_the_rest() {
        let mut limiter = LogLimiter::new(Duration::from_secs(5));
        let t0 = Instant::now();
        assert_eq!(limiter.allow_at(t0), Some(0));
        assert_eq!(limiter.allow_at(t0 + Duration::from_secs(1)), None);
        assert_eq!(limiter.allow_at(t0 + Duration::from_secs(4)), None);
        assert_eq!(limiter.allow_at(t0 + Duration::from_secs(5)), Some(2));
        assert_eq!(limiter.allow_at(t0 + Duration::from_secs(6)), None);
        assert_eq!(limiter.allow_at(t0 + Duration::from_secs(11)), Some(1));
    }
}
