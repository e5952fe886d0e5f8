//! Keeps a front end's descriptor honest: its `clutter_rate` and `detection_probability` are what the user
//! gave (or the agent's defaults) to start with, and are then refined from what the front end actually emits
//! ([`RateEstimator`], `calibration.rs`). When the estimate drifts from the announced figures the agent logs
//! it and, unless `--keep-descriptor` was given, announces the estimate as its new descriptor.
//!
//! Drift is checked every [`CHECK_INTERVAL_S`] seconds of the sensor's stamps once the estimator has enough
//! frames; it counts when the clutter rate differs by more than `max(0.3, 25 %)` or the detection
//! probability by more than 0.1. The tolerance keeps the descriptor from changing at every check, since each
//! change is a new measurement model in the filter. The interval is in seconds, not frames, so that a slow
//! front end is calibrated as soon as a fast one: a microphone pair's 0.256 s frames reach the estimator's
//! 60 frames after 15 s, and with a check every 50 frames its first estimate waited until 25.6 s. Until then
//! the filter works with the user's figures; on two-talker speech synthesized elsewhere
//! (`tools/speech_scene`, 15 scenes) the earlier estimate takes the count right from 56 to 63 %, on the
//! rendered default room (seeds 1–5) from 49.5 to 53 %.
//!
//! A front end that reports its own account of each set (`front_end_report.rs`: the camera's
//! multi-Bernoulli image tracker) is calibrated from those reports instead of from persistence, with
//! the same checks and tolerances.

use protocol::{SensorDescriptor, SensorModel};
use transport::LogLimiter;

use crate::calibration::{Estimate, RateEstimator};
use crate::front_end_report::{FrontEndReport, ReportWindow};

/// Seconds of the sensor's stamps between two drift checks.
pub const CHECK_INTERVAL_S: f64 = 2.5;
/// Smallest clutter-rate difference that counts as drift.
const CLUTTER_TOLERANCE: f64 = 0.3;
/// Relative clutter-rate difference that counts as drift.
const CLUTTER_RELATIVE_TOLERANCE: f64 = 0.25;
/// Detection-probability difference that counts as drift.
const DETECTION_TOLERANCE: f64 = 0.1;
/// How fast a walking person's head moves, m/s (the drift a camera or LIDAR reading of it may show).
const WALKING_SPEED: f64 = 1.5;
/// How fast a talker's direction seen from a microphone pair turns, rad/s (a talker moves slowly while
/// speaking).
const TALKER_TURN_RATE: f64 = 0.25;
/// Typical distance from a camera to the people it watches, m (turns a walking speed into pixels).
const CAMERA_DISTANCE: f64 = 3.0;

/// What the agent does when its front end and its descriptor disagree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalibrationMode {
    /// Announce the estimate as the new descriptor (the default).
    Update,
    /// Keep the descriptor; only log the drift.
    LogOnly,
}

/// One sensor's running calibration.
pub struct DescriptorCalibration {
    estimator: RateEstimator,
    /// The front end's own reports, once it sends them (they then replace the persistence estimate).
    reports: Option<ReportWindow>,
    announced: SensorDescriptor,
    mode: CalibrationMode,
    /// The stamp of the last drift check.
    last_check: Option<f64>,
    drift_log: LogLimiter,
}

impl DescriptorCalibration {
    /// A calibration starting from `descriptor`; `None` for sensor kinds whose readings it cannot gate
    /// (positions and bearing–range sensors are taken as the user gives them).
    pub fn new(descriptor: &SensorDescriptor, mode: CalibrationMode) -> Option<Self> {
        Some(Self {
            estimator: estimator_for(&descriptor.model)?,
            reports: None,
            announced: descriptor.clone(),
            mode,
            last_check: None,
            drift_log: LogLimiter::new(std::time::Duration::from_secs(30)),
        })
    }

    /// Takes one emitted frame; returns a descriptor to announce when the figures drifted and the mode says so.
    /// Ignored once the front end sends its own reports.
    pub fn observe(&mut self, stamp: f64, measurements: &[Vec<f64>]) -> Option<SensorDescriptor> {
        if self.reports.is_some() {
            return None;
        }
        self.estimator.observe(stamp, measurements);
        if !self.check_due(stamp) {
            return None;
        }
        let estimate = self.estimator.estimate()?;
        self.check(&estimate)
    }

    /// Takes the front end's report of its set stamped `stamp`; returns a descriptor to announce as
    /// [`DescriptorCalibration::observe`] does.
    pub fn observe_report(
        &mut self,
        stamp: f64,
        report: FrontEndReport,
    ) -> Option<SensorDescriptor> {
        self.reports
            .get_or_insert_with(ReportWindow::default)
            .push(report);
        if !self.check_due(stamp) {
            return None;
        }
        let estimate = self.reports.as_ref()?.estimate()?;
        self.check(&estimate)
    }

    /// Whether [`CHECK_INTERVAL_S`] has passed between the last check and the frame stamped `now` (the
    /// first frame starts the clock); if so, the check is taken as done now.
    fn check_due(&mut self, now: f64) -> bool {
        let last = *self.last_check.get_or_insert(now);
        if (now - last).abs() < CHECK_INTERVAL_S {
            return false;
        }
        self.last_check = Some(now);
        true
    }

    /// Logs a drift of `estimate` from the announced figures and, in update mode, returns the new
    /// descriptor.
    fn check(&mut self, estimate: &Estimate) -> Option<SensorDescriptor> {
        if !drifted(&self.announced, estimate) {
            return None;
        }
        self.report(estimate);
        if self.mode == CalibrationMode::LogOnly {
            return None;
        }
        self.announced.clutter_rate = round_to(estimate.clutter_rate, 0.05);
        self.announced.detection_probability = round_to(estimate.detection_probability, 0.01);
        Some(self.announced.clone())
    }

    fn report(&mut self, estimate: &Estimate) {
        let Some(suppressed) = self.drift_log.allow("drift") else {
            return;
        };
        tracing::warn!(
            sensor = %self.announced.sensor,
            announced_clutter = self.announced.clutter_rate,
            measured_clutter = format!("{:.2}", estimate.clutter_rate),
            announced_detection = self.announced.detection_probability,
            measured_detection = format!("{:.2}", estimate.detection_probability),
            frames = estimate.frames,
            action = match self.mode {
                CalibrationMode::Update => "announcing the measured figures",
                CalibrationMode::LogOnly => "keeping the descriptor",
            },
            suppressed,
            "the front end's output and its descriptor disagree"
        );
    }
}

/// Whether the estimate is far enough from the announced figures to count as drift.
fn drifted(announced: &SensorDescriptor, estimate: &Estimate) -> bool {
    let clutter_tolerance =
        CLUTTER_TOLERANCE.max(CLUTTER_RELATIVE_TOLERANCE * announced.clutter_rate);
    (estimate.clutter_rate - announced.clutter_rate).abs() > clutter_tolerance
        || (estimate.detection_probability - announced.detection_probability).abs()
            > DETECTION_TOLERANCE
}

fn round_to(value: f64, step: f64) -> f64 {
    (value / step).round() * step
}

/// The estimator for a sensor model: its noise, how fast a moving person's reading drifts, and the width
/// of its measurement region, per coordinate.
fn estimator_for(model: &SensorModel) -> Option<RateEstimator> {
    match model {
        SensorModel::Camera(camera) => {
            let pixels = WALKING_SPEED * focal_length(&camera.projection) / CAMERA_DISTANCE;
            let [w, h] = camera.image_size.map(f64::from);
            Some(RateEstimator::new(
                &camera.noise_std,
                &[pixels, pixels],
                &[w, h],
            ))
        }
        SensorModel::MicPair(pair) => {
            let max_delay = pair.baseline() / pair.speed_of_sound;
            Some(RateEstimator::new(
                &[pair.noise_std],
                &[max_delay * TALKER_TURN_RATE],
                &[2.0 * max_delay],
            ))
        }
        SensorModel::Lidar(lidar) => {
            let span = lidar.elevation_limits[1] - lidar.elevation_limits[0];
            Some(RateEstimator::new(
                &lidar.noise_std,
                // Range, azimuth and elevation drift of a person walking at 1.5 m/s a metre or more away.
                &[WALKING_SPEED, WALKING_SPEED, WALKING_SPEED],
                &[lidar.max_range, std::f64::consts::TAU, span.max(1e-3)],
            ))
        }
        SensorModel::BearingRange(_) | SensorModel::Position(_) => None,
    }
}

/// The focal length in pixels of a projection `P = s·K·[R | t]` (zero skew): with the rows `a_i` of its
/// left 3 × 3 block scaled so that `|a_2| = 1`, `c_x = a_0 · a_2` and `f² = |a_0|² − c_x²`.
fn focal_length(projection: &[[f64; 4]; 3]) -> f64 {
    let row = |i: usize| &projection[i][..3];
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let scale = dot(row(2), row(2)).sqrt().max(f64::MIN_POSITIVE);
    let cx = dot(row(0), row(2)) / (scale * scale);
    (dot(row(0), row(0)) / (scale * scale) - cx * cx)
        .max(1.0)
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mic_pair_descriptor() -> SensorDescriptor {
        let json = r#"{"version": 1, "site": "room", "sensor": "mics_s",
            "model": {"kind": "mic_pair", "mics": [[1.25, 0.0, 1.5], [1.75, 0.0, 1.5]],
                      "speed_of_sound": 343.0, "noise_std": 6.25e-05},
            "detection_probability": 0.7, "clutter_rate": 1.0}"#;
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn checks_come_every_interval_of_the_stamps_whatever_the_frame_rate() {
        let mut calibration =
            DescriptorCalibration::new(&mic_pair_descriptor(), CalibrationMode::Update).unwrap();
        let due: Vec<f64> = [0.0, 1.0, 2.4, 2.5, 3.0, 4.9, 5.0, 9.0]
            .into_iter()
            .filter(|&stamp| calibration.check_due(stamp))
            .collect();
        assert_eq!(due, vec![2.5, 5.0, 9.0]);
    }

    #[test]
    fn a_slow_front_end_is_calibrated_soon_after_enough_frames() {
        // A microphone pair's 0.256 s frames: one talker always heard at the same TDOA, and a second
        // measurement that wanders over the whole range (clutter), so the estimate (p_D ≈ 1, clutter
        // ≈ 1 per frame) drifts from the announced 0.7 once the estimator has its frames.
        let mut calibration =
            DescriptorCalibration::new(&mic_pair_descriptor(), CalibrationMode::Update).unwrap();
        let max_delay = 0.5 / 343.0;
        let first = (0..400).find_map(|k| {
            let clutter = max_delay * (2.0 * ((k * 37 % 101) as f64 / 101.0) - 1.0);
            let frame = [vec![2e-4], vec![clutter]];
            calibration
                .observe(k as f64 * 0.256, &frame)
                .map(|d| (k, d))
        });
        let (frame, descriptor) = first.expect("the drift is announced");
        let settle = (CHECK_INTERVAL_S / 0.256).ceil() as usize;
        assert!(
            frame < crate::calibration::MIN_FRAMES + settle,
            "announced at frame {frame}"
        );
        assert!(descriptor.detection_probability > 0.85);
    }

    #[test]
    fn focal_length_of_a_look_at_camera() {
        let pose = simulator::LookAt {
            eye: [0.0, 0.0, 2.5],
            target: [1.5, 1.0, 1.2],
            focal_px: 500.0,
            image_size: [640, 480],
        };
        let projection = simulator::look_at_projection(&pose);
        assert!((focal_length(&projection) - 500.0).abs() < 1e-6);
        let scaled = projection.map(|row| row.map(|v| 3.0 * v));
        assert!((focal_length(&scaled) - 500.0).abs() < 1e-6);
    }
}
