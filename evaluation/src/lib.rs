//! Tracks against the truth, for the offline replay (`fusion-server replay`) and the clients that
//! watch a live deployment (`fusion-checker`, `fusion-demo`, the integration tests): one place,
//! so that every program reports the same figures for the same tracks.
//!
//! * [`score()`] pairs each track set with the truth set nearest in time and scores it with
//!   [`gmphd::metrics`]' OSPA and GOSPA (c = 1 m, p = 1) on the positions, with both counts;
//! * [`mean_ospa`] and [`mean_gospa`] average those scores from a stamp on;
//! * [`plot()`] draws tracks over truth and the OSPA curve into an SVG file.
//!
//! Nothing here runs a filter or touches the network: it reads protocol `TrackSet`s and
//! `TruthSet`s, however they were obtained.

mod means;
pub mod plot;
pub mod score;

pub use means::{mean_gospa, mean_ospa};
pub use plot::{plot, PlotData};
pub use score::{score, Score, TRUTH_TOLERANCE_S};
