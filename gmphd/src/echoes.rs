//! Side peaks of a delay measurement: copies of an object's measurement at a fixed offset to
//! either side of it.
//!
//! A microphone pair measures a talker's time difference of arrival as the position of a peak
//! of the two signals' generalized cross-correlation. Beside the direct path's peak the
//! correlation has lesser peaks at a fixed lag to either side: the sidelobes of the weighted
//! cross-spectrum's point-spread function, and the cross-terms of a strong early reflection
//! (a wall just behind the pair puts them at twice its distance over c). A front end that
//! reports every peak it believes reports them too. The plain PHD update takes each for an
//! object of its own or for clutter: a side peak pulls a track by the offset, or starts a
//! ghost on another hyperbola; and a frame whose direct peak was missed looks like a miss.
//!
//! With [`Echoes`] the update gives each detectable component, besides the hypothesis that a
//! measurement z is its direct path (h(x) + noise, with `p_D w`), those that z is one of its
//! side peaks (h(x) ± δ + noise, each with `p_D w ρ`): a side peak then updates its own track
//! at `z ∓ δ` instead of starting another, and counts as the track's detection. This is the
//! measurement model of multipath tracking with known path offsets (several detections per
//! object, each through a path of its own: Habtemariam, Tharmarasa, Thayaparan, Mallick &
//! Kirubarajan, "A multiple-detection joint probabilistic data association filter", IEEE
//! J. Sel. Topics Signal Process. 7(3), 2013), put into the PHD's per-measurement weighing.
//! That weighing would count an object's several detections as more than one object; the
//! model is meant with the per-label Bernoulli update ([`crate::existence`]), which keeps a
//! label's detections at one object in all.
//!
//! Side peaks are looked for only beside components of at least [`LEAST_WEIGHT`]: beside every
//! light component (a birth, a hypothesis spread along a hyperbola) each measurement would
//! support three hyperbolas instead of one, and their crossings seed ghosts. On two-talker
//! rooms synthesized outside the project (`tools/speech_scene/`) the model gives 0.362 m and
//! 75 % right counts against 0.405 m and 73 % without it; looked for beside every component,
//! 63 %.

use crate::error::{invalid, FilterError};
use crate::gaussian::Gaussian;

/// Side peaks at `±offset` from an object's measurement, along the measurement's delay entry
/// ([`crate::MeasurementModel::delay_entry`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Echoes {
    /// δ: how far each side peak lies from the direct path's measurement, in the entry's
    /// units (seconds for a TDOA); positive.
    pub offset: f64,
    /// ρ: the expected number of side peaks on each side per detection of the direct path;
    /// positive (a ratio of intensities, so it may exceed 1 where the direct peak is the
    /// one more often missed).
    pub rate: f64,
}

impl Echoes {
    /// Checks that both numbers are positive and finite.
    pub fn validate(&self) -> Result<(), FilterError> {
        if !(self.offset > 0.0 && self.offset.is_finite()) {
            return Err(invalid(
                "echo offset",
                format!("{} is not a finite number > 0", self.offset),
            ));
        }
        if !(self.rate > 0.0 && self.rate.is_finite()) {
            return Err(invalid(
                "echo rate",
                format!("{} is not a finite number > 0", self.rate),
            ));
        }
        Ok(())
    }
}

/// The shifts of one sensor's update: on which entry, by how much, at what log weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EchoShifts {
    /// The measurement entry the side peaks lie along.
    pub(crate) entry: usize,
    /// δ.
    pub(crate) offset: f64,
    /// ln ρ, added to a side-peak hypothesis' log weight.
    pub(crate) log_rate: f64,
}

/// The least weight of a component beside which side peaks are looked for (see the module
/// documentation). On the synthesized rooms 0.1–0.3 give 0.36–0.39 m on fifteen scenes and
/// 0.41–0.44 m on ten more, with right counts 63–76 % that move by noise-sized steps; 0.15 did
/// best on both.
pub const LEAST_WEIGHT: f64 = 0.15;

impl EchoShifts {
    /// The shifts of `echoes` along `entry`.
    pub(crate) fn new(echoes: Echoes, entry: usize) -> Self {
        Self {
            entry,
            offset: echoes.offset,
            log_rate: echoes.rate.ln(),
        }
    }

    /// Whether side peaks are looked for beside `component`.
    pub(crate) fn beside(&self, component: &Gaussian) -> bool {
        component.weight >= LEAST_WEIGHT
    }

    /// The two side-peak hypotheses' shifts of the residual z − ẑ: a side peak at ẑ + δ has
    /// the direct-path residual z − δ − ẑ.
    pub(crate) fn residual_shifts(&self) -> [f64; 2] {
        [-self.offset, self.offset]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_and_rates_must_be_positive() {
        assert!(Echoes {
            offset: 2.8e-4,
            rate: 0.5
        }
        .validate()
        .is_ok());
        for (offset, rate) in [(0.0, 0.5), (-1.0, 0.5), (f64::NAN, 0.5), (1e-4, 0.0)] {
            assert!(Echoes { offset, rate }.validate().is_err());
        }
    }
}
