//! Sensor models: what one measurement of each kind of sensor is, and the parameters that describe it.
//!
//! In JSON a model is an object tagged by `kind` (`{"kind": "camera", "projection": ..., ...}`); the serde
//! impls live in `model_serde.rs` because postcard cannot read an internally tagged enum.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Speed of sound in air at about 20 °C, m/s: the value of `speed_of_sound` when a `mic_pair` omits it.
pub const DEFAULT_SPEED_OF_SOUND: f64 = 343.0;

/// The `kind` of a sensor model, as it appears in JSON (`"camera"`, `"mic_pair"`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SensorKind {
    /// A pinhole camera giving pixel positions `[u, v]`.
    Camera,
    /// Two microphones giving a time difference of arrival `[tau]`.
    MicPair,
    /// A 3-D range scanner giving `[range, azimuth, elevation]` in its own frame.
    Lidar,
    /// A planar sensor (radar, sonar) giving `[bearing, range]`.
    BearingRange,
    /// A sensor giving world positions `[x, y, z]` directly.
    Position,
}

impl SensorKind {
    /// Every kind, in contract order.
    pub const ALL: [SensorKind; 5] = [
        Self::Camera,
        Self::MicPair,
        Self::Lidar,
        Self::BearingRange,
        Self::Position,
    ];

    /// The JSON name of the kind.
    pub fn name(self) -> &'static str {
        match self {
            Self::Camera => "camera",
            Self::MicPair => "mic_pair",
            Self::Lidar => "lidar",
            Self::BearingRange => "bearing_range",
            Self::Position => "position",
        }
    }

    /// Number of values in one measurement of this kind.
    pub fn measurement_dim(self) -> usize {
        match self {
            Self::Camera => 2,
            Self::MicPair => 1,
            Self::Lidar => 3,
            Self::BearingRange => 2,
            Self::Position => 3,
        }
    }
}

impl fmt::Display for SensorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `kind: "camera"`: a pinhole camera; one measurement is `[u, v]` in pixels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraModel {
    /// 3×4 homogeneous projection, world → pixel (rows).
    pub projection: [[f64; 4]; 3],
    /// Image width and height in pixels; a point outside the image is not detectable.
    pub image_size: [u32; 2],
    /// Standard deviations `[σu, σv]` in pixels.
    pub noise_std: [f64; 2],
}

/// `kind: "mic_pair"`: two microphones; one measurement is `[tau]`, tau = (‖x−m₂‖ − ‖x−m₁‖)/c, in seconds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MicPairModel {
    /// World positions of the two microphones `[m₁, m₂]`.
    pub mics: [[f64; 3]; 2],
    /// Speed of sound c in m/s; [`DEFAULT_SPEED_OF_SOUND`] when absent from JSON.
    #[serde(default = "default_speed_of_sound")]
    pub speed_of_sound: f64,
    /// Standard deviation of tau in seconds.
    pub noise_std: f64,
}

impl MicPairModel {
    /// Distance between the two microphones, m: with the speed of sound it bounds |tau| by d/c.
    pub fn baseline(&self) -> f64 {
        let [m1, m2] = self.mics;
        (0..3).map(|i| (m1[i] - m2[i]).powi(2)).sum::<f64>().sqrt()
    }
}

fn default_speed_of_sound() -> f64 {
    DEFAULT_SPEED_OF_SOUND
}

/// `kind: "lidar"`: one measurement is `[range, azimuth, elevation]` in the sensor frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LidarModel {
    /// Sensor origin in the world frame.
    pub position: [f64; 3],
    /// Unit quaternion `[w, x, y, z]` rotating sensor-frame vectors into the world frame.
    pub orientation: [f64; 4],
    /// Standard deviations `[σr, σaz, σel]` (m, rad, rad).
    pub noise_std: [f64; 3],
    /// Largest detectable range in metres.
    pub max_range: f64,
    /// `[min, max]` elevation in radians that the sensor sees.
    pub elevation_limits: [f64; 2],
}

/// `kind: "bearing_range"`: one measurement is `[bearing, range]` in the horizontal plane.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingRangeModel {
    /// Sensor origin in the world frame.
    pub position: [f64; 3],
    /// Standard deviations `[σθ, σr]` (rad, m).
    pub noise_std: [f64; 2],
    /// Largest detectable range in metres.
    pub max_range: f64,
}

/// An axis-aligned box in the world frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// Lower corner `[x, y, z]`.
    pub min: [f64; 3],
    /// Upper corner `[x, y, z]`.
    pub max: [f64; 3],
}

/// `kind: "position"`: one measurement is a world position `[x, y, z]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionModel {
    /// Standard deviations `[σx, σy, σz]` in metres.
    pub noise_std: [f64; 3],
    /// The box the sensor covers (and over which its clutter is spread).
    pub region: Region,
}

/// The `model` of a [`crate::SensorDescriptor`]: one variant per `kind`.
#[derive(Debug, Clone, PartialEq)]
pub enum SensorModel {
    /// `kind: "camera"`.
    Camera(CameraModel),
    /// `kind: "mic_pair"`.
    MicPair(MicPairModel),
    /// `kind: "lidar"`.
    Lidar(LidarModel),
    /// `kind: "bearing_range"`.
    BearingRange(BearingRangeModel),
    /// `kind: "position"`.
    Position(PositionModel),
}

impl SensorModel {
    /// The model's kind.
    pub fn kind(&self) -> SensorKind {
        match self {
            Self::Camera(_) => SensorKind::Camera,
            Self::MicPair(_) => SensorKind::MicPair,
            Self::Lidar(_) => SensorKind::Lidar,
            Self::BearingRange(_) => SensorKind::BearingRange,
            Self::Position(_) => SensorKind::Position,
        }
    }

    /// The JSON `kind` string (`"camera"`, `"mic_pair"`, `"lidar"`, `"bearing_range"`, `"position"`).
    pub fn kind_name(&self) -> &'static str {
        self.kind().name()
    }

    /// Number of values in one measurement: camera 2, mic_pair 1, lidar 3, bearing_range 2, position 3.
    pub fn measurement_dim(&self) -> usize {
        self.kind().measurement_dim()
    }
}
