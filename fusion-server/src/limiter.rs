//! Rate-limited logging: a bad publisher must not flood the log either.

use std::collections::HashMap;

/// Lets at most one message per `period` seconds through for each key, and counts the rest.
#[derive(Debug)]
pub struct LogLimiter {
    period: f64,
    last: HashMap<String, (f64, u64)>,
}

impl LogLimiter {
    /// A limiter letting one message per key through every `period` seconds.
    pub fn new(period: f64) -> Self {
        Self {
            period,
            last: HashMap::new(),
        }
    }

    /// Returns `Some(suppressed)` when a message for `key` may be logged at `now`, with the
    /// number of messages suppressed since the last one; `None` when it must be dropped.
    pub fn allow(&mut self, key: &str, now: f64) -> Option<u64> {
        match self.last.get_mut(key) {
            Some((at, suppressed)) if now - *at < self.period => {
                *suppressed += 1;
                None
            }
            Some((at, suppressed)) => {
                let n = *suppressed;
                *at = now;
                *suppressed = 0;
                Some(n)
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
    fn one_message_per_period_and_a_count_of_the_rest() {
        let mut limiter = LogLimiter::new(1.0);
        assert_eq!(limiter.allow("a", 0.0), Some(0));
        assert_eq!(limiter.allow("a", 0.5), None);
        assert_eq!(limiter.allow("a", 0.6), None);
        assert_eq!(limiter.allow("b", 0.6), Some(0), "keys are independent");
        assert_eq!(limiter.allow("a", 1.2), Some(2));
    }
}
