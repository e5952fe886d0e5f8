//! Validation: every rule of shared/PROTOCOL.md "Validation", as `validate()` methods on the messages.
//!
//! Decoding already rejects a wrong shape, an unknown field and a bad `site`/`sensor` chunk (the identifier
//! types check themselves); the codec rejects payloads over 1 MiB. What is left is checked here:
//! - `version` ≠ 1;
//! - any non-finite number, anywhere;
//! - `detection_probability` outside (0, 1], a negative `clutter_rate`;
//! - noise: every `noise_std` must be > 0 (a zero deviation would make the likelihood singular), as must
//!   `speed_of_sound`, `max_range` and the sizes in `image_size`;
//! - a degenerate model: mics closer than [`MIN_MIC_BASELINE_M`], a camera whose left 3×3 block is singular
//!   (|det| below [`CAMERA_SINGULARITY_TOLERANCE`] times the product of its row norms), a lidar quaternion whose
//!   norm differs from 1 by more than [`QUATERNION_NORM_TOLERANCE`], elevation limits not ordered within
//!   [−π/2, π/2], a position region whose `min` is not below `max` on every axis;
//! - more than 10 000 measurements in a set; a measurement whose length does not fit the sensor's kind
//!   ([`crate::MeasurementSet::validate_against`]);
//! - a covariance of the wrong size, not symmetric (to [`SYMMETRY_RELATIVE_TOLERANCE`] of its largest entry)
//!   or not positive definite (a Cholesky pivot ≤ 0); this holds for track covariances too;
//! - a live set stamped more than `max_future_s` ahead of the server's clock
//!   ([`crate::MeasurementSet::validate_stamp`]).
//!
//! Beyond the page, tracks must have `weight` ≥ 0 and the set `expected_count` ≥ 0, and a status
//! must have non-negative `uptime_s` and latencies: anything else is not a PHD or a duration.

mod checks;
mod matrix;
mod messages;
mod model;

pub use matrix::check_covariance;

/// Largest |a_ij − a_ji| of a covariance, relative to its largest absolute entry, still taken as symmetric.
pub const SYMMETRY_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Largest allowed difference between a lidar quaternion's norm and 1.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// Shortest mic-pair baseline in metres; a shorter one measures nothing.
pub const MIN_MIC_BASELINE_M: f64 = 1e-6;

/// Smallest |det| of a camera's left 3×3 block relative to the product of its row norms (1 for orthogonal rows).
pub const CAMERA_SINGULARITY_TOLERANCE: f64 = 1e-9;
