//! The wire contract of the fusion service, version 1: the only place the rest of the code learns it from.
//!
//! The contract itself is `shared/PROTOCOL.md` (edge agents → Zenoh → fusion server, and any outside client
//! with nothing but that page); where this crate and the page disagree, the crate is wrong or the page must
//! change first. In short:
//!
//! - **Keys** ([`keys`]): everything of a deployment lives under `fusion/<site>`. Each edge agent writes
//!   `fusion/<site>/sensors/<sensor>/descriptor` ([`SensorDescriptor`], put and queryable),
//!   `.../measurements` ([`MeasurementSet`], one put per scan, empty sets included) and holds the liveliness
//!   token `.../alive`. The server writes `fusion/<site>/tracks` ([`TrackSet`]) and answers
//!   `fusion/<site>/status` ([`Status`]); simulators put `fusion/<site>/truth` ([`TruthSet`]). `<site>` and
//!   `<sensor>` are single chunks of `[A-Za-z0-9_-]`, 1 to 64 characters ([`Site`], [`SensorId`]).
//! - **Encodings** ([`codec`]): every payload says `application/json` or `application/postcard` (the default
//!   between our own programs); a receiver decides by that, never by sniffing. A query picks the reply's form
//!   with `format=json|postcard`. Payloads over [`MAX_PAYLOAD_BYTES`] are refused.
//! - **Messages** ([`messages`]): field names and JSON shapes are part of the contract. Matrices are arrays of
//!   rows, absent optional values are written as `null` (an omitted one is read as `null`), a sensor model
//!   is an object tagged by `kind`
//!   (`camera`, `mic_pair`, `lidar`, `bearing_range`, `position`). Unknown fields are rejected. World frame:
//!   right-handed, metres, `z` up; angles in radians; `stamp` is capture time in seconds since the Unix epoch.
//! - **Replay files**: JSON Lines, each input line one [`ReplayLine`], each output line one [`TrackSet`].
//! - **Validation** ([`validate`]): `validate()` on every message applies the rules of the page's
//!   "Validation" section; a payload that does not decode or validate must never reach the filter.
//!
//! ```
//! use protocol::{decode, encode, keys, MeasurementSet, SensorId, Site, WireFormat};
//!
//! let site = Site::default();
//! let sensor = SensorId::new("cam1")?;
//! assert_eq!(keys::measurements_key(&site, &sensor), "fusion/default/sensors/cam1/measurements");
//!
//! let set = MeasurementSet::new(sensor, 42, 1763700000.04, vec![vec![320.5, 240.1]]);
//! set.validate()?;
//! let bytes = encode(&set, WireFormat::Postcard)?;
//! let back: MeasurementSet = decode(&bytes, WireFormat::from_encoding_str("application/postcard")?)?;
//! assert_eq!(back, set);
//! # Ok::<(), protocol::ProtocolError>(())
//! ```

#![warn(missing_docs)]

pub mod codec;
#[cfg(feature = "zenoh")]
mod codec_zenoh;
pub mod error;
pub mod ids;
pub mod keys;
pub mod messages;
pub mod validate;

pub use codec::{decode, encode, WireFormat, JSON_ENCODING, POSTCARD_ENCODING};
pub use error::{ChunkRole, ProtocolError};
pub use ids::{InstanceId, SensorId, Site, DEFAULT_SITE, MAX_CHUNK_LEN};
pub use keys::{parse_sensor_key, parse_site_key, SensorKeyKind, SiteKeyKind};
pub use messages::{
    BearingRangeModel, CameraModel, LatencyMs, LidarModel, MeasurementSet, MicPairModel,
    PositionModel, Region, Rejected, ReplayLine, SensorDescriptor, SensorKind, SensorModel,
    SensorStatus, ServerRole, Status, Track, TrackSet, TruthObject, TruthSet,
    DEFAULT_SPEED_OF_SOUND,
};

/// The protocol version every message carries in its `version` field.
pub const PROTOCOL_VERSION: u32 = 1;

/// Most measurements one [`MeasurementSet`] may hold.
pub const MAX_MEASUREMENTS: usize = 10_000;

/// Largest payload, in bytes, that is sent or accepted (1 MiB).
pub const MAX_PAYLOAD_BYTES: usize = 1 << 20;
