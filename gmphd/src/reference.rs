//! The textbook algorithms, written as the papers write them, against which the fast
//! kernels of the filter are tested.
//!
//! The filter's update, reduction and unscented projection are written for speed: fixed-size
//! matrices, log-space weights, gates and candidate indices, shared gains, sorted sweeps,
//! skipped sigma points. This module keeps the plain versions beside them:
//!
//! * [`update`]: the GM-PHD update of Vo & Ma 2006 (Prop. 2, and the unscented variant of
//!   their section IV; Pham eq. 3.19) — every component with every measurement, the gain
//!   K = Pₓz S⁻¹, the posterior P − K S Kᵀ, each weight p_D w q(z) over
//!   κ(z) + Σ p_D w q(z) — with the gating rules of [`crate::gating`] applied as stated;
//! * [`prune_merge_cap`]: Vo & Ma's reduction (Table II) as a loop: take the heaviest
//!   remaining component, merge every remaining one within the merge distance of it,
//!   repeat; then keep the heaviest J_max;
//! * [`unscented_moments`]: the scaled unscented transform through all 2n + 1 sigma points
//!   ([`crate::ukf::SigmaPoints`], which the nonlinear prediction uses as it is).
//!
//! They allocate freely and run in O(J × |Z|) and O(J²); they are meant to be read, and to
//! be the specification the property tests (`tests/reference_kernels.rs`) hold the fast
//! code to, on random mixtures and every sensor kind. Not every detail is textbook: where
//! the filter deliberately departs from the papers (a detection probability averaged over
//! a component's spread at the edge of the view, [`crate::update`]'s module
//! documentation), the reference departs the same way, through the same function.

mod reduce;
mod unscented;
mod update;

pub use reduce::{merge, prune_merge_cap};
pub use unscented::unscented_moments;
pub use update::update;
