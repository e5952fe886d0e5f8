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
use crate::ukf::UnscentedWeights;

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
///
/// The plain transform ([`crate::reference::unscented_moments`]) through all 2n + 1 sigma
/// points, less the work that cannot change its result: a position is a function of the
/// state's leading `position_dims` entries (the `MotionModel` contract) and column j of a
/// lower factor is zero above row j, so only the first d columns move the position. The
/// other 2(n − d) sigma points (the velocities', once the factor has taken the position's
/// share) are the mean's image: they are neither factored nor measured, and their terms
/// are counted instead of summed.
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
    let weights = step.unscented.weights(n_dim.value())?;
    let d = step.motion.position_dims().min(n_dim.value());
    let root = square_root::<D>(n_dim, component, d, weights.spread);
    let sizes = (n_dim.value(), d, m_dim.value());
    measure_sigma_points(component, step, root.as_slice(), sizes, scratch);
    let residual = Residual::of(step.sensor);
    let mean = weighted_mean::<D>(m_dim, &weights, residual, scratch);
    Ok(moments_about::<D>(
        (n_dim, m_dim),
        &weights,
        residual,
        mean,
        root.as_slice(),
        scratch,
    ))
}

/// The lower Cholesky factor of `spread` · P, its first `d` columns computed (the rest
/// zero), or all of it repaired when P is slightly indefinite from round-off (as
/// [`SigmaPoints`](crate::ukf::SigmaPoints) repairs it).
fn square_root<D: Dims>(
    n_dim: D::N,
    component: &Gaussian,
    d: usize,
    spread: f64,
) -> OMatrix<f64, D::N, D::N>
where
    DefaultAllocator: Storage<D>,
{
    let n = n_dim.value();
    let mut root = OMatrix::<f64, D::N, D::N>::zeros_generic(n_dim, n_dim);
    let entry = |r, c| spread * component.cov[(r, c)];
    if !lower_cholesky_columns(n, d, entry, root.as_mut_slice()) {
        let repaired = robust_cholesky(&(&component.cov * spread)).unpack();
        root.as_mut_slice().copy_from_slice(repaired.as_slice());
    }
    root
}

/// Measures the sigma points of the n-state `component` into `scratch.outputs` (m entries
/// each), of which only the first d columns of `root` move the position: point 0 is the mean,
/// point 1 + i is mean + column i of `root`, point 1 + n + i mean − column i. Points whose
/// position is the mean's are marked `at_centre` and not measured (their output slot is
/// never read).
fn measure_sigma_points(
    component: &Gaussian,
    step: &UpdateStep<'_>,
    root: &[f64],
    (n, d, m): (usize, usize, usize),
    scratch: &mut UnscentedScratch,
) {
    let points = 2 * n + 1;
    scratch.outputs.resize(points * m, 0.0);
    scratch.residual.resize(m, 0.0);
    scratch.centre_residual.resize(m, 0.0);
    scratch.at_centre.clear();
    scratch.at_centre.resize(points, true);
    copy_into(&mut scratch.point, &component.mean);
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
        if position != centre {
            *at_centre = false;
            step.sensor.measure_into(&position, output);
        }
    }
}

/// ȳ = y₀ + Σ wᵢ residual(yᵢ, y₀), so that angular outputs near ±π average correctly.
/// Points at the centre all have the centre's residual (computed once, in
/// `centre_residual`), so they are counted instead of visited.
fn weighted_mean<D: Dims>(
    m_dim: D::M,
    weights: &UnscentedWeights,
    residual: Residual<'_>,
    scratch: &mut UnscentedScratch,
) -> OVector<f64, D::M>
where
    DefaultAllocator: Storage<D>,
{
    let m = m_dim.value();
    let outputs = &scratch.outputs;
    let at_centre = &scratch.at_centre;
    let mut mean = OVector::<f64, D::M>::from_column_slice_generic(m_dim, U1, &outputs[..m]);
    residual.write(
        &outputs[..m],
        &outputs[..m],
        &mut scratch.centre_residual[..m],
    );
    for j in (1..at_centre.len()).filter(|&j| !at_centre[j]) {
        residual.write(
            &outputs[j * m..(j + 1) * m],
            &outputs[..m],
            &mut scratch.residual[..m],
        );
        for (y, r) in mean.as_mut_slice().iter_mut().zip(&scratch.residual[..m]) {
            *y += weights.outer * r;
        }
    }
    let centred = at_centre[1..].iter().filter(|c| **c).count();
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
    mean
}

/// The moments about the sigma points' weighted `mean` ȳ: the covariance Σ w_c dy dyᵀ
/// (symmetrised) and the cross-covariance Σ w_c dx dyᵀ, dy = residual(yⱼ, ȳ) and
/// dx = xⱼ − x₀ (± a column of `root`).
fn moments_about<D: Dims>(
    (n_dim, m_dim): (D::N, D::M),
    weights: &UnscentedWeights,
    residual: Residual<'_>,
    mean: OVector<f64, D::M>,
    root: &[f64],
    scratch: &mut UnscentedScratch,
) -> UnscentedMoments<D>
where
    DefaultAllocator: Storage<D>,
{
    let (n, m) = (n_dim.value(), m_dim.value());
    let outputs = &scratch.outputs;
    let at_centre = &scratch.at_centre;
    let centred = at_centre[1..].iter().filter(|c| **c).count();
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
    for j in (0..at_centre.len()).filter(|&j| j == 0 || !cancels(j)) {
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
        if w != 0.0 {
            add_outer(cov.as_mut_slice(), w, dy, dy);
        }
        if j > 0 {
            let (column, signed_weight) = if j <= n {
                (j - 1, weights.outer)
            } else {
                (j - 1 - n, -weights.outer)
            };
            add_outer(
                cross_cov.as_mut_slice(),
                signed_weight,
                &root[column * n..(column + 1) * n],
                dy,
            );
        }
    }
    for c in 0..m {
        for r in c + 1..m {
            let symmetric = 0.5 * (cov[(r, c)] + cov[(c, r)]);
            cov[(r, c)] = symmetric;
            cov[(c, r)] = symmetric;
        }
    }
    UnscentedMoments {
        mean,
        cov,
        cross_cov,
    }
}

/// A += w · x yᵀ for the column-major `a` of x.len() rows (column c is w y_c x).
fn add_outer(a: &mut [f64], w: f64, x: &[f64], y: &[f64]) {
    for (column, y_c) in a.chunks_exact_mut(x.len()).zip(y) {
        let scaled = w * y_c;
        for (entry, x_r) in column.iter_mut().zip(x) {
            *entry += scaled * x_r;
        }
    }
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
