//! Validation of sensor descriptors and their models: finite, noise > 0, not degenerate.

use super::checks::{
    check_all_finite, check_all_positive, check_non_negative, check_positive, check_probability,
    check_version,
};
use super::{CAMERA_SINGULARITY_TOLERANCE, MIN_MIC_BASELINE_M, QUATERNION_NORM_TOLERANCE};
use crate::error::ProtocolError;
use crate::messages::{
    BearingRangeModel, CameraModel, LidarModel, MicPairModel, PositionModel, SensorDescriptor,
    SensorModel,
};
use std::f64::consts::FRAC_PI_2;

impl SensorDescriptor {
    /// Checks the descriptor against the contract: version, model, `detection_probability` in (0, 1],
    /// `clutter_rate` ≥ 0, every number finite.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        check_version(self.version)?;
        self.model.validate()?;
        check_probability(self.detection_probability, "detection_probability")?;
        check_non_negative(self.clutter_rate, "clutter_rate")
    }
}

impl SensorModel {
    /// Checks that every number is finite, every noise deviation is > 0 and the model is not degenerate.
    pub fn validate(&self) -> Result<(), ProtocolError> {
        match self {
            SensorModel::Camera(m) => validate_camera(m),
            SensorModel::MicPair(m) => validate_mic_pair(m),
            SensorModel::Lidar(m) => validate_lidar(m),
            SensorModel::BearingRange(m) => validate_bearing_range(m),
            SensorModel::Position(m) => validate_position(m),
        }
    }
}

/// Rejects a non-finite entry of a matrix given as rows; entries are named `field[i][j]`.
fn check_rows_finite<R: AsRef<[f64]>>(rows: &[R], field: &str) -> Result<(), ProtocolError> {
    for (i, row) in rows.iter().enumerate() {
        check_all_finite(row.as_ref(), |j| format!("{field}[{i}][{j}]"))?;
    }
    Ok(())
}

/// The error for a model of `kind` that cannot describe a real sensor.
fn degenerate(kind: &'static str, reason: String) -> ProtocolError {
    ProtocolError::DegenerateModel { kind, reason }
}

fn validate_camera(m: &CameraModel) -> Result<(), ProtocolError> {
    check_rows_finite(&m.projection, "model.projection")?;
    check_all_positive(&m.noise_std, "model.noise_std")?;
    if m.image_size.contains(&0) {
        return Err(degenerate(
            "camera",
            format!("image_size {:?} has a zero side", m.image_size),
        ));
    }
    // det(M) / (‖r₀‖‖r₁‖‖r₂‖) lies in [0, 1] (Hadamard) whatever the focal length's units: a scale-free test.
    let [r0, r1, r2] = m.projection.map(|row| [row[0], row[1], row[2]]);
    let det = r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
        + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]);
    let norm = |r: [f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    let scale = norm(r0) * norm(r1) * norm(r2);
    let relative = if scale > 0.0 { det.abs() / scale } else { 0.0 };
    if !(relative.is_finite() && relative >= CAMERA_SINGULARITY_TOLERANCE) {
        return Err(degenerate(
            "camera",
            format!(
                "the left 3×3 block of projection is singular (|det| = {:e}, {relative:e} of the product of its \
                 row norms, below {CAMERA_SINGULARITY_TOLERANCE:e})",
                det.abs()
            ),
        ));
    }
    Ok(())
}

fn validate_mic_pair(m: &MicPairModel) -> Result<(), ProtocolError> {
    check_rows_finite(&m.mics, "model.mics")?;
    check_positive(m.speed_of_sound, "model.speed_of_sound")?;
    check_positive(m.noise_std, "model.noise_std")?;
    let [m1, m2] = m.mics;
    let baseline =
        ((m2[0] - m1[0]).powi(2) + (m2[1] - m1[1]).powi(2) + (m2[2] - m1[2]).powi(2)).sqrt();
    if baseline < MIN_MIC_BASELINE_M {
        return Err(degenerate(
            "mic_pair",
            format!("the mics are {baseline:e} m apart, less than {MIN_MIC_BASELINE_M:e} m"),
        ));
    }
    Ok(())
}

fn validate_lidar(m: &LidarModel) -> Result<(), ProtocolError> {
    check_all_finite(&m.position, |i| format!("model.position[{i}]"))?;
    check_all_finite(&m.orientation, |i| format!("model.orientation[{i}]"))?;
    check_all_finite(&m.elevation_limits, |i| {
        format!("model.elevation_limits[{i}]")
    })?;
    check_all_positive(&m.noise_std, "model.noise_std")?;
    check_positive(m.max_range, "model.max_range")?;
    let norm = m.orientation.iter().map(|q| q * q).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(degenerate(
            "lidar",
            format!(
                "orientation quaternion has norm {norm}, which differs from 1 by more than \
                 {QUATERNION_NORM_TOLERANCE:e}"
            ),
        ));
    }
    let [min, max] = m.elevation_limits;
    if min >= max || min < -FRAC_PI_2 || max > FRAC_PI_2 {
        return Err(degenerate(
            "lidar",
            format!("elevation_limits [{min}, {max}] must satisfy -π/2 ≤ min < max ≤ π/2"),
        ));
    }
    Ok(())
}

fn validate_bearing_range(m: &BearingRangeModel) -> Result<(), ProtocolError> {
    check_all_finite(&m.position, |i| format!("model.position[{i}]"))?;
    check_all_positive(&m.noise_std, "model.noise_std")?;
    check_positive(m.max_range, "model.max_range")
}

fn validate_position(m: &PositionModel) -> Result<(), ProtocolError> {
    check_all_positive(&m.noise_std, "model.noise_std")?;
    check_all_finite(&m.region.min, |i| format!("model.region.min[{i}]"))?;
    check_all_finite(&m.region.max, |i| format!("model.region.max[{i}]"))?;
    for axis in 0..3 {
        let (min, max) = (m.region.min[axis], m.region.max[axis]);
        if min >= max {
            return Err(degenerate(
                "position",
                format!("region.min[{axis}] = {min} is not below region.max[{axis}] = {max}"),
            ));
        }
    }
    Ok(())
}
