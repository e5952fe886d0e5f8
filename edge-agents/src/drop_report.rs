//! Whole frames (or scans) that a live reader dropped because the analysis fell behind: counted by
//! the reader thread, which never waits, and reported, rate-limited, by the analysis side.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use transport::LogLimiter;

/// At most one report of drops per this interval.
const REPORT_INTERVAL: Duration = Duration::from_secs(5);

/// The analysis side of a drop counter.
#[derive(Debug)]
pub struct DropReport {
    dropped: Arc<AtomicU64>,
    reported: u64,
    limiter: LogLimiter,
}

impl DropReport {
    /// A report and the counter its reader thread increments.
    pub fn new() -> (Self, Arc<AtomicU64>) {
        let dropped = Arc::new(AtomicU64::new(0));
        let report = Self {
            dropped: Arc::clone(&dropped),
            reported: 0,
            limiter: LogLimiter::new(REPORT_INTERVAL),
        };
        (report, dropped)
    }

    /// Everything dropped so far.
    pub fn total(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// `Some((total, since the last report))` when there are new drops and a report is due.
    pub fn due(&mut self) -> Option<(u64, u64)> {
        let total = self.total();
        if total > self.reported && self.limiter.allow("dropped").is_some() {
            let new = total - self.reported;
            self.reported = total;
            Some((total, new))
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_new_drops_once_per_interval() {
        let (mut report, counter) = DropReport::new();
        assert_eq!(report.due(), None);
        counter.fetch_add(3, Ordering::Relaxed);
        assert_eq!(report.due(), Some((3, 3)));
        counter.fetch_add(1, Ordering::Relaxed);
        assert_eq!(report.due(), None, "within the interval");
        assert_eq!(report.total(), 4);
    }
}
