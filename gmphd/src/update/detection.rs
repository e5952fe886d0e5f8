//! The detection probability of a predicted component.
//!
//! The GM-PHD filter evaluates p_D at each component's mean (Vo & Ma 2006, eq. 20 assumes p_D
//! constant over a component). Where the mean lies outside the sensor's view that gives
//! p_D = 0 however far the component reaches into the view, and a p_D of 0 leaves the
//! component untouched by the update: no missed-detection decay, no detection child. A track
//! whose prediction drifted just past the edge of the view (a head near the top of the
//! volume after a pause in the data, a clutter return's child with a wrong velocity) then
//! keeps its weight for ever while the object itself, seen inside the view, is taken over
//! by a birth. So when p_D is zero at the mean, it is averaged over the component's spread.
//! p_D depends on the position alone, so the average is over the position's marginal (the
//! leading d × d block of P, d = 2 or 3): the mean and the 2d points mean ± √d · (columns
//! of that block's Cholesky factor), equally weighted — an unscented estimate of E[p_D(x)]
//! that is positive when the component reaches into the view. Components seen at their
//! mean are unchanged.

use nalgebra::DVector;

use super::UpdateStep;
use crate::gaussian::Gaussian;
use crate::linalg::{copy_into, lower_cholesky};

/// Largest number of position coordinates (motion models have 2 or 3).
const MAX_POSITION_DIMS: usize = 3;

/// p_D for `component` (see the module documentation), in [0, 1]; `point` is scratch
/// for the spread's points (resized as needed, so that a loop over components allocates
/// it once).
pub(crate) fn detection_probability(
    component: &Gaussian,
    step: &UpdateStep<'_>,
    point: &mut DVector<f64>,
) -> f64 {
    let at = |state: &DVector<f64>| {
        let position = step.motion.position(state);
        step.sensor.detection_probability(&position).clamp(0.0, 1.0)
    };
    let at_mean = at(&component.mean);
    if at_mean > 0.0 {
        return at_mean;
    }
    let d = step.motion.position_dims().min(component.dim());
    let mut root = [0.0; MAX_POSITION_DIMS * MAX_POSITION_DIMS];
    if d == 0 || d > MAX_POSITION_DIMS {
        return 0.0;
    }
    if !lower_cholesky(d, |r, c| component.cov[(r, c)], &mut root[..d * d]) {
        return 0.0;
    }
    let scale = (d as f64).sqrt();
    copy_into(point, &component.mean);
    let mut sum = 0.0;
    for column in 0..d {
        for sign in [scale, -scale] {
            for row in 0..d {
                point[row] = component.mean[row] + sign * root[row + column * d];
            }
            sum += at(point);
        }
    }
    sum / (2 * d + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;
    use crate::measurement::{Detection, PositionSensor};
    use crate::motion::ConstantVelocity;
    use crate::ukf::UnscentedParams;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn a_component_reaching_into_the_view_is_detectable() {
        let sensor = PositionSensor::new(
            &[0.05, 0.05, 0.05],
            &[0.0, 0.0, 0.0],
            &[3.0, 2.0, 2.0],
            Detection::new(0.9, 2.0).unwrap(),
        )
        .unwrap();
        let motion = ConstantVelocity::new(3, 1.0).unwrap();
        let unscented = UnscentedParams::default();
        let step = UpdateStep {
            motion: &motion,
            sensor: &sensor,
            unscented: &unscented,
        };
        let mut point = DVector::zeros(0);
        let component = |z: f64, std: f64| {
            let mean = DVector::from_vec(vec![1.5, 1.0, z, 0.0, 0.0, 0.0]);
            let cov = DMatrix::from_diagonal_element(6, 6, std * std);
            Gaussian::new(1.0, mean, cov, Label(1))
        };
        // Inside: p_D itself.
        assert_eq!(
            detection_probability(&component(1.7, 0.5), &step, &mut point),
            0.9
        );
        // Just above the view with a wide spread: one of the 7 points of the position's
        // marginal (mean − √3·σ in z) inside; the velocity's spread does not matter.
        let reaching = detection_probability(&component(2.05, 0.5), &step, &mut point);
        assert!((reaching - 0.9 / 7.0).abs() < 1e-12, "{reaching}");
        // Tight and outside, or far outside: not detectable.
        assert_eq!(
            detection_probability(&component(2.05, 0.01), &step, &mut point),
            0.0
        );
        assert_eq!(
            detection_probability(&component(9.0, 0.5), &step, &mut point),
            0.0
        );
    }
}
