//! Measurement models: what a sensor reports about an object at a world point.
//!
//! Every model maps a 3-D world point (metres, z up) to a measurement vector,
//! knows its noise, its state-dependent detection probability and its uniform
//! clutter. The filter turns an object state into a world point through the
//! motion model (`MotionModel::position`), so the same sensor works with any
//! motion model. Kinds and conventions follow the wire contract (PROTOCOL.md).

mod bearing_range;
mod camera;
mod height_prior;
mod lidar;
mod mic_pair;
mod position;

pub use bearing_range::BearingRange;
pub use camera::PinholeCamera;
pub use height_prior::{HeightPrior, DEFAULT_HEIGHT_STD};
pub use lidar::Lidar;
pub use mic_pair::MicPair;
pub use position::PositionSensor;

use std::fmt::Debug;

use serde::Serialize;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use crate::error::{invalid, FilterError};
use crate::linalg::{check_finite_vector, check_spd, wrap_angle};

/// One measurement of a set, with an optional covariance of its own.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// The measured vector.
    pub z: DVector<f64>,
    /// When given, replaces the model's `noise_cov` for this measurement (e.g. a
    /// camera agent that reports estimates of its own single-view filter).
    pub cov: Option<DMatrix<f64>>,
}

impl Measurement {
    /// A measurement with the model's default noise.
    pub fn new(z: DVector<f64>) -> Self {
        Self { z, cov: None }
    }

    /// A measurement with its own noise covariance.
    pub fn with_cov(z: DVector<f64>, cov: DMatrix<f64>) -> Self {
        Self { z, cov: Some(cov) }
    }
}

/// Detection probability and clutter rate, the two numbers every sensor carries.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Detection {
    /// Probability of detecting an object inside the field of view, in (0, 1].
    pub probability: f64,
    /// Mean number of false measurements per set (λ), ≥ 0, spread uniformly over
    /// the measurement region.
    pub clutter_rate: f64,
}

impl Detection {
    /// Checked constructor.
    pub fn new(probability: f64, clutter_rate: f64) -> Result<Self, FilterError> {
        if !(probability > 0.0 && probability <= 1.0) {
            return Err(invalid(
                "detection probability",
                format!("{probability} is not in (0, 1]"),
            ));
        }
        if !(clutter_rate >= 0.0 && clutter_rate.is_finite()) {
            return Err(invalid(
                "clutter rate",
                format!("{clutter_rate} is not a finite number >= 0"),
            ));
        }
        Ok(Self {
            probability,
            clutter_rate,
        })
    }
}

/// What a model may tell the update so that it goes faster; every field's default (none)
/// is right for any model and changes nothing but the speed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UpdateHints {
    /// A measurement entry that is not an angle
    /// ([`MeasurementModel::angular_entries`]): the gated update sorts measurements along
    /// it, so that each component meets only the measurements inside its gate's extent
    /// there instead of every one. `None`: every pair is tested.
    pub index_dim: Option<usize>,
    /// Bytes that determine h entirely: two models with the same key measure every point
    /// alike. The filter remembers the unscented projections of its static births (the
    /// same components at every birth) per key. `None`: they are projected afresh each
    /// time. The built-in models give their type name and their whole serialized selves, so
    /// that no parameter can be left out.
    pub projection_key: Option<Vec<u8>>,
}

/// A sensor's measurement model h(p) + noise, with its field of view and clutter.
pub trait MeasurementModel: Send + Sync + Debug {
    /// Dimension of one measurement vector.
    fn dim(&self) -> usize;

    /// Noise-free measurement h(p) of a 3-D world point, written into `out` (length
    /// `dim()`): the unscented update measures every sigma point of every component, and
    /// must not allocate for each.
    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]);

    /// Noise-free measurement h(p) of a 3-D world point, as a vector of its own.
    fn measure(&self, p: &Vector3<f64>) -> DVector<f64> {
        let mut z = DVector::zeros(self.dim());
        self.measure_into(p, z.as_mut_slice());
        z
    }

    /// Measurement noise covariance R (dim × dim).
    fn noise_cov(&self) -> DMatrix<f64>;

    /// Detection probability of an object at world point `p`: the sensor's
    /// probability inside its field of view, 0 outside it, behind a camera or out
    /// of range.
    fn detection_probability(&self, p: &Vector3<f64>) -> f64;

    /// Where the sensor sees from, for a sensor whose view of an object a nearer one can
    /// block (a camera's centre, a LIDAR's or a radar's position; see [`crate::occlusion`]).
    /// `None` by default: nothing blocks the sensor (a microphone pair hears around people).
    fn line_of_sight_origin(&self) -> Option<Vector3<f64>> {
        None
    }

    /// Whether the sensor detects an object only while it is active (a microphone pair hears
    /// a talker only while the talker talks; see [`crate::activity`]). False by default: the
    /// sensor sees an object whatever it does.
    fn detects_only_active(&self) -> bool {
        false
    }

    /// The measurement entry that is a delay read off a correlation peak (a microphone pair's
    /// TDOA), beside which side peaks appear ([`crate::echoes`]). `None` by default.
    fn delay_entry(&self) -> Option<usize> {
        None
    }

    /// Mean number of clutter measurements per set (λ).
    fn clutter_rate(&self) -> f64;

    /// Uniform clutter density: 1 / volume of the measurement region.
    fn clutter_density(&self) -> f64;

    /// Clutter intensity κ(z) = λ · clutter density (uniform over the region).
    fn clutter_intensity(&self) -> f64 {
        self.clutter_rate() * self.clutter_density()
    }

    /// The entries of a measurement that are angles: the residual z − ẑ wraps them to
    /// [-pi, pi) ([`MeasurementModel::residual`]). None by default.
    fn angular_entries(&self) -> &[usize] {
        &[]
    }

    /// z − ẑ with the [`MeasurementModel::angular_entries`] wrapped to [-pi, pi). The filter
    /// computes every residual this way (from `angular_entries`, without calling this
    /// method), so a model does not override it.
    fn residual(&self, z: &DVector<f64>, zhat: &DVector<f64>) -> DVector<f64> {
        wrapped_residual(z, zhat, self.angular_entries())
    }

    /// What the update may use to go faster on this model; see [`UpdateHints`]. The
    /// default, no hints, is right for any model.
    fn update_hints(&self) -> UpdateHints {
        UpdateHints::default()
    }

    /// `Some(d)` when h(p) = p[..d], i.e. the model is linear in the position and
    /// the exact Kalman update applies; `None` for nonlinear models.
    fn linear_position_dims(&self) -> Option<usize> {
        None
    }

    /// The world point a noise-free measurement `z` comes from, with the covariance the
    /// sensor's default noise maps to there; see [`MeasurementModel::invert_with_noise`].
    fn invert(&self, z: &DVector<f64>) -> Option<(Vector3<f64>, Matrix3<f64>)> {
        self.invert_with_noise(z, &self.noise_cov())
    }

    /// The world point p with h(p) = `z`, and the covariance J R Jᵀ that the measurement
    /// noise `noise` (R) maps to, J the Jacobian of the inverse map at `z` (first order).
    /// Used by measurement-driven birth (Ristic, Clark, Vo & Vo 2012).
    ///
    /// `None` (the default) when one measurement does not determine a point — a camera
    /// pixel is a ray, a TDOA a hyperboloid — or when `z` is malformed or degenerate
    /// (wrong size, non-finite, a range ≤ 0). The covariance is symmetric positive
    /// semi-definite; it can be singular where the inverse map loses a direction (a
    /// LIDAR return exactly along its ±z axis, where azimuth is undefined).
    fn invert_with_noise(
        &self,
        z: &DVector<f64>,
        noise: &DMatrix<f64>,
    ) -> Option<(Vector3<f64>, Matrix3<f64>)> {
        let _ = (z, noise);
        None
    }

    /// Maps `dim()` uniforms in [0, 1) to a point of the measurement region,
    /// uniformly distributed there when the inputs are (used to simulate clutter).
    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError>;

    /// Checks one measurement against this model: size, finiteness, and that its
    /// own covariance (if any) is symmetric positive definite of size dim × dim.
    fn validate(&self, measurement: &Measurement) -> Result<(), FilterError> {
        if measurement.z.len() != self.dim() {
            return Err(FilterError::DimensionMismatch {
                what: "measurement",
                expected: self.dim(),
                found: measurement.z.len(),
            });
        }
        check_finite_vector(&measurement.z, "measurement")?;
        if let Some(cov) = &measurement.cov {
            check_spd(cov, self.dim(), "measurement covariance")?;
        }
        Ok(())
    }
}

/// Checks a per-axis noise standard deviation list and returns the diagonal covariance.
pub(crate) fn diagonal_noise(std: &[f64]) -> Result<DMatrix<f64>, FilterError> {
    if let Some(bad) = std.iter().find(|s| !(**s > 0.0 && s.is_finite())) {
        return Err(invalid(
            "noise standard deviation",
            format!("{bad} is not a finite number > 0"),
        ));
    }
    Ok(DMatrix::from_diagonal(&DVector::from_iterator(
        std.len(),
        std.iter().map(|s| s * s),
    )))
}

/// Checks that exactly `dim` uniforms in [0, 1] were given.
pub(crate) fn check_uniforms(u: &[f64], dim: usize) -> Result<(), FilterError> {
    if u.len() != dim {
        return Err(FilterError::DimensionMismatch {
            what: "clutter uniforms",
            expected: dim,
            found: u.len(),
        });
    }
    if u.iter().any(|x| !(0.0..=1.0).contains(x)) {
        return Err(invalid("clutter uniforms", "values must lie in [0, 1)"));
    }
    Ok(())
}

/// z − ẑ with the components listed in `angular` wrapped to [-pi, pi).
pub(crate) fn wrapped_residual(
    z: &DVector<f64>,
    zhat: &DVector<f64>,
    angular: &[usize],
) -> DVector<f64> {
    let mut r = z - zhat;
    for &i in angular {
        if i < r.len() {
            r[i] = wrap_angle(r[i]);
        }
    }
    r
}

/// z − ẑ into `out` with the components listed in `angular` wrapped to [-pi, pi), without
/// allocating.
#[inline]
pub(crate) fn wrapped_residual_into(z: &[f64], zhat: &[f64], angular: &[usize], out: &mut [f64]) {
    for ((o, a), b) in out.iter_mut().zip(z).zip(zhat) {
        *o = a - b;
    }
    for &i in angular {
        if let Some(r) = out.get_mut(i) {
            *r = wrap_angle(*r);
        }
    }
}

/// The [`UpdateHints`] of a built-in model: measurements indexed along `index_dim`, and
/// projections remembered under the model's type name and the model serialized whole
/// (every field, so that a parameter added later is part of the key without anyone having
/// to remember it; the name, because the serialization does not say which model it is).
pub(crate) fn hints_of<T: Serialize>(model: &T, index_dim: usize) -> UpdateHints {
    let name = std::any::type_name::<T>().as_bytes();
    let mut key = Vec::with_capacity(name.len() + 1 + 8 * 32);
    key.extend_from_slice(name);
    key.push(0);
    UpdateHints {
        index_dim: Some(index_dim),
        projection_key: postcard::to_extend(model, key).ok(),
    }
}

/// True when `z` has `dim` finite entries and `noise` is a finite `dim` × `dim` matrix:
/// the precondition of every `invert_with_noise`.
pub(crate) fn invertible_input(z: &DVector<f64>, noise: &DMatrix<f64>, dim: usize) -> bool {
    z.len() == dim
        && noise.nrows() == dim
        && noise.ncols() == dim
        && z.iter().chain(noise.iter()).all(|x| x.is_finite())
}

/// Checks that a 3-D point given as an array is finite.
pub(crate) fn finite_point(p: [f64; 3], name: &'static str) -> Result<Vector3<f64>, FilterError> {
    if p.iter().all(|x| x.is_finite()) {
        Ok(Vector3::from(p))
    } else {
        Err(FilterError::NonFinite { what: name })
    }
}

/// Checks a strictly positive finite scalar.
pub(crate) fn positive(value: f64, name: &'static str) -> Result<f64, FilterError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(invalid(name, format!("{value} is not a finite number > 0")))
    }
}

/// A model's residual as the update computes it for every pair, without allocating:
/// z − ẑ with the model's angular entries wrapped.
#[derive(Clone, Copy)]
pub(crate) struct Residual<'a> {
    angular: &'a [usize],
}

impl<'a> Residual<'a> {
    /// The residual of `sensor`.
    pub(crate) fn of(sensor: &'a dyn MeasurementModel) -> Self {
        Self {
            angular: sensor.angular_entries(),
        }
    }

    /// z − ẑ (wrapped as the model says) into `out`.
    #[inline]
    pub(crate) fn write(&self, z: &[f64], zhat: &[f64], out: &mut [f64]) {
        wrapped_residual_into(z, zhat, self.angular, out)
    }
}
