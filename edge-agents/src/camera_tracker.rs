//! The camera's single-view tracker: a small 2-D GM-PHD filter on the image plane (Pham's single-view stage,
//! thesis ch. 7), whose estimates and their 2×2 position covariances are what the camera agent publishes.
//!
//! - State `[u, v, u̇, v̇]` in pixels and pixels per second, nearly constant velocity
//!   (`gmphd::ConstantVelocity` with 2 dimensions, white-noise acceleration `accel_noise` px/s²).
//! - Measurement: `gmphd::PositionSensor` of 2 dimensions over the image rectangle `[0, w] × [0, h]` (pixel
//!   coordinates taken as the "position"), noise, `p_D` and clutter from the camera's descriptor.
//! - Birth: `gmphd::GridBirth`, an 8 × 6 grid of components over the image, each with a position spread of
//!   half a cell and a velocity spread of [`BIRTH_VELOCITY_STD`]; `birth_rate` expected births per frame
//!   over the whole image (a birth grid rather than measurement-driven birth: that is what gmphd offers, and
//!   it keeps the filter a pure function of its input).
//! - Survival [`SURVIVAL_PER_SECOND`] per second, prune/merge/cap 1e-5 / 4 / 100, extraction by label mass
//!   above `extraction_threshold` (`gmphd::WeightThresholdExtractor`).

use gmphd::extract::{StateExtractor, WeightThresholdExtractor};
use gmphd::{
    BirthTiming, ConstantVelocity, Detection, FilterConfig, GmPhdFilter, GridBirth,
    GridBirthConfig, Measurement, PositionSensor, PruneMergeCap, Survival,
};
use nalgebra::DVector;
use protocol::CameraModel;

use crate::error::AgentError;

/// Probability that a tracked head is still in view one second later.
pub const SURVIVAL_PER_SECOND: f64 = 0.9;
/// Spread of a newborn head's image velocity, px/s.
pub const BIRTH_VELOCITY_STD: f64 = 100.0;
/// Birth grid cells along the image's width and height.
const BIRTH_CELLS: [usize; 2] = [8, 6];
/// Interval assumed before the first frame, so that its prediction already adds births.
const FIRST_INTERVAL_S: f64 = 0.04;

/// The tracker's tunable settings (the command-line flags).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingleViewSettings {
    /// White-noise acceleration on the image plane, px/s².
    pub accel_noise: f64,
    /// Expected new objects per frame over the whole image.
    pub birth_rate: f64,
    /// A label whose mass exceeds this gives an estimate.
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

/// A 2-D GM-PHD filter on one camera's image plane.
pub struct SingleViewTracker {
    settings: SingleViewSettings,
    camera: CameraModel,
    sensor: PositionSensor,
    extractor: WeightThresholdExtractor,
    /// Built at the first frame, whose stamp starts the filter's clock.
    filter: Option<GmPhdFilter>,
}

impl SingleViewTracker {
    /// A tracker for the camera `camera` with detection probability `p_d` and `clutter_rate` per frame.
    pub fn new(
        camera: &CameraModel,
        p_d: f64,
        clutter_rate: f64,
        settings: SingleViewSettings,
    ) -> Result<Self, AgentError> {
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
        let [width, height] = camera.image_size.map(f64::from);
        let sensor = PositionSensor::new(
            &camera.noise_std,
            &[0.0, 0.0],
            &[width, height],
            Detection::new(p_d, clutter_rate)?,
        )?;
        let extractor = WeightThresholdExtractor {
            threshold: settings.extraction_threshold,
            ..WeightThresholdExtractor::default()
        };
        let tracker = Self {
            settings,
            camera: camera.clone(),
            sensor,
            extractor,
            filter: None,
        };
        // Build a filter once now so that bad settings fail at start, not at the first frame.
        tracker.build_filter(0.0)?;
        Ok(tracker)
    }

    /// Runs one frame of head points (pixels) taken at `stamp` through the filter and returns its estimates.
    pub fn step(
        &mut self,
        stamp: f64,
        points: &[[f64; 2]],
    ) -> Result<SingleViewEstimates, AgentError> {
        let filter = match &mut self.filter {
            Some(filter) => filter,
            None => self
                .filter
                .insert(self.build_filter(stamp - FIRST_INTERVAL_S)?),
        };
        let measurements: Vec<Measurement> = points
            .iter()
            .map(|p| Measurement::new(DVector::from_column_slice(p)))
            .collect();
        filter.predict_to(stamp)?;
        filter.update(&self.sensor, &measurements)?;
        filter.reduce();
        let estimates = self
            .extractor
            .extract(filter.intensity())
            .map_err(|e| AgentError::invalid("camera tracker extraction", e.to_string()))?;
        let mut out = SingleViewEstimates {
            points: Vec::with_capacity(estimates.len()),
            covariances: Vec::with_capacity(estimates.len()),
        };
        for estimate in estimates {
            let p = &estimate.cov;
            // The symmetric part: the filter's arithmetic may leave asymmetry in the last bits.
            let off_diagonal = 0.5 * (p[(0, 1)] + p[(1, 0)]);
            out.points.push(vec![estimate.mean[0], estimate.mean[1]]);
            out.covariances.push(vec![
                vec![p[(0, 0)], off_diagonal],
                vec![off_diagonal, p[(1, 1)]],
            ]);
        }
        Ok(out)
    }

    /// A fresh filter whose clock starts at `start_time`.
    fn build_filter(&self, start_time: f64) -> Result<GmPhdFilter, AgentError> {
        let [width, height] = self.camera.image_size.map(f64::from);
        let motion = ConstantVelocity::new(2, self.settings.accel_noise)?;
        let birth = GridBirth::new(&GridBirthConfig {
            region_min: vec![0.0, 0.0],
            region_max: vec![width, height],
            cells: BIRTH_CELLS.to_vec(),
            state_dim: 4,
            velocity_std: BIRTH_VELOCITY_STD,
            extra_std: 0.0,
            total_rate: self.settings.birth_rate,
            timing: BirthTiming::PerStep,
        })?;
        let reducer = PruneMergeCap::new(1e-5, 4.0, 100)?;
        let config = FilterConfig {
            survival: Survival::PerSecond(SURVIVAL_PER_SECOND),
            unscented: Default::default(),
        };
        Ok(GmPhdFilter::new(
            Box::new(motion),
            Box::new(birth),
            Box::new(reducer),
            config,
            start_time,
        )?)
    }
}

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
    fn non_positive_settings_are_refused() {
        let settings = SingleViewSettings {
            accel_noise: 0.0,
            birth_rate: 0.05,
            extraction_threshold: 0.5,
        };
        assert!(SingleViewTracker::new(&camera(), 0.95, 0.5, settings).is_err());
    }
}
