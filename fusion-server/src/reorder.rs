//! The reorder buffer: sets from sensors with different rates and latencies are held for a
//! window and released strictly in `stamp` order.
//!
//! Time is whatever the caller says it is: the wall clock in the live server, the largest stamp
//! seen so far in `replay` (so that replays are deterministic and need no clock).

use std::collections::BTreeMap;

/// Why a set was not admitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refused {
    /// Older than a set already released to the filter: the filter cannot go back in time.
    Late {
        /// The refused set's stamp.
        stamp: f64,
        /// The newest stamp already released.
        released: f64,
    },
    /// The buffer is full; the set is dropped and counted.
    Full,
}

/// Holds items keyed by stamp until they have waited `window` (in caller time units, seconds).
#[derive(Debug)]
pub struct ReorderBuffer<T> {
    window: f64,
    capacity: usize,
    /// Keyed by (stamp bits, arrival counter): stamps are finite and non-negative, so their
    /// IEEE bits order like the numbers; the counter keeps equal stamps in arrival order.
    held: BTreeMap<(u64, u64), Held<T>>,
    arrivals: u64,
    released: Option<f64>,
}

#[derive(Debug)]
struct Held<T> {
    held_since: f64,
    item: T,
}

impl<T> ReorderBuffer<T> {
    /// A buffer that holds each item `window` seconds and at most `capacity` items.
    pub fn new(window: f64, capacity: usize) -> Self {
        Self {
            window,
            capacity,
            held: BTreeMap::new(),
            arrivals: 0,
            released: None,
        }
    }

    /// The newest stamp released so far.
    pub fn released(&self) -> Option<f64> {
        self.released
    }

    /// Sets the newest released stamp (after restoring a checkpoint).
    pub fn set_released(&mut self, stamp: f64) {
        self.released = Some(stamp);
    }

    /// Number of items waiting.
    pub fn len(&self) -> usize {
        self.held.len()
    }

    /// True when nothing waits.
    pub fn is_empty(&self) -> bool {
        self.held.is_empty()
    }

    /// Admits an item stamped `stamp` (finite, ≥ 0) arriving at `now`.
    pub fn push(&mut self, stamp: f64, now: f64, item: T) -> Result<(), Refused> {
        debug_assert!(stamp.is_finite() && stamp >= 0.0);
        if let Some(released) = self.released {
            if stamp < released {
                return Err(Refused::Late { stamp, released });
            }
        }
        if self.held.len() >= self.capacity {
            return Err(Refused::Full);
        }
        self.arrivals += 1;
        self.held.insert(
            (stamp.max(0.0).to_bits(), self.arrivals),
            Held {
                held_since: now,
                item,
            },
        );
        Ok(())
    }

    /// Releases, in stamp order, the items at the front that have waited the full window by `now`.
    pub fn pop_ready(&mut self, now: f64) -> Vec<(f64, T)> {
        let mut out = Vec::new();
        while let Some(entry) = self.held.first_entry() {
            if entry.get().held_since + self.window > now {
                break;
            }
            let ((bits, _), held) = entry.remove_entry();
            let stamp = f64::from_bits(bits);
            self.released = Some(stamp);
            out.push((stamp, held.item));
        }
        out
    }

    /// Releases everything, in stamp order (shutdown, end of a replay).
    pub fn drain(&mut self) -> Vec<(f64, T)> {
        let mut out = Vec::new();
        while let Some(((bits, _), held)) = self.held.pop_first() {
            let stamp = f64::from_bits(bits);
            self.released = Some(stamp);
            out.push((stamp, held.item));
        }
        out
    }

    /// Time at which the front item becomes ready, if any (lets the caller sleep until then).
    pub fn next_ready_at(&self) -> Option<f64> {
        self.held
            .first_key_value()
            .map(|(_, held)| held.held_since + self.window)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn releases_in_stamp_order_after_the_window() {
        let mut buffer = ReorderBuffer::new(0.1, 10);
        buffer.push(10.02, 0.00, "b").unwrap();
        buffer.push(10.01, 0.05, "a").unwrap();
        assert!(
            buffer.pop_ready(0.09).is_empty(),
            "nothing waited 0.1 s yet"
        );
        // The front (stamp 10.01) arrived at 0.05: not ready at 0.12 although "b" would be.
        assert!(buffer.pop_ready(0.12).is_empty());
        let out = buffer.pop_ready(0.16);
        assert_eq!(out, vec![(10.01, "a"), (10.02, "b")]);
    }

    #[test]
    fn a_set_older_than_the_released_ones_is_late() {
        let mut buffer = ReorderBuffer::new(0.0, 10);
        buffer.push(5.0, 0.0, 1).unwrap();
        assert_eq!(buffer.pop_ready(0.0).len(), 1);
        assert_eq!(
            buffer.push(4.9, 0.1, 2),
            Err(Refused::Late {
                stamp: 4.9,
                released: 5.0
            })
        );
        assert!(
            buffer.push(5.0, 0.1, 3).is_ok(),
            "an equal stamp is not late"
        );
    }

    #[test]
    fn a_full_buffer_refuses_and_keeps_what_it_has() {
        let mut buffer = ReorderBuffer::new(1.0, 2);
        buffer.push(1.0, 0.0, 1).unwrap();
        buffer.push(2.0, 0.0, 2).unwrap();
        assert_eq!(buffer.push(3.0, 0.0, 3), Err(Refused::Full));
        assert_eq!(buffer.drain(), vec![(1.0, 1), (2.0, 2)]);
    }

    #[test]
    fn equal_stamps_keep_arrival_order() {
        let mut buffer = ReorderBuffer::new(0.0, 10);
        for i in 0..5 {
            buffer.push(1.0, 0.0, i).unwrap();
        }
        let items: Vec<_> = buffer.drain().into_iter().map(|(_, i)| i).collect();
        assert_eq!(items, vec![0, 1, 2, 3, 4]);
    }
}
