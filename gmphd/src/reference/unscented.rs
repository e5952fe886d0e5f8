//! The plain unscented projection of a component into a sensor's measurement space.

use nalgebra::DVector;

use crate::error::FilterError;
use crate::gaussian::Gaussian;
use crate::measurement::MeasurementModel;
use crate::motion::MotionModel;
use crate::ukf::{SigmaPoints, UnscentedParams, UnscentedResult};

/// The predicted measurement of `component` through `motion` (state to world point) and
/// `sensor`, its covariance without noise and its cross-covariance with the state: the
/// scaled unscented transform through all 2n + 1 sigma points, with the sensor's residual
/// (angles wrapped) for every difference of measurements.
pub fn unscented_moments(
    component: &Gaussian,
    motion: &dyn MotionModel,
    sensor: &dyn MeasurementModel,
    params: &UnscentedParams,
) -> Result<UnscentedResult, FilterError> {
    let points = SigmaPoints::new(&component.mean, &component.cov, params)?;
    let measure = |x: &DVector<f64>| sensor.measure(&motion.position(x));
    Ok(points.transform(measure, |a, b| sensor.residual(a, b)))
}
