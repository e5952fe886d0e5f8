//! The camera's single-view tracker: a labelled 2-D GM-PHD filter on the image plane (Pham's single-view
//! stage, thesis ch. 7), whose confirmed tracks and their 2×2 position covariances are what the camera
//! agent publishes.
//!
//! - State `[u, v, u̇, v̇]` in pixels and pixels per second, nearly constant velocity
//!   (`gmphd::ConstantVelocity` with 2 dimensions, white-noise acceleration `accel_noise` px/s²).
//! - Measurement: `gmphd::PositionSensor` of 2 dimensions over the image rectangle `[0, w] × [0, h]` (pixel
//!   coordinates taken as the "position"), noise, `p_D` and clutter from the camera's descriptor.
//! - Birth from the measurements (Ristic, Clark, Vo & Vo 2012, `gmphd::AdaptiveBirth`): each head point
//!   that the tracks do not explain seeds a newborn there for the next frame, position covariance the
//!   measurement noise, zero-mean velocity with [`BIRTH_VELOCITY_STD`]; `birth_rate` expected new heads
//!   per frame shared among the unexplained points. A head is picked up at its second detection, wherever
//!   in the image it appears, where a static grid spreads its birth mass over the whole image.
//! - Objects leave at the image's edges: outside the image a component does not survive.
//! - Survival [`SURVIVAL_PER_SECOND`] per second; prune/merge/cap 1e-5 / 4 / 100.
//! - Identities and their lifecycle from `gmphd::LabelledTracker` (label continuity, Pham ch. 4, and the
//!   track manager): a label is confirmed when its weight exceeds `extraction_threshold` in
//!   [`CONFIRM_HITS`] of the last [`CONFIRM_WINDOW`] frames. Only confirmed tracks are published, so a
//!   false box, which seeds a newborn that the next frame does not find again, never shows.
//! - A confirmed track that misses its detection is carried for up to [`MAX_COAST_S`]: published at its
//!   predicted position with the covariance the prediction grew, until a detection takes it up again.

use gmphd::tracks::TrackManagerConfig;
use gmphd::{
    AdaptiveBirthConfig, BirthTiming, ConstantVelocity, Detection, FilterConfig, GmPhdFilter,
    LabelledTracker, Measurement, MixtureBirth, PositionSensor, PruneMergeCap, Survival,
    SurvivalRegion, TrackerConfig,
};
use nalgebra::DVector;
use protocol::CameraModel;

use crate::error::AgentError;

/// Default white-noise acceleration, px/s² (`--accel-noise`).
pub const DEFAULT_ACCEL_NOISE: f64 = 200.0;
/// Default expected new heads per frame (`--birth-rate`).
pub const DEFAULT_BIRTH_RATE: f64 = 0.1;
/// Default weight of a label that counts as a detection of its track (`--extraction-threshold`).
pub const DEFAULT_EXTRACTION_THRESHOLD: f64 = 0.5;
/// Probability that a tracked head is still in view one second later.
pub const SURVIVAL_PER_SECOND: f64 = 0.9;
/// Spread of a newborn head's image velocity, px/s.
pub const BIRTH_VELOCITY_STD: f64 = 100.0;
/// Frames looked at for confirmation, and the hits among them that confirm a track.
pub const CONFIRM_WINDOW: usize = 3;
/// See [`CONFIRM_WINDOW`].
pub const CONFIRM_HITS: usize = 2;
/// Longest time a confirmed track is published without a detection, s.
pub const MAX_COAST_S: f64 = 0.2;
/// A label lighter than this counts as missed (one miss at `p_D` 0.9 leaves 0.1).
const DELETE_THRESHOLD: f64 = 0.15;
/// Time without detection after which a track is deleted, s.
const DELETE_AFTER_S: f64 = 0.5;
/// Interval assumed before the first frame.
const FIRST_INTERVAL_S: f64 = 0.04;

/// The tracker's tunable settings (the command-line flags).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingleViewSettings {
    /// White-noise acceleration on the image plane, px/s².
    pub accel_noise: f64,
    /// Expected new objects per frame over the whole image.
    pub birth_rate: f64,
    /// A label whose weight exceeds this in a frame counts as detected there.
    pub extraction_threshold: f64,
}

/// One frame's output: estimated head points and their covariances.
#[derive(Debug, Clone, PartialEq)]
pub struct SingleViewEstimates {
    /// `[u, v]` per estimate.
    pub points: Vec<Vec<f64>>,
    /// The 2×2 position covariance (rows) of each estimate.
    pub covariances: Vec<Vec<Vec<f64>>>,
}

/// A labelled 2-D GM-PHD tracker on one camera's image plane.
pub struct SingleViewTracker {
    sensor: PositionSensor,
    image: [f64; 2],
    tracker: LabelledTracker,
}

impl SingleViewTracker {
    /// A tracker for the camera `camera` with detection probability `p_d` and `clutter_rate` per frame.
    pub fn new(
        camera: &CameraModel,
        p_d: f64,
        clutter_rate: f64,
        settings: SingleViewSettings,
    ) -> Result<Self, AgentError> {
        check_settings(&settings)?;
        let image = camera.image_size.map(f64::from);
        let sensor = PositionSensor::new(
            &camera.noise_std,
            &[0.0, 0.0],
            &image,
            Detection::new(p_d, clutter_rate)?,
        )?;
        let tracker =
            LabelledTracker::new(build_filter(&settings, image)?, tracker_config(&settings))
                .map_err(|e| AgentError::invalid("camera tracker", e.to_string()))?;
        Ok(Self {
            sensor,
            image,
            tracker,
        })
    }

    /// Runs one frame of head points (pixels) taken at `stamp` through the tracker and returns its
    /// confirmed tracks: those detected within the last [`MAX_COAST_S`], inside the image.
    pub fn step(
        &mut self,
        stamp: f64,
        points: &[[f64; 2]],
    ) -> Result<SingleViewEstimates, AgentError> {
        let measurements: Vec<Measurement> = points
            .iter()
            .map(|p| Measurement::new(DVector::from_column_slice(p)))
            .collect();
        self.tracker
            .step(stamp, &self.sensor, &measurements)
            .map_err(|e| AgentError::invalid("camera tracker", e.to_string()))?;
        let mut out = SingleViewEstimates {
            points: Vec::new(),
            covariances: Vec::new(),
        };
        let [width, height] = self.image;
        for track in self.tracker.confirmed_tracks() {
            let (u, v) = (track.mean[0], track.mean[1]);
            let inside = (0.0..=width).contains(&u) && (0.0..=height).contains(&v);
            if !inside || stamp - track.last_update > MAX_COAST_S + 1e-9 {
                continue;
            }
            let p = &track.cov;
            // The symmetric part: the filter's arithmetic may leave asymmetry in the last bits.
            let off_diagonal = 0.5 * (p[(0, 1)] + p[(1, 0)]);
            out.points.push(vec![u, v]);
            out.covariances.push(vec![
                vec![p[(0, 0)], off_diagonal],
                vec![off_diagonal, p[(1, 1)]],
            ]);
        }
        Ok(out)
    }
}

/// Refuses a setting that is not a positive number, naming its flag.
fn check_settings(settings: &SingleViewSettings) -> Result<(), AgentError> {
    for (flag, value) in [
        ("--accel-noise", settings.accel_noise),
        ("--birth-rate", settings.birth_rate),
        ("--extraction-threshold", settings.extraction_threshold),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(AgentError::invalid(
                flag,
                format!("{value} is not a positive number"),
            ));
        }
    }
    if settings.extraction_threshold >= 1.0 {
        return Err(AgentError::invalid(
            "--extraction-threshold",
            format!("{} is not below 1", settings.extraction_threshold),
        ));
    }
    Ok(())
}

/// The filter: nearly constant velocity, births from the measurements, death at the image's edges.
fn build_filter(settings: &SingleViewSettings, image: [f64; 2]) -> Result<GmPhdFilter, AgentError> {
    let motion = ConstantVelocity::new(2, settings.accel_noise)?;
    let no_static_birth = MixtureBirth::new(4, Vec::new(), BirthTiming::PerStep)?;
    let reducer = PruneMergeCap::new(1e-5, 4.0, 100)?;
    let config = FilterConfig {
        survival: Survival::PerSecond(SURVIVAL_PER_SECOND),
        unscented: Default::default(),
    };
    let birth = AdaptiveBirthConfig {
        rate: settings.birth_rate,
        position_inflation: 1.0,
        velocity_std: BIRTH_VELOCITY_STD,
        extra_std: 0.0,
        min_weight: 1e-6,
    };
    Ok(GmPhdFilter::new(
        Box::new(motion),
        Box::new(no_static_birth),
        Box::new(reducer),
        config,
        0.0,
    )?
    .with_adaptive_birth(birth)?
    .with_survival_region(SurvivalRegion::new(vec![0.0, 0.0], image.to_vec())?)?)
}

/// Label continuity and the track lifecycle of the single view.
fn tracker_config(settings: &SingleViewSettings) -> TrackerConfig {
    let threshold = settings.extraction_threshold;
    TrackerConfig {
        extraction_threshold: threshold,
        merge_threshold: 4.0,
        first_interval_s: FIRST_INTERVAL_S,
        tracks: TrackManagerConfig {
            confirm_threshold: threshold,
            confirm_window: CONFIRM_WINDOW,
            confirm_hits: CONFIRM_HITS,
            confirm_at_once_threshold: None,
            delete_threshold: DELETE_THRESHOLD.min(threshold),
            delete_after_sets: usize::MAX,
            max_coast_s: DELETE_AFTER_S,
        },
        ..TrackerConfig::default()
    }
}

#[cfg(test)]
#[path = "camera_tracker_crowd_tests.rs"]
mod crowd_tests;

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> CameraModel {
        CameraModel {
            projection: [
                [500.0, 0.0, 320.0, 0.0],
                [0.0, 500.0, 240.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
            ],
            image_size: [640, 480],
            noise_std: [3.0, 3.0],
        }
    }

    #[test]
    fn a_steadily_seen_head_becomes_one_estimate_near_it() {
        let settings = SingleViewSettings {
            accel_noise: 200.0,
            birth_rate: 0.05,
            extraction_threshold: 0.5,
        };
        let mut tracker = SingleViewTracker::new(&camera(), 0.95, 0.5, settings).unwrap();
        let mut last = None;
        for k in 0..20 {
            let t = 100.0 + k as f64 * 0.04;
            let u = 200.0 + 50.0 * (t - 100.0);
            last = Some(tracker.step(t, &[[u, 150.0]]).unwrap());
        }
        let last = last.unwrap();
        assert_eq!(last.points.len(), 1, "{last:?}");
        let expected_u = 200.0 + 50.0 * 0.76;
        assert!((last.points[0][0] - expected_u).abs() < 5.0, "{last:?}");
        assert!((last.points[0][1] - 150.0).abs() < 5.0, "{last:?}");
        let c = &last.covariances[0];
        assert_eq!(c[0][1], c[1][0]);
        assert!(
            c[0][0] > 0.0 && c[0][0] < 9.0,
            "posterior variance {c:?} not below the noise"
        );
    }

    #[test]
    fn a_confirmed_head_is_carried_through_a_missed_detection_and_a_lone_false_box_never_shows() {
        let mut tracker = SingleViewTracker::new(&camera(), 0.9, 2.0, default_settings()).unwrap();
        let dt = 0.04;
        let head = |k: usize| [200.0 + 2.0 * k as f64, 150.0];
        let mut seen = None;
        for k in 0..10 {
            // A false box somewhere new in every frame.
            let false_box = [50.0 + 37.0 * k as f64, 400.0 - 23.0 * k as f64];
            let out = tracker.step(k as f64 * dt, &[head(k), false_box]).unwrap();
            assert!(out.points.len() <= 1, "frame {k}: {out:?}");
            seen = Some(out);
        }
        let seen = seen.unwrap();
        let missed = tracker.step(10.0 * dt, &[]).unwrap();
        println!("seen {seen:?}\nmissed {missed:?}");
        assert_eq!(
            missed.points.len(),
            1,
            "the head is dropped at its first miss"
        );
        let predicted_u = head(10)[0];
        assert!(
            (missed.points[0][0] - predicted_u).abs() < 2.0,
            "{missed:?}"
        );
        assert!(missed.covariances[0][0][0] > seen.covariances[0][0][0]);
        let gone = (11..20)
            .map(|k| tracker.step(k as f64 * dt, &[]).unwrap().points.len())
            .collect::<Vec<_>>();
        println!("estimates while unseen: {gone:?}");
        assert_eq!(
            gone.last(),
            Some(&0),
            "a head unseen for 0.36 s is still published"
        );
    }

    fn default_settings() -> SingleViewSettings {
        SingleViewSettings {
            accel_noise: DEFAULT_ACCEL_NOISE,
            birth_rate: DEFAULT_BIRTH_RATE,
            extraction_threshold: DEFAULT_EXTRACTION_THRESHOLD,
        }
    }

    #[test]
    fn non_positive_settings_are_refused() {
        let settings = SingleViewSettings {
            accel_noise: 0.0,
            birth_rate: 0.05,
            extraction_threshold: 0.5,
        };
        assert!(SingleViewTracker::new(&camera(), 0.95, 0.5, settings).is_err());
    }
}
