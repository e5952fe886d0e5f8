//! Serde for [`SensorModel`]: tagged by `kind` in human-readable formats, externally tagged otherwise.
//!
//! The contract's JSON form puts the tag inside the object (`{"kind": "camera", ...}`). Serde reads such an
//! internally tagged enum by buffering the object with `deserialize_any`, which postcard (a format without
//! self-description) cannot do. So the human-readable path (JSON) uses an internally tagged mirror and the
//! compact path (postcard) an externally tagged one, which postcard writes as a variant index and the struct.

use super::model::{
    BearingRangeModel, CameraModel, LidarModel, MicPairModel, PositionModel, SensorModel,
};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Mirror written to human-readable formats: `{"kind": "...", <fields>}`.
#[derive(Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum TaggedRef<'a> {
    Camera(&'a CameraModel),
    MicPair(&'a MicPairModel),
    Lidar(&'a LidarModel),
    BearingRange(&'a BearingRangeModel),
    Position(&'a PositionModel),
}

/// Mirror read from human-readable formats.
#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum Tagged {
    Camera(CameraModel),
    MicPair(MicPairModel),
    Lidar(LidarModel),
    BearingRange(BearingRangeModel),
    Position(PositionModel),
}

/// Mirror written to compact formats: variant index, then the fields.
#[derive(Serialize)]
enum CompactRef<'a> {
    Camera(&'a CameraModel),
    MicPair(&'a MicPairModel),
    Lidar(&'a LidarModel),
    BearingRange(&'a BearingRangeModel),
    Position(&'a PositionModel),
}

/// Mirror read from compact formats.
#[derive(Deserialize)]
enum Compact {
    Camera(CameraModel),
    MicPair(MicPairModel),
    Lidar(LidarModel),
    BearingRange(BearingRangeModel),
    Position(PositionModel),
}

impl Serialize for SensorModel {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if serializer.is_human_readable() {
            match self {
                SensorModel::Camera(m) => TaggedRef::Camera(m),
                SensorModel::MicPair(m) => TaggedRef::MicPair(m),
                SensorModel::Lidar(m) => TaggedRef::Lidar(m),
                SensorModel::BearingRange(m) => TaggedRef::BearingRange(m),
                SensorModel::Position(m) => TaggedRef::Position(m),
            }
            .serialize(serializer)
        } else {
            match self {
                SensorModel::Camera(m) => CompactRef::Camera(m),
                SensorModel::MicPair(m) => CompactRef::MicPair(m),
                SensorModel::Lidar(m) => CompactRef::Lidar(m),
                SensorModel::BearingRange(m) => CompactRef::BearingRange(m),
                SensorModel::Position(m) => CompactRef::Position(m),
            }
            .serialize(serializer)
        }
    }
}

impl<'de> Deserialize<'de> for SensorModel {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        if deserializer.is_human_readable() {
            Ok(match Tagged::deserialize(deserializer)? {
                Tagged::Camera(m) => SensorModel::Camera(m),
                Tagged::MicPair(m) => SensorModel::MicPair(m),
                Tagged::Lidar(m) => SensorModel::Lidar(m),
                Tagged::BearingRange(m) => SensorModel::BearingRange(m),
                Tagged::Position(m) => SensorModel::Position(m),
            })
        } else {
            Ok(match Compact::deserialize(deserializer)? {
                Compact::Camera(m) => SensorModel::Camera(m),
                Compact::MicPair(m) => SensorModel::MicPair(m),
                Compact::Lidar(m) => SensorModel::Lidar(m),
                Compact::BearingRange(m) => SensorModel::BearingRange(m),
                Compact::Position(m) => SensorModel::Position(m),
            })
        }
    }
}
