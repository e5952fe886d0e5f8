//! The unscented transform of one component into a sensor's measurement space, as
//! [`SigmaPoints::transform`](crate::ukf::SigmaPoints::transform) computes it, but with its
//! buffers kept in an [`UnscentedScratch`] that one worker thread reuses for every
//! component, and its results sized by the update's [`Dims`](super::dims): on the fixed
//! sizes nothing is allocated per component (loops of known length, unrolled, without
//! bounds checks); on the dynamic fallback only the three results are.

use nalgebra::{DVector, DefaultAllocator, Dim, OMatrix, OVector, U1};

use super::dims::{Dims, Storage};
use super::UpdateStep;
use crate::error::FilterError;
use crate::gaussian::Gaussian;
use crate::linalg::{copy_into, lower_cholesky_columns, robust_cholesky};
use crate::measurement::Residual;

/// Reusable buffers of the transform.
#[derive(Default)]
pub(super) struct UnscentedScratch {
    /// One sigma point (a `DVector`, which is what motion models take).
    point: DVector<f64>,
    /// The 2n + 1 transformed points, m entries each.
    outputs: Vec<f64>,
    /// Per point: whether it is the mean's image (its column moved only what the sensor
    /// does not see), so that the residuals computed for the mean serve it too.
    at_centre: Vec<bool>,
    residual: Vec<f64>,
    /// residual(y₀, y₀), and the residual of y₀ against the predicted measurement.
    centre_residual: Vec<f64>,
}

/// Predicted measurement, its covariance (noise not included) and the cross-covariance
/// with the state.
pub(super) struct UnscentedMoments<D: Dims>
where
    DefaultAllocator: Storage<D>,
{
    pub(super) mean: OVector<f64, D::M>,
    pub(super) cov: OMatrix<f64, D::M, D::M>,
    pub(super) cross_cov: OMatrix<f64, D::N, D::M>,
}

/// The unscented moments of `component` seen by `step.sensor` through `step.motion`, for
/// the sizes `dims` (the component's state size and the sensor's measurement size).
pub(super) fn project<D: Dims>(
    dims: D,
    component: &Gaussian,
    step: &UpdateStep<'_>,
    scratch: &mut UnscentedScratch,
) -> Result<UnscentedMoments<D>, FilterError>
where
    DefaultAllocator: Storage<D>,
{
    let (n_dim, m_dim) = (dims.state(component), dims.measurement());
    let (n, m) = (n_dim.value(), m_dim.value());
    let weights = step.unscented.weights(n)?;
    // A position is a function of the state's leading `position_dims` entries (the
    // `MotionModel` contract) and column j of a lower factor is zero above row j, so only the
    // first d columns move the position: the other 2(n − d) sigma points (the velocities',
    // once the factor has taken the position's share) are the mean's image. Only the first d
    // columns are factored and visited.
    let d = step.motion.position_dims().min(n);
    let mut root = OMatrix::<f64, D::N, D::N>::zeros_generic(n_dim, n_dim);
    let spread = weights.spread;
    if !lower_cholesky_columns(
        n,
        d,
        |r, c| spread * component.cov[(r, c)],
        root.as_mut_slice(),
    ) {
        // Repair a covariance made slightly indefinite by round-off, as SigmaPoints does.
        let repaired = robust_cholesky(&(&component.cov * weights.spread)).unpack();
        root.as_mut_slice().copy_from_slice(repaired.as_slice());
    }
    let root = root.as_slice();
    let points = 2 * n + 1;
    scratch.outputs.resize(points * m, 0.0);
    scratch.residual.resize(m, 0.0);
    scratch.centre_residual.resize(m, 0.0);
    scratch.at_centre.clear();
    scratch.at_centre.resize(points, true);
    copy_into(&mut scratch.point, &component.mean);
    // Point 0 is the mean, point 1 + i is mean + column i, point 1 + n + i mean − column i.
    let centre = step.motion.position(&component.mean);
    let (first, rest) = scratch.outputs.split_at_mut(m);
    step.sensor.measure_into(&centre, first);
    for ((j, output), at_centre) in rest
        .chunks_exact_mut(m)
        .enumerate()
        .zip(&mut scratch.at_centre[1..])
    {
        let (column, sign) = if j < n { (j, 1.0) } else { (j - n, -1.0) };
        if column >= d {
            continue;
        }
        let root_column = &root[column * n..(column + 1) * n];
        // Slices, not nalgebra's iterators: those step through a general strided layout.
        // (Each of exactly n entries, a constant on the fixed sizes.)
        for ((x, mean), l) in scratch.point.as_mut_slice()[..n]
            .iter_mut()
            .zip(&component.mean.as_slice()[..n])
            .zip(root_column)
        {
            *x = mean + sign * l;
        }
        let position = step.motion.position(&scratch.point);
        // The mean's image (a column without spread in the position) is not measured, and its
        // output slot is never read.
        if position != centre {
            *at_centre = false;
            step.sensor.measure_into(&position, output);
        }
    }

    // ȳ = y₀ + Σ wᵢ residual(yᵢ, y₀): angular outputs near ±π average correctly.
    // Points at the centre all have the centre's residual (computed once, in
    // `centre_residual`), so they are counted instead of visited: with the position leading
    // the state, the velocity columns of the factor give n of the 2n outer points, and
    // skipping them halves the work of the moments.
    let outputs = &scratch.outputs;
    let at_centre = &scratch.at_centre;
    let residual = Residual::of(step.sensor);
    let mut mean = OVector::<f64, D::M>::from_column_slice_generic(m_dim, U1, &outputs[..m]);
    residual.write(
        &outputs[..m],
        &outputs[..m],
        &mut scratch.centre_residual[..m],
    );
    let centred = at_centre[1..].iter().filter(|c| **c).count();
    for j in (1..points).filter(|&j| !at_centre[j]) {
        residual.write(
            &outputs[j * m..(j + 1) * m],
            &outputs[..m],
            &mut scratch.residual[..m],
        );
        for (y, r) in mean.as_mut_slice().iter_mut().zip(&scratch.residual[..m]) {
            *y += weights.outer * r;
        }
    }
    if centred > 0 {
        let centre_weight = centred as f64 * weights.outer;
        for (y, r) in mean
            .as_mut_slice()
            .iter_mut()
            .zip(&scratch.centre_residual[..m])
        {
            *y += centre_weight * r;
        }
    }
    let mut cov = OMatrix::<f64, D::M, D::M>::zeros_generic(m_dim, m_dim);
    let mut cross_cov = OMatrix::<f64, D::N, D::M>::zeros_generic(n_dim, m_dim);
    residual.write(
        &outputs[..m],
        mean.as_slice(),
        &mut scratch.centre_residual[..m],
    );
    // Whether point j's contribution to the cross-covariance cancels: a point at the centre
    // whose mirror image (the same column, the other sign) is at the centre too adds
    // ±w·column·dyᵀ with the same dy.
    let cancels = |j: usize| {
        let mirror = if j <= n { j + n } else { j - n };
        at_centre[j] && at_centre[mirror]
    };
    for j in (0..points).filter(|&j| j == 0 || !cancels(j)) {
        let dy = if j == 0 || at_centre[j] {
            &scratch.centre_residual[..m]
        } else {
            residual.write(
                &outputs[j * m..(j + 1) * m],
                mean.as_slice(),
                &mut scratch.residual[..m],
            );
            &scratch.residual[..m]
        };
        // The centre point carries the covariance weight of every point at the centre.
        let w = match j {
            0 => weights.centre_cov + centred as f64 * weights.outer,
            _ if at_centre[j] => 0.0,
            _ => weights.outer,
        };
        // Column-major storage: entry (r, c) of an R-row matrix is at r + c·R.
        if w != 0.0 {
            for (c, cov_column) in cov.as_mut_slice().chunks_exact_mut(m).enumerate() {
                let scaled = w * dy[c];
                for (entry, y) in cov_column.iter_mut().zip(dy) {
                    *entry += scaled * y;
                }
            }
        }
        // x_j − x_0 is ± a column of the root (zero for the centre point).
        if j > 0 {
            let (column, signed_weight) = if j <= n {
                (j - 1, weights.outer)
            } else {
                (j - 1 - n, -weights.outer)
            };
            let dx = &root[column * n..(column + 1) * n];
            for (c, cross_column) in cross_cov.as_mut_slice().chunks_exact_mut(n).enumerate() {
                let scaled = signed_weight * dy[c];
                for (entry, x) in cross_column.iter_mut().zip(dx) {
                    *entry += scaled * x;
                }
            }
        }
    }
    for c in 0..m {
        for r in c + 1..m {
            let symmetric = 0.5 * (cov[(r, c)] + cov[(c, r)]);
            cov[(r, c)] = symmetric;
            cov[(c, r)] = symmetric;
        }
    }
    Ok(UnscentedMoments {
        mean,
        cov,
        cross_cov,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;
    use crate::measurement::{BearingRange, Detection, MeasurementModel};
    use crate::motion::CoordinatedTurn;
    use crate::ukf::{SigmaPoints, UnscentedParams};
    use crate::update::dims::{Dynamic, Fixed};
    use nalgebra::DMatrix;

    #[test]
    fn matches_the_generic_transform() {
        let motion = CoordinatedTurn::new(5.0, 0.02, 0.0, UnscentedParams::default()).unwrap();
        let detection = Detection::new(0.9, 1.0).unwrap();
        let sensor = BearingRange::new([0.0, 0.0, 0.0], [0.05, 5.0], 3000.0, detection).unwrap();
        // Straddling the ±π bearing cut, where the residual wraps.
        let mean = DVector::from_vec(vec![-900.0, 3.0, 4.0, -2.0, 0.01]);
        let cov = DMatrix::from_fn(
            5,
            5,
            |r, c| if r == c { 400.0 / (r + 1) as f64 } else { 3.0 },
        );
        let component = Gaussian::new(1.0, mean.clone(), cov.clone(), Label(1));
        let params = UnscentedParams::default();
        let step = UpdateStep {
            motion: &motion,
            sensor: &sensor,
            unscented: &params,
        };
        let scratch = &mut UnscentedScratch::default();
        let fast = project(Dynamic(2), &component, &step, scratch).unwrap();
        let fixed = project(Fixed::<5, 2>, &component, &step, scratch).unwrap();
        assert_eq!(fixed.mean.as_slice(), fast.mean.as_slice());
        assert_eq!(fixed.cov.as_slice(), fast.cov.as_slice());
        assert_eq!(fixed.cross_cov.as_slice(), fast.cross_cov.as_slice());
        let generic = SigmaPoints::new(&mean, &cov, &params).unwrap().transform(
            |x| sensor.measure(&crate::motion::MotionModel::position(&motion, x)),
            |a, b| sensor.residual(a, b),
        );
        assert!((fast.mean - generic.mean).amax() < 1e-9);
        assert!((fast.cov - generic.cov).amax() < 1e-6);
        assert!((fast.cross_cov - generic.cross_cov).amax() < 1e-6);
    }
}
