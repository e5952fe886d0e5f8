//! The bridge from the wire contract's [`SensorDescriptor`] to the filter's measurement
//! models.
//!
//! [`measurement_model`] maps each `kind` of PROTOCOL.md to its `gmphd` model, carrying the
//! descriptor's detection probability and clutter rate:
//!
//! | kind | model | measurement |
//! |---|---|---|
//! | `camera` | [`gmphd::PinholeCamera`] | `[u, v]` px through the 3×4 projection |
//! | `mic_pair` | [`gmphd::MicPair`] (planar at the pair's height when the pair is horizontal) | `[tau]`, tau = (‖x−m₂‖ − ‖x−m₁‖)/c |
//! | `lidar` | [`gmphd::Lidar`] | `[range, azimuth, elevation]` in the sensor frame |
//! | `bearing_range` | [`gmphd::BearingRange`] | `[bearing, range]` in the horizontal plane |
//! | `position` | [`gmphd::PositionSensor`] | `[x, y, z]` world |
//!
//! ```
//! use protocol::{CameraModel, SensorDescriptor, SensorId, SensorModel, Site};
//!
//! let camera = SensorModel::Camera(CameraModel {
//!     projection: [[800.0, 0.0, 320.0, -400.0], [0.0, 800.0, 240.0, -300.0], [0.0, 0.0, 1.0, -2.0]],
//!     image_size: [640, 480],
//!     noise_std: [3.0, 3.0],
//! });
//! let descriptor = SensorDescriptor::new(Site::default(), SensorId::new("cam1")?, camera, 0.95, 2.0);
//! let model = sensor_models::measurement_model(&descriptor)?;
//! assert_eq!(model.dim(), 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

mod error;

pub use error::Error;

use gmphd::{
    BearingRange, Detection, Lidar, MeasurementModel, MicPair, PinholeCamera, PositionSensor,
};
use nalgebra::Matrix3x4;
use protocol::{SensorDescriptor, SensorModel, PROTOCOL_VERSION};

/// Largest height difference (m) between a pair's microphones for which the pair counts as
/// horizontal.
pub const HORIZONTAL_PAIR_TOLERANCE_M: f64 = 0.01;

/// A microphone pair's model: Pham's planar model (sources at the pair's height) when the
/// pair is horizontal, since such a pair does not observe height ([`MicPair::in_plane`]);
/// the 3-D model otherwise.
fn mic_pair(
    pair: &protocol::MicPairModel,
    detection: Detection,
) -> Result<Box<dyn MeasurementModel>, gmphd::FilterError> {
    let [m1, m2] = pair.mics;
    let model = MicPair::new(m1, m2, pair.speed_of_sound, pair.noise_std, detection)?;
    let model = if (m1[2] - m2[2]).abs() <= HORIZONTAL_PAIR_TOLERANCE_M {
        model.in_plane(0.5 * (m1[2] + m2[2]))?
    } else {
        model
    };
    Ok(Box::new(model))
}

/// The measurement model a descriptor describes, with its detection probability and
/// clutter rate.
pub fn measurement_model(
    descriptor: &SensorDescriptor,
) -> Result<Box<dyn MeasurementModel>, Error> {
    let sensor = descriptor.sensor.as_str();
    if descriptor.version != PROTOCOL_VERSION {
        return Err(Error::UnsupportedVersion {
            sensor: sensor.to_owned(),
            version: descriptor.version,
            expected: PROTOCOL_VERSION,
        });
    }
    let detection = Detection::new(descriptor.detection_probability, descriptor.clutter_rate)
        .map_err(|source| Error::Detection {
            sensor: sensor.to_owned(),
            source,
        })?;
    let model: Result<Box<dyn MeasurementModel>, _> = match &descriptor.model {
        SensorModel::Camera(camera) => {
            let [width, height] = camera.image_size;
            PinholeCamera::new(
                Matrix3x4::from_fn(|r, c| camera.projection[r][c]),
                [f64::from(width), f64::from(height)],
                camera.noise_std,
                detection,
            )
            .map(|m| Box::new(m) as Box<dyn MeasurementModel>)
        }
        SensorModel::MicPair(pair) => mic_pair(pair, detection),
        SensorModel::Lidar(lidar) => Lidar::new(
            lidar.position,
            lidar.orientation,
            lidar.noise_std,
            lidar.max_range,
            lidar.elevation_limits,
            detection,
        )
        .map(|m| Box::new(m) as Box<dyn MeasurementModel>),
        SensorModel::BearingRange(radar) => {
            BearingRange::new(radar.position, radar.noise_std, radar.max_range, detection)
                .map(|m| Box::new(m) as Box<dyn MeasurementModel>)
        }
        SensorModel::Position(position) => PositionSensor::new(
            &position.noise_std,
            &position.region.min,
            &position.region.max,
            detection,
        )
        .map(|m| Box::new(m) as Box<dyn MeasurementModel>),
    };
    model.map_err(|source| Error::Model {
        sensor: sensor.to_owned(),
        kind: descriptor.model.kind(),
        source,
    })
}
