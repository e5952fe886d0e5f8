//! When the update spreads its work over the rayon pool, and how.
//!
//! Each stage maps a list (components, measurements) to a list of results in order; every
//! item is computed the same way on any thread, so the output is identical, component for
//! component, on any number of threads.

use rayon::prelude::*;

/// Least work (in nanoseconds of one core, roughly) that is spread over the rayon pool:
/// below it, handing work to another thread costs more than it saves. On the 2-vCPU machine
/// of BENCHMARKS.md two threads were slower than one at every size measured (0.3–5 ms
/// updates, the dense step), so only updates of several milliseconds go parallel, where a
/// machine with real spare cores gains.
const PARALLEL_MIN_WORK_NS: usize = 2_000_000;

/// Rough single-core cost of scoring one component–measurement pair.
pub(super) const PAIR_NS: usize = 10;
/// Rough single-core cost of preparing one component for a linear sensor.
pub(super) const LINEAR_COMPONENT_NS: usize = 200;
/// Rough single-core cost of preparing one component for a nonlinear sensor.
pub(super) const UNSCENTED_COMPONENT_NS: usize = 1_000;
/// Rough single-core cost of one component's gain and posterior covariance.
pub(super) const CORRECTION_NS: usize = 500;

/// `f` of every item of `items` (with its index), in order, stopping at the first error:
/// on the rayon pool when `work_ns` (estimated single-core nanoseconds) is worth it, each
/// worker with scratch from `init`; otherwise here, with `scratch`.
pub(super) fn try_map<T, S, R, E>(
    items: &[T],
    work_ns: usize,
    scratch: &mut S,
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, usize, &T) -> Result<R, E> + Sync + Send,
) -> Result<Vec<R>, E>
where
    T: Sync,
    R: Send,
    E: Send,
{
    if parallel(work_ns) {
        return items
            .par_iter()
            .enumerate()
            .map_init(init, |s, (i, item)| f(s, i, item))
            .collect();
    }
    // Pushed into a Vec of the final size: collecting through `Result` would grow it by
    // doubling, moving every (few-hundred-byte) result each time.
    let mut out = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        out.push(f(scratch, i, item)?);
    }
    Ok(out)
}

/// [`try_map`] of an `f` that cannot fail.
pub(super) fn map<T, S, R>(
    items: &[T],
    work_ns: usize,
    scratch: &mut S,
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, usize, &T) -> R + Sync + Send,
) -> Vec<R>
where
    T: Sync,
    R: Send,
{
    let never = try_map(items, work_ns, scratch, init, |s, i, item| {
        Ok::<R, std::convert::Infallible>(f(s, i, item))
    });
    match never {
        Ok(out) => out,
        Err(infallible) => match infallible {},
    }
}

/// Whether `work_ns` is worth spreading over the rayon pool: only with more than one
/// thread and enough work.
fn parallel(work_ns: usize) -> bool {
    work_ns >= PARALLEL_MIN_WORK_NS && rayon::current_num_threads() > 1
}
