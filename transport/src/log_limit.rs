//! Rate-limited warnings: a bad publisher, a flooding sensor or a router that is away for minutes
//! costs a few log lines, not one per message.

use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Lets at most one message per `interval` through for each key, and counts the ones it held
/// back.
#[derive(Debug)]
pub struct LogLimiter {
    interval: Duration,
    /// Per key: when a message was last let through, and how many were held back since.
    last: HashMap<String, (Instant, u64)>,
}

impl LogLimiter {
    /// A limiter letting one message per key through every `interval`.
    pub fn new(interval: Duration) -> Self {
        Self {
            interval,
            last: HashMap::new(),
        }
    }

    /// `Some(n)` when a message for `key` should be logged now, `n` being the ones held back
    /// since the last one logged; `None` when it should be dropped (and counted).
    pub fn allow(&mut self, key: &str) -> Option<u64> {
        self.allow_at(key, Instant::now())
    }

    /// [`LogLimiter::allow`] at a given instant (a parameter so that tests need no sleeping).
    pub fn allow_at(&mut self, key: &str, now: Instant) -> Option<u64> {
        match self.last.get_mut(key) {
            Some((at, held_back)) if now.duration_since(*at) < self.interval => {
                *held_back += 1;
                None
            }
            Some((at, held_back)) => {
                *at = now;
                Some(std::mem::take(held_back))
            }
            None => {
                self.last.insert(key.to_string(), (now, 0));
                Some(0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_message_per_interval_and_key_and_a_count_of_the_rest() {
        let mut limiter = LogLimiter::new(Duration::from_secs(5));
        let t0 = Instant::now();
        let at = |s| t0 + Duration::from_secs(s);
        assert_eq!(limiter.allow_at("a", t0), Some(0));
        assert_eq!(limiter.allow_at("a", at(1)), None);
        assert_eq!(limiter.allow_at("a", at(4)), None);
        assert_eq!(
            limiter.allow_at("b", at(4)),
            Some(0),
            "keys are independent"
        );
        assert_eq!(limiter.allow_at("a", at(5)), Some(2));
        assert_eq!(limiter.allow_at("a", at(6)), None);
        assert_eq!(limiter.allow_at("a", at(11)), Some(1));
    }
}
