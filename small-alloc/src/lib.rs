//! mimalloc as the global allocator, without its aligned entry points for ordinary
//! alignments.
//!
//! The filter allocates and frees a mean and a covariance per updated component, a few
//! hundred thousand small blocks a second, so the allocator is on its hot path.
//! `mimalloc::MiMalloc` passes every request to `mi_malloc_aligned`, and mimalloc 3's
//! aligned path only takes its fast path while the size class's page has a block on its
//! free list: once the page is used up it falls to a generic path that, for a block size
//! that is not a power of two (a 6-vector is 48 bytes, a 6 × 6 covariance 288), allocates
//! `size + align − 1` bytes from the next size class instead of collecting the blocks freed
//! meanwhile. In the dense scenario a third of the allocations went that way.
//!
//! `mi_malloc` returns blocks aligned to 16 bytes (mimalloc's `MI_MAX_ALIGN_SIZE`; its size
//! classes are multiples of two words) or, for a block of one word, to 8 bytes: so a request
//! whose alignment is at most 16 and at most its size goes there, as Rust's own `System`
//! allocator does with `malloc`. Anything else still goes to the aligned entry points.

use std::alloc::{GlobalAlloc, Layout};
use std::ffi::c_void;

use libmimalloc_sys as mi;

/// The alignment every `mi_malloc` block of at least this size has (`MI_MAX_ALIGN_SIZE`).
const PLAIN_ALIGN: usize = 16;

/// The global allocator of the server and of the filter's benchmarks:
/// `#[global_allocator] static ALLOCATOR: small_alloc::SmallAlloc = small_alloc::SmallAlloc;`
pub struct SmallAlloc;

/// Whether mimalloc's plain entry points already give `layout`'s alignment.
fn plain(layout: Layout) -> bool {
    layout.align() <= PLAIN_ALIGN && layout.align() <= layout.size()
}

// SAFETY: every entry point is mimalloc's own; blocks from either kind of entry point are
// freed by `mi_free`, and a plain block is only handed out where its alignment suffices.
unsafe impl GlobalAlloc for SmallAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if plain(layout) {
            mi::mi_malloc(layout.size()).cast()
        } else {
            mi::mi_malloc_aligned(layout.size(), layout.align()).cast()
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if plain(layout) {
            mi::mi_zalloc(layout.size()).cast()
        } else {
            mi::mi_zalloc_aligned(layout.size(), layout.align()).cast()
        }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, _layout: Layout) {
        mi::mi_free(ptr.cast::<c_void>())
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
        if plain(new_layout) {
            mi::mi_realloc(ptr.cast(), new_size).cast()
        } else {
            mi::mi_realloc_aligned(ptr.cast(), new_size, layout.align()).cast()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every size and alignment a program may ask for comes back aligned, writable and
    /// intact through growth and shrinking.
    #[test]
    fn blocks_have_the_alignment_asked_for() {
        let allocator = SmallAlloc;
        for align in [1, 2, 4, 8, 16, 32, 64, 4096] {
            for size in [1, 3, 8, 16, 24, 48, 100, 288, 1000, 5000, 100_000] {
                let layout = Layout::from_size_align(size, align).unwrap();
                unsafe {
                    for zeroed in [false, true] {
                        let ptr = if zeroed {
                            allocator.alloc_zeroed(layout)
                        } else {
                            allocator.alloc(layout)
                        };
                        assert!(!ptr.is_null());
                        assert_eq!(ptr as usize % align, 0, "size {size}, align {align}");
                        if zeroed {
                            assert!((0..size).all(|i| *ptr.add(i) == 0));
                        }
                        ptr.write_bytes(0xA5, size);
                        let grown = allocator.realloc(ptr, layout, size * 3);
                        assert_eq!(grown as usize % align, 0);
                        assert!((0..size).all(|i| *grown.add(i) == 0xA5));
                        let grown_layout = Layout::from_size_align(size * 3, align).unwrap();
                        let shrunk = allocator.realloc(grown, grown_layout, size.div_ceil(2));
                        assert_eq!(shrunk as usize % align, 0);
                        assert!((0..size.div_ceil(2)).all(|i| *shrunk.add(i) == 0xA5));
                        let shrunk_layout =
                            Layout::from_size_align(size.div_ceil(2), align).unwrap();
                        allocator.dealloc(shrunk, shrunk_layout);
                    }
                }
            }
        }
    }
}
