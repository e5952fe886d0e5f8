//! Built-in scenarios, also shipped as files under `simulator/scenarios/`.

mod dense;
mod room;

pub use dense::{dense, dense_scaled};
pub use room::{default_room, ROOM_FLOOR, ROOM_HEIGHT};

use protocol::SensorId;

/// The id of a preset's sensor, from a literal name.
fn preset_sensor_id(name: &'static str) -> SensorId {
    // Preset names are literals of `[a-z0-9_]`, valid chunks by construction; every preset
    // is built (and validated) by the tests, so this cannot fire at run time.
    SensorId::new(name).expect("preset sensor names are valid key chunks")
}
