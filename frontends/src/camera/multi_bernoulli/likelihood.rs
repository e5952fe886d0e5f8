//! The image likelihood of one hypothesised person (the paper's `g_y(x)` of eq. 20, as a ratio against
//! the image without that person).
//!
//! With the paper's exponential foreground and background terms the log-likelihood of a person is linear
//! in the foreground values of the pixels its region covers: it grows with every pixel that is foreground
//! and falls with every pixel that is background. Here that sum runs over the pixels of the person's
//! region that the other people do not already explain (`cover.rs`), each pixel scored `f − threshold`,
//! and is divided by the number of pixels that count as one independent observation (neighbouring
//! pixels of one frame are far from independent; without this the filter would be certain after one
//! frame of any blob).
//!
//! A hypothesis whose region lies mostly outside the image (or behind the camera) has left the view: it
//! gets likelihood 0, so a person walking out of the image loses its existence.

use super::bernoulli::PersonState;
use super::cover::Cover;
use super::foreground::ForegroundMap;
use super::region::{PersonProjector, Region};

/// Smallest share of a person's region inside the image for the person to count as in view.
pub const MIN_INSIDE_SHARE: f32 = 0.25;

/// Scores hypotheses against one frame's foreground map.
pub struct Likelihood<'a> {
    /// Projects a hypothesis into the image.
    pub projector: &'a PersonProjector,
    /// The frame's foreground.
    pub map: &'a ForegroundMap,
    /// Pixels per independent observation.
    pub pixels_per_observation: f32,
    /// How much more a pixel of the head counts than one of the body.
    pub head_weight: f32,
}

impl Likelihood<'_> {
    /// The log-likelihood ratio of a person in `state`, scored on the pixels `cover` leaves free;
    /// `region` is a scratch buffer. `−∞` when the person is out of view.
    pub fn log_ratio(&self, state: &PersonState, cover: &Cover, region: &mut Region) -> f64 {
        if !self
            .projector
            .rasterise(state[0], state[1], state[4], region)
        {
            return f64::NEG_INFINITY;
        }
        let area = region.area();
        if area.is_nan()
            || area <= 0.0
            || region.area_inside(self.map.size()) < MIN_INSIDE_SHARE * area
        {
            return f64::NEG_INFINITY;
        }
        let sum = |spans: &[super::region::RowSpan]| -> f32 {
            spans
                .iter()
                .map(|span| cover.free_sum(self.map, span))
                .sum()
        };
        let score = self.head_weight * sum(region.head()) + sum(&region.spans[region.head_spans..]);
        f64::from(score / self.pixels_per_observation)
    }
}
