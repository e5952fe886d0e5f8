//! The message types of the contract, one file per message; their JSON forms are those of shared/PROTOCOL.md.

mod descriptor;
mod measurements;
mod model;
mod model_serde;
mod replay;
mod status;
mod tracks;
mod truth;

pub use descriptor::SensorDescriptor;
pub use measurements::MeasurementSet;
pub use model::{
    BearingRangeModel, CameraModel, LidarModel, MicPairModel, PositionModel, Region, SensorKind,
    SensorModel, DEFAULT_SPEED_OF_SOUND,
};
pub use replay::ReplayLine;
pub use status::{LatencyMs, Rejected, SensorStatus, ServerRole, Status};
pub use tracks::{Track, TrackSet};
pub use truth::{TruthObject, TruthSet};
