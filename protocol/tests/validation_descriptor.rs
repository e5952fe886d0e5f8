//! Validation rules of sensor descriptors: one test per rule, each checking the rejection's message.

mod common;

use common::documents::*;
use protocol::{decode, SensorDescriptor, SensorModel, WireFormat};

fn descriptor(literal: &str) -> SensorDescriptor {
    let descriptor: SensorDescriptor = decode(literal.as_bytes(), WireFormat::Json).unwrap();
    descriptor.validate().expect("the literal is valid");
    descriptor
}

/// Applies `change` to the model of `literal`'s descriptor and returns the validation error message.
fn model_error(literal: &str, change: impl FnOnce(&mut SensorModel)) -> String {
    let mut descriptor = descriptor(literal);
    change(&mut descriptor.model);
    descriptor
        .validate()
        .expect_err("must be rejected")
        .to_string()
}

#[test]
fn version_other_than_1_is_rejected() {
    let mut d = descriptor(CAMERA_DESCRIPTOR);
    d.version = 2;
    assert_eq!(
        d.validate().unwrap_err().to_string(),
        "version 2 is not supported, expected 1"
    );
}

#[test]
fn bad_site_or_sensor_chunk_does_not_decode() {
    let bad_sensor = CAMERA_DESCRIPTOR.replace("\"cam1\"", "\"a/b\"");
    let error = decode::<SensorDescriptor>(bad_sensor.as_bytes(), WireFormat::Json).unwrap_err();
    let message = error.to_string();
    assert!(
        message.starts_with("json decode failed: sensor chunk \"a/b\" contains '/'"),
        "{message}"
    );
    let bad_site = CAMERA_DESCRIPTOR.replace("\"default\"", "\"\"");
    let error = decode::<SensorDescriptor>(bad_site.as_bytes(), WireFormat::Json).unwrap_err();
    assert!(error.to_string().contains("site chunk is empty"), "{error}");
}

#[test]
fn detection_probability_outside_0_1_is_rejected() {
    let mut d = descriptor(CAMERA_DESCRIPTOR);
    d.detection_probability = 1.5;
    assert_eq!(
        d.validate().unwrap_err().to_string(),
        "field detection_probability = 1.5 is outside (0, 1]"
    );
    d.detection_probability = 0.0;
    assert_eq!(
        d.validate().unwrap_err().to_string(),
        "field detection_probability = 0 is outside (0, 1]"
    );
    d.detection_probability = 1.0;
    assert!(d.validate().is_ok(), "1 is inside (0, 1]");
}

#[test]
fn negative_clutter_rate_is_rejected() {
    let mut d = descriptor(CAMERA_DESCRIPTOR);
    d.clutter_rate = -0.5;
    assert_eq!(
        d.validate().unwrap_err().to_string(),
        "field clutter_rate = -0.5 is outside [0, inf)"
    );
    d.clutter_rate = 0.0;
    assert!(d.validate().is_ok(), "no clutter is allowed");
}

#[test]
fn negative_or_zero_noise_is_rejected() {
    let message = model_error(CAMERA_DESCRIPTOR, |m| {
        if let SensorModel::Camera(c) = m {
            c.noise_std[1] = -3.0;
        }
    });
    assert_eq!(message, "field model.noise_std[1] = -3 is outside (0, inf)");
    let message = model_error(MIC_PAIR_DESCRIPTOR, |m| {
        if let SensorModel::MicPair(p) = m {
            p.noise_std = 0.0;
        }
    });
    assert_eq!(message, "field model.noise_std = 0 is outside (0, inf)");
    let message = model_error(POSITION_DESCRIPTOR, |m| {
        if let SensorModel::Position(p) = m {
            p.noise_std[2] = 0.0;
        }
    });
    assert_eq!(message, "field model.noise_std[2] = 0 is outside (0, inf)");
}

#[test]
fn non_finite_numbers_in_a_descriptor_are_rejected() {
    let message = model_error(CAMERA_DESCRIPTOR, |m| {
        if let SensorModel::Camera(c) = m {
            c.projection[1][3] = f64::NAN;
        }
    });
    assert_eq!(message, "field model.projection[1][3] = NaN is not finite");
    let message = model_error(LIDAR_DESCRIPTOR, |m| {
        if let SensorModel::Lidar(l) = m {
            l.position[0] = f64::INFINITY;
        }
    });
    assert_eq!(message, "field model.position[0] = inf is not finite");
    let mut d = descriptor(BEARING_RANGE_DESCRIPTOR);
    d.clutter_rate = f64::NEG_INFINITY;
    assert_eq!(
        d.validate().unwrap_err().to_string(),
        "field clutter_rate = -inf is not finite"
    );
    // JSON cannot even carry one: a number too large for f64 does not decode.
    let huge = CAMERA_DESCRIPTOR.replace("\"clutter_rate\": 2.0", "\"clutter_rate\": 1e400");
    let error = decode::<SensorDescriptor>(huge.as_bytes(), WireFormat::Json).unwrap_err();
    assert!(
        error.to_string().starts_with("json decode failed: "),
        "{error}"
    );
}

#[test]
fn zero_length_mic_baseline_is_rejected() {
    let message = model_error(MIC_PAIR_DESCRIPTOR, |m| {
        if let SensorModel::MicPair(p) = m {
            p.mics[1] = p.mics[0];
        }
    });
    assert_eq!(
        message,
        "degenerate mic_pair model: the mics are 0e0 m apart, less than 1e-6 m"
    );
}

#[test]
fn non_positive_speed_of_sound_is_rejected() {
    let message = model_error(MIC_PAIR_DESCRIPTOR, |m| {
        if let SensorModel::MicPair(p) = m {
            p.speed_of_sound = 0.0;
        }
    });
    assert_eq!(
        message,
        "field model.speed_of_sound = 0 is outside (0, inf)"
    );
}

#[test]
fn singular_camera_matrix_is_rejected() {
    let message = model_error(CAMERA_DESCRIPTOR, |m| {
        if let SensorModel::Camera(c) = m {
            // Third row a combination of the first two: rank 2.
            c.projection[2] = [800.0, 800.0, 560.0, -700.0];
        }
    });
    assert!(
        message
            .starts_with("degenerate camera model: the left 3×3 block of projection is singular"),
        "{message}"
    );
    // The test is scale-free: a valid camera in other units stays valid.
    let mut d = descriptor(CAMERA_DESCRIPTOR);
    if let SensorModel::Camera(c) = &mut d.model {
        c.projection = c.projection.map(|row| row.map(|v| v * 1e-6));
    }
    assert!(d.validate().is_ok());
}

#[test]
fn zero_image_size_is_rejected() {
    let message = model_error(CAMERA_DESCRIPTOR, |m| {
        if let SensorModel::Camera(c) = m {
            c.image_size = [640, 0];
        }
    });
    assert_eq!(
        message,
        "degenerate camera model: image_size [640, 0] has a zero side"
    );
}

#[test]
fn non_unit_quaternion_is_rejected() {
    let message = model_error(LIDAR_DESCRIPTOR, |m| {
        if let SensorModel::Lidar(l) = m {
            l.orientation = [1.0, 0.0, 0.0, 0.01];
        }
    });
    assert_eq!(
        message,
        "degenerate lidar model: orientation quaternion has norm 1.0000499987500624, which differs from 1 by \
         more than 1e-6"
    );
    let mut d = descriptor(LIDAR_DESCRIPTOR);
    if let SensorModel::Lidar(l) = &mut d.model {
        l.orientation = [1.0 + 5e-7, 0.0, 0.0, 0.0];
    }
    assert!(d.validate().is_ok(), "within 1e-6 of unit norm");
}

#[test]
fn non_positive_max_range_is_rejected() {
    let message = model_error(LIDAR_DESCRIPTOR, |m| {
        if let SensorModel::Lidar(l) = m {
            l.max_range = 0.0;
        }
    });
    assert_eq!(message, "field model.max_range = 0 is outside (0, inf)");
    let message = model_error(BEARING_RANGE_DESCRIPTOR, |m| {
        if let SensorModel::BearingRange(b) = m {
            b.max_range = -1.0;
        }
    });
    assert_eq!(message, "field model.max_range = -1 is outside (0, inf)");
}

#[test]
fn unordered_elevation_limits_are_rejected() {
    let message = model_error(LIDAR_DESCRIPTOR, |m| {
        if let SensorModel::Lidar(l) = m {
            l.elevation_limits = [0.3, 0.3];
        }
    });
    assert_eq!(
        message,
        "degenerate lidar model: elevation_limits [0.3, 0.3] must satisfy -π/2 ≤ min < max ≤ π/2"
    );
    let message = model_error(LIDAR_DESCRIPTOR, |m| {
        if let SensorModel::Lidar(l) = m {
            l.elevation_limits = [-0.3, 2.0];
        }
    });
    assert!(message.contains("elevation_limits [-0.3, 2]"), "{message}");
}

#[test]
fn empty_position_region_is_rejected() {
    let message = model_error(POSITION_DESCRIPTOR, |m| {
        if let SensorModel::Position(p) = m {
            p.region.max[1] = p.region.min[1];
        }
    });
    assert_eq!(
        message,
        "degenerate position model: region.min[1] = 0 is not below region.max[1] = 0"
    );
}
