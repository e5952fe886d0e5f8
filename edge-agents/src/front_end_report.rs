//! A front end that filters over time (the camera's multi-Bernoulli image tracker) knows what its output
//! is worth better than the persistence estimate of `calibration.rs` can tell from outside: a false
//! track of a filter persists like a person. Such a front end reports, with each set, its own account of
//! it, and the descriptor's figures are the running means of those accounts:
//!
//! - clutter rate: the expected number of false measurements per set, `Σ (1 − r)` over the published
//!   estimates (`r` their existence probabilities), but never below [`MIN_CLUTTER_RATE`]: a filter sure
//!   of its tracks has no way to count the ones it is wrongly sure of, nor the estimates it places
//!   wrongly (on the rendered room the camera's image tracker publishes 0.00 to 0.57 points per set
//!   away from every head, where `Σ (1 − r)` says about 0.01);
//! - detection probability: of the people the filter holds in the view (`Σ r` over its confirmed
//!   estimates, hidden ones included), the share it published (`Σ r` over the published ones), within
//!   [`P_BOUNDS`].
//!
//! Both over the last [`WINDOW_SETS`] sets, once [`MIN_SETS`] sets with someone in view are in.

use std::collections::VecDeque;

use crate::calibration::Estimate;

/// Sets the figures are taken over.
pub const WINDOW_SETS: usize = 250;
/// Sets with someone in view needed before the figures are used.
pub const MIN_SETS: usize = 50;
/// The clutter rate announced is at least this, per set (the order of the misplaced estimates a
/// filter cannot see; with 0.05 instead, the rendered room's fused count was right in 81–84 % of the
/// track sets of two seeds instead of 84–87 %).
pub const MIN_CLUTTER_RATE: f64 = 0.3;
/// The detection probability announced stays within these bounds.
pub const P_BOUNDS: (f64, f64) = (0.05, 0.99);

/// A front end's own account of one set it emitted.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrontEndReport {
    /// Expected number of the set's measurements that are not of an object.
    pub expected_false: f64,
    /// Expected number of objects in the sensor's view.
    pub objects_in_view: f64,
    /// Expected number of those the set has a measurement of.
    pub objects_measured: f64,
}

/// The running figures of a front end's reports.
#[derive(Debug, Clone, Default)]
pub struct ReportWindow {
    reports: VecDeque<FrontEndReport>,
}

impl ReportWindow {
    /// Adds one set's report (the oldest beyond the window goes).
    pub fn push(&mut self, report: FrontEndReport) {
        self.reports.push_back(report);
        if self.reports.len() > WINDOW_SETS {
            self.reports.pop_front();
        }
    }

    /// The figures, once enough sets with someone in view are in.
    pub fn estimate(&self) -> Option<Estimate> {
        let occupied = self
            .reports
            .iter()
            .filter(|r| r.objects_in_view > 0.5)
            .count();
        if occupied < MIN_SETS {
            return None;
        }
        let n = self.reports.len() as f64;
        let false_sum: f64 = self.reports.iter().map(|r| r.expected_false).sum();
        let in_view: f64 = self.reports.iter().map(|r| r.objects_in_view).sum();
        let measured: f64 = self.reports.iter().map(|r| r.objects_measured).sum();
        Some(Estimate {
            clutter_rate: (false_sum / n).max(MIN_CLUTTER_RATE),
            detection_probability: (measured / in_view).clamp(P_BOUNDS.0, P_BOUNDS.1),
            frames: self.reports.len(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_figures_are_the_reports_running_means_within_their_bounds() {
        let mut window = ReportWindow::default();
        let report = FrontEndReport {
            expected_false: 0.6,
            objects_in_view: 2.0,
            objects_measured: 1.6,
        };
        for _ in 0..MIN_SETS - 1 {
            window.push(report);
        }
        assert!(window.estimate().is_none());
        window.push(report);
        let estimate = window.estimate().unwrap();
        assert!((estimate.clutter_rate - 0.6).abs() < 1e-9);
        assert!((estimate.detection_probability - 0.8).abs() < 1e-9);
        for _ in 0..WINDOW_SETS {
            window.push(FrontEndReport {
                expected_false: 0.0,
                objects_in_view: 1.0,
                objects_measured: 1.0,
            });
        }
        let estimate = window.estimate().unwrap();
        assert_eq!(estimate.clutter_rate, MIN_CLUTTER_RATE);
        assert_eq!(estimate.detection_probability, P_BOUNDS.1);
        assert_eq!(estimate.frames, WINDOW_SETS);
    }
}
