//! The memory the tracks history holds, measured with a counting allocator: the room's track
//! sets (3 tracks each) for the default `output.history_s` at the rate the default room
//! publishes them (one set per measurement set of its sensors), and that it stops growing
//! once full.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

use fusion_server::config::OutputConfig;
use fusion_server::history::TrackHistory;
use protocol::{Site, Track, TrackSet};

/// Counts the bytes currently allocated through it.
struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn room_set(seq: u64, stamp: f64) -> TrackSet {
    let track = |id: u64| Track {
        id,
        position: [1.0 + id as f64 * 0.3, 1.0, 1.7],
        velocity: Some([0.3, -0.1, 0.0]),
        position_covariance: [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.02]],
        weight: 0.98,
        first_seen: 1_763_700_000.0,
    };
    TrackSet {
        version: 1,
        site: Site::default(),
        seq,
        stamp,
        expected_count: 3.02,
        tracks: (1..=3).map(track).collect(),
    }
}

#[test]
fn the_room_history_holds_a_bounded_measured_amount_of_memory() {
    let output = OutputConfig::default();
    // Each processed set is published: the room's rate is the sum of its sensors' rates.
    let rate_hz: f64 = simulator::default_room()
        .sensors
        .iter()
        .map(|s| s.rate_hz)
        .sum();
    let period = 1.0 / rate_hz;
    let capacity = (output.history_s * rate_hz) as u64;
    let before = LIVE.load(Ordering::Relaxed);
    let mut history = TrackHistory::for_publisher(output.history_s, output.max_publish_hz);
    for seq in 0..capacity {
        history.record(room_set(seq, 1_763_700_000.0 + seq as f64 * period));
    }
    let full = LIVE.load(Ordering::Relaxed) - before;
    let per_set = full as f64 / history.len() as f64;
    println!(
        "history of {} s at {:.1} Hz: {} sets, {:.2} MB allocated, {:.0} bytes per room track set \
         (heap_bytes estimate {:.2} MB)",
        output.history_s,
        rate_hz,
        history.len(),
        full as f64 / 1e6,
        per_set,
        history.heap_bytes() as f64 / 1e6
    );
    assert!(history.len() as u64 >= capacity, "every published set kept");
    // The estimate counts what the allocator was asked for (growth of the deque aside).
    let estimate = history.heap_bytes() as isize;
    assert!(
        (full - estimate).abs() <= estimate / 10,
        "measured {full} bytes, estimated {estimate}"
    );

    // As much again: the oldest sets go, the memory stays where it was.
    for seq in capacity..2 * capacity {
        history.record(room_set(seq, 1_763_700_000.0 + seq as f64 * period));
    }
    let after = LIVE.load(Ordering::Relaxed) - before;
    println!(
        "after twice as many sets: {} kept, {:.2} MB",
        history.len(),
        after as f64 / 1e6
    );
    assert!(history.len() as u64 <= capacity + 2, "the span bounds it");
    assert!(
        after <= full + full / 100,
        "grew from {full} to {after} bytes"
    );
}
