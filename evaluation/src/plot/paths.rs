//! The plot's data rearranged for drawing: one path per truth object and per track id, and the
//! extent of all of them in space and time.

use std::collections::BTreeMap;
use std::ops::Range;

use protocol::{TrackSet, TruthSet};

/// Where one object or track was: (stamp, position) in the order of its sets.
pub(super) type Path = Vec<(f64, [f64; 3])>;

/// The truth's paths by object id and the tracks' paths by track id.
pub(super) struct Paths {
    /// One path per simulated object.
    pub truth: BTreeMap<u64, Path>,
    /// One path per track label.
    pub tracks: BTreeMap<u64, Path>,
}

/// The time axis shared by the height and OSPA panels: seconds since the first stamp drawn.
#[derive(Debug, Clone, Copy)]
pub(super) struct TimeSpan {
    start: f64,
    end: f64,
}

impl TimeSpan {
    /// The axis, from 0 to the length of the span.
    pub fn axis(self) -> Range<f64> {
        0.0..(self.end - self.start)
    }

    /// `stamp` on the axis.
    pub fn since_start(self, stamp: f64) -> f64 {
        stamp - self.start
    }
}

impl Paths {
    /// Gathers the paths of `truth` and `tracks`.
    pub fn new(tracks: &[TrackSet], truth: &[TruthSet]) -> Self {
        let mut paths = Self {
            truth: BTreeMap::new(),
            tracks: BTreeMap::new(),
        };
        for set in truth {
            for object in &set.objects {
                paths
                    .truth
                    .entry(object.id)
                    .or_default()
                    .push((set.stamp, object.position));
            }
        }
        for set in tracks {
            for track in &set.tracks {
                paths
                    .tracks
                    .entry(track.id)
                    .or_default()
                    .push((set.stamp, track.position));
            }
        }
        paths
    }

    fn points(&self) -> impl Iterator<Item = &(f64, [f64; 3])> {
        self.truth.values().chain(self.tracks.values()).flatten()
    }

    /// The extent of every point along `axis` (0 = x, 1 = y, 2 = z) with a 0.2 m margin, or
    /// 0..1 when there is nothing to draw.
    pub fn range(&self, axis: usize) -> Range<f64> {
        let (lo, hi) = self
            .points()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, p)| {
                (lo.min(p[axis]), hi.max(p[axis]))
            });
        if lo.is_finite() {
            (lo - 0.2)..(hi + 0.2)
        } else {
            0.0..1.0
        }
    }

    /// From the first stamp to the last, or 0..1 s when they do not make a span.
    pub fn time_span(&self) -> TimeSpan {
        let start = self.points().map(|(t, _)| *t).fold(f64::INFINITY, f64::min);
        let end = self
            .points()
            .map(|(t, _)| *t)
            .fold(f64::NEG_INFINITY, f64::max);
        if start.is_finite() && end > start {
            TimeSpan { start, end }
        } else {
            TimeSpan {
                start: 0.0,
                end: 1.0,
            }
        }
    }
}
