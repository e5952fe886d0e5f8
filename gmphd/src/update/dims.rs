//! The sizes of one update — state n and measurement m — as types, so that the update's
//! per-component work (unscented moments, innovation factor, gain, posterior covariance) is
//! compiled once for each common size with fixed-size nalgebra matrices on the stack
//! (no allocation, loops of known length, no bounds checks) and once for any size with
//! dynamic matrices. Both are the same generic code: only the storage differs and the
//! arithmetic is done in the same order, so they agree (bit for bit in practice; the test
//! `fixed_and_dynamic_sizes_update_alike` holds them to 1e-9).

use nalgebra::allocator::Allocator;
use nalgebra::{Const, Dim, Dyn};

use crate::gaussian::Gaussian;

/// The sizes an update runs with.
///
/// Code generic over `D: Dims` also needs the bound `DefaultAllocator: Storage<D>`, which
/// says nalgebra can store its matrices (Rust does not carry it along with this trait).
pub(super) trait Dims: Copy + Send + Sync {
    /// State size.
    type N: Dim;
    /// Measurement size.
    type M: Dim;

    /// The state size of `component` (the same for every component of a fixed-size update).
    fn state(self, component: &Gaussian) -> Self::N;

    /// The measurement size.
    fn measurement(self) -> Self::M;
}

/// An update whose components all have N states, measured by a sensor of size M.
#[derive(Debug, Clone, Copy)]
pub(super) struct Fixed<const N: usize, const M: usize>;

impl<const N: usize, const M: usize> Dims for Fixed<N, M> {
    type N = Const<N>;
    type M = Const<M>;

    #[inline(always)]
    fn state(self, component: &Gaussian) -> Const<N> {
        debug_assert_eq!(component.dim(), N);
        Const
    }

    #[inline(always)]
    fn measurement(self) -> Const<M> {
        Const
    }
}

/// Any sizes (each component's own state size), measured by a sensor of size `.0`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Dynamic(pub(super) usize);

impl Dims for Dynamic {
    type N = Dyn;
    type M = Dyn;

    fn state(self, component: &Gaussian) -> Dyn {
        Dyn(component.dim())
    }

    fn measurement(self) -> Dyn {
        Dyn(self.0)
    }
}

/// The matrices an update of sizes `D` stores: n × n, n × m, m × m and m-vectors.
pub(super) trait Storage<D: Dims>:
    Allocator<D::N, D::N> + Allocator<D::N, D::M> + Allocator<D::M, D::M> + Allocator<D::M>
{
}

impl<D: Dims, A> Storage<D> for A where
    A: Allocator<D::N, D::N> + Allocator<D::N, D::M> + Allocator<D::M, D::M> + Allocator<D::M>
{
}

#[cfg(test)]
mod tests {
    use super::super::sized::{update_sized, UpdateScratch, Work};
    use super::super::UpdateStep;
    use super::*;
    use crate::gating::Gating;
    use crate::gaussian::Label;
    use crate::measurement::PositionSensor;
    use crate::measurement::{Detection, Lidar, Measurement, MeasurementModel, PinholeCamera};
    use crate::motion::ConstantVelocity;
    use crate::ukf::UnscentedParams;
    use nalgebra::{DMatrix, DVector, DefaultAllocator, Matrix3x4, Vector3};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// 40 components of a 3-D constant-velocity state around `centre` (±`spread` m), with
    /// correlated covariances, and 30 measurements of points near them.
    fn scene(
        sensor: &dyn MeasurementModel,
        centre: [f64; 3],
        spread: f64,
    ) -> (Vec<Gaussian>, Vec<Measurement>) {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let point = |rng: &mut ChaCha8Rng| {
            Vector3::from_fn(|i, _| centre[i] + spread * rng.gen_range(-1.0..1.0))
        };
        let components = (0..40)
            .map(|i| {
                let p = point(&mut rng);
                let mean = DVector::from_fn(6, |r, _| {
                    if r < 3 {
                        p[r]
                    } else {
                        rng.gen_range(-1.0..1.0)
                    }
                });
                let a = DMatrix::from_fn(6, 6, |_, _| rng.gen_range(-0.1..0.1));
                let cov = &a * a.transpose() + DMatrix::from_diagonal_element(6, 6, 0.01);
                Gaussian::new(rng.gen_range(0.05..1.0), mean, cov, Label(i + 1))
            })
            .collect();
        let measurements = (0..30)
            .map(|_| Measurement::new(sensor.measure(&point(&mut rng))))
            .collect();
        (components, measurements)
    }

    /// The update of `scene` on the sizes `fixed` and on dynamic sizes.
    fn assert_fixed_matches_dynamic<F: Dims>(
        fixed: F,
        sensor: &dyn MeasurementModel,
        centre: [f64; 3],
    ) where
        DefaultAllocator: Storage<F>,
        nalgebra::OMatrix<f64, F::N, F::M>: Send + Sync,
        nalgebra::OMatrix<f64, F::M, F::M>: Send + Sync,
        nalgebra::OVector<f64, F::M>: Send + Sync,
    {
        let motion = ConstantVelocity::new(3, 1.0).unwrap();
        let unscented = UnscentedParams::default();
        let step = UpdateStep {
            motion: &motion,
            sensor,
            unscented: &unscented,
        };
        let (components, measurements) = scene(sensor, centre, 1.0);
        let seen: Vec<(usize, &Gaussian, f64)> = components
            .iter()
            .enumerate()
            .map(|(i, c)| (i, c, (0.9 * c.weight).ln()))
            .collect();
        let gating = Gating::default();
        let work = Work {
            step: &step,
            gate: gating.distance_threshold(sensor.dim()),
            min_weight: gating.min_weight,
            measurements: &measurements,
            index_dim: sensor.update_hints().index_dim,
            seen: &seen,
            echoes: None,
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let scratch = &mut UpdateScratch::default();
        let a_association = update_sized(fixed, &work, None, scratch, &mut a).unwrap();
        let dynamic = Dynamic(sensor.dim());
        let b_association = update_sized::<Dynamic>(dynamic, &work, None, scratch, &mut b).unwrap();
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()));
        assert!(a.len() > measurements.len(), "{} children only", a.len());
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.label, y.label);
            assert!(close(x.weight, y.weight));
            assert!(x.mean.iter().zip(&y.mean).all(|(p, q)| close(*p, *q)));
            assert!(x.cov.iter().zip(&y.cov).all(|(p, q)| close(*p, *q)));
        }
        assert!(a_association
            .iter()
            .zip(&b_association)
            .all(|(p, q)| close(*p, *q)));
    }

    #[test]
    fn fixed_and_dynamic_sizes_update_alike() {
        // The example camera of PROTOCOL.md (f = 800 px, centre at (-0.3, -0.225, 2) looking
        // along +z), objects 3 m in front of it.
        let projection = Matrix3x4::new(
            800.0, 0.0, 320.0, -400.0, 0.0, 800.0, 240.0, -300.0, 0.0, 0.0, 1.0, -2.0,
        );
        let detection = Detection::new(0.9, 2.0).unwrap();
        let camera = PinholeCamera::new(projection, [640.0, 480.0], [3.0, 3.0], detection).unwrap();
        assert_fixed_matches_dynamic(Fixed::<6, 2>, &camera, [-0.3, -0.225, 5.0]);

        let lidar = Lidar::new(
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.05, 0.01, 0.01],
            50.0,
            [-0.4, 0.4],
            detection,
        )
        .unwrap();
        assert_fixed_matches_dynamic(Fixed::<6, 3>, &lidar, [8.0, 0.0, 0.0]);

        let position = PositionSensor::new(&[0.05; 3], &[-5.0; 3], &[5.0; 3], detection).unwrap();
        assert_fixed_matches_dynamic(Fixed::<6, 3>, &position, [0.0, 0.0, 0.0]);
    }
}
