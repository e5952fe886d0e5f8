//! The sizes of one update — state n and measurement m — as types, so that the update's
//! per-component work (unscented moments, innovation factor, gain, posterior covariance) is
//! compiled once for each common size with fixed-size nalgebra matrices on the stack
//! (no allocation, loops of known length, no bounds checks) and once for any size with
//! dynamic matrices. Both are the same generic code: only the storage differs, and the
//! arithmetic is done in the same order, so they give the same result bit for bit
//! (`tests::fixed_and_dynamic_sizes_update_alike`).

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
