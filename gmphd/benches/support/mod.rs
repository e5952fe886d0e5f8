//! Shared by the benchmarks: the clock they measure with, the allocator, and the integration
//! tests' measurement simulation and Vo & Ma's demo scenario.
#![allow(dead_code)]

pub mod clock;

/// The allocator the fusion server runs with: the filter allocates a mean and a covariance
/// per child component, and glibc's malloc spends a third of an update on that.
#[global_allocator]
static ALLOCATOR: small_alloc::SmallAlloc = small_alloc::SmallAlloc;

/// The integration tests' simulation and scenarios (`tests/common`), so that benchmarks and
/// accuracy tests run on the same kind of sets.
#[path = "../../tests/common/mod.rs"]
pub mod common;
