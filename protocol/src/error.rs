//! The one error type of the crate: every rejection names what was wrong and with which value.

use thiserror::Error;

/// Which kind of key chunk an identifier is (used in error messages).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChunkRole {
    /// The `<site>` chunk of `fusion/<site>/...`.
    Site,
    /// The `<sensor>` chunk of `fusion/<site>/sensors/<sensor>/...`.
    Sensor,
    /// The `<instance>` chunk of `fusion/<site>/server/<instance>/...`.
    Instance,
}

impl std::fmt::Display for ChunkRole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ChunkRole::Site => "site",
            ChunkRole::Sensor => "sensor",
            ChunkRole::Instance => "server instance",
        })
    }
}

/// Everything that can go wrong when building keys, encoding, decoding or validating protocol messages.
#[derive(Debug, Error)]
pub enum ProtocolError {
    /// A message carries a `version` other than [`crate::PROTOCOL_VERSION`].
    #[error("version {found} is not supported, expected {expected}")]
    UnsupportedVersion {
        /// The version the message carried.
        found: u32,
        /// The only version this crate speaks.
        expected: u32,
    },

    /// A site or sensor identifier is empty.
    #[error("{role} chunk is empty")]
    EmptyChunk {
        /// Whether the chunk names a site or a sensor.
        role: ChunkRole,
    },

    /// A site or sensor identifier is longer than [`crate::MAX_CHUNK_LEN`] characters.
    #[error("{role} chunk {value:?} has {len} characters, at most {max} are allowed")]
    ChunkTooLong {
        /// Whether the chunk names a site or a sensor.
        role: ChunkRole,
        /// The offending identifier.
        value: String,
        /// Its length in characters.
        len: usize,
        /// The largest length allowed.
        max: usize,
    },

    /// A site or sensor identifier contains a character outside `[A-Za-z0-9_-]`.
    #[error("{role} chunk {value:?} contains {bad:?}")]
    ChunkBadCharacter {
        /// Whether the chunk names a site or a sensor.
        role: ChunkRole,
        /// The offending identifier.
        value: String,
        /// The first character that is not allowed.
        bad: char,
    },

    /// A key expression does not have the shape of the key it was parsed as.
    #[error("key {key:?} is not a {expected} key: {reason}")]
    MalformedKey {
        /// The key that was parsed.
        key: String,
        /// Which kind of key was expected (e.g. "sensor").
        expected: &'static str,
        /// What is wrong with it.
        reason: String,
    },

    /// A number that must be finite is NaN or infinite.
    #[error("field {field} = {value} is not finite")]
    NonFinite {
        /// Path of the field, e.g. `measurements[3][1]`.
        field: String,
        /// The offending value.
        value: f64,
    },

    /// A number lies outside the interval the contract allows.
    #[error("field {field} = {value} is outside {allowed}")]
    OutOfRange {
        /// Path of the field, e.g. `detection_probability`.
        field: String,
        /// The offending value.
        value: f64,
        /// The allowed interval in mathematical notation, e.g. `(0, 1]`.
        allowed: &'static str,
    },

    /// A sensor model that cannot describe a real sensor (coincident mics, singular camera, ...).
    #[error("degenerate {kind} model: {reason}")]
    DegenerateModel {
        /// The model's `kind` (e.g. `camera`).
        kind: &'static str,
        /// What makes it degenerate.
        reason: String,
    },

    /// A measurement whose number of values does not fit the sensor's kind.
    #[error("measurement {index} has {len} values, a {kind} measurement has {expected}")]
    MeasurementLength {
        /// Index of the measurement in the set.
        index: usize,
        /// Its number of values.
        len: usize,
        /// The sensor's `kind`.
        kind: &'static str,
        /// The number of values that kind of measurement has.
        expected: usize,
    },

    /// A set holds more than [`crate::MAX_MEASUREMENTS`] measurements.
    #[error("set holds {count} measurements, at most {max} are allowed")]
    TooManyMeasurements {
        /// Number of measurements in the set.
        count: usize,
        /// The limit.
        max: usize,
    },

    /// `covariances` does not hold exactly one matrix per measurement.
    #[error("covariances holds {covariances} matrices for {measurements} measurements")]
    CovarianceCount {
        /// Number of matrices.
        covariances: usize,
        /// Number of measurements.
        measurements: usize,
    },

    /// A matrix does not have the size it must have.
    #[error("field {field} must be {expected}×{expected}, found {found}")]
    MatrixShape {
        /// Path of the matrix, e.g. `covariances[1]`.
        field: String,
        /// Its required number of rows and of columns.
        expected: usize,
        /// What was found instead, e.g. `3 rows` or `row 1 with 2 values`.
        found: String,
    },

    /// A covariance matrix is not symmetric.
    #[error(
        "field {field} is not symmetric: [{row}][{col}] = {upper} but [{col}][{row}] = {lower}"
    )]
    NotSymmetric {
        /// Path of the matrix.
        field: String,
        /// Row of the first asymmetric entry (upper triangle).
        row: usize,
        /// Column of the first asymmetric entry (upper triangle).
        col: usize,
        /// The entry `[row][col]`.
        upper: f64,
        /// The entry `[col][row]`.
        lower: f64,
    },

    /// A covariance matrix is symmetric but not positive definite.
    #[error("field {field} is not positive definite (Cholesky pivot {pivot} = {value})")]
    NotPositiveDefinite {
        /// Path of the matrix.
        field: String,
        /// Index of the first non-positive pivot.
        pivot: usize,
        /// The pivot's value before the square root.
        value: f64,
    },

    /// A measurement set names another sensor than the descriptor it is checked against.
    #[error(
        "measurement set is from sensor {set:?} but the descriptor is for sensor {descriptor:?}"
    )]
    SensorMismatch {
        /// Sensor named by the set.
        set: String,
        /// Sensor named by the descriptor.
        descriptor: String,
    },

    /// A live set is stamped too far ahead of the server's clock.
    #[error("stamp {stamp} is {ahead:.3} s ahead of the server clock {now} (at most {max_future_s} s allowed)")]
    StampInFuture {
        /// The set's stamp (s since the Unix epoch).
        stamp: f64,
        /// The server's clock (s since the Unix epoch).
        now: f64,
        /// `stamp - now`.
        ahead: f64,
        /// The configured tolerance.
        max_future_s: f64,
    },

    /// A payload (received or about to be sent) is larger than [`crate::MAX_PAYLOAD_BYTES`].
    #[error("payload of {size} bytes exceeds {max}")]
    PayloadTooLarge {
        /// Size of the payload in bytes.
        size: usize,
        /// The limit in bytes.
        max: usize,
    },

    /// A payload declared as JSON could not be decoded into the expected type.
    #[error("json decode failed: {0}")]
    JsonDecode(#[source] serde_json::Error),

    /// A value could not be written as JSON.
    #[error("json encode failed: {0}")]
    JsonEncode(#[source] serde_json::Error),

    /// A payload declared as postcard could not be decoded into the expected type.
    #[error("postcard decode failed: {0}")]
    PostcardDecode(#[source] postcard::Error),

    /// A postcard payload holds more bytes than the value it encodes.
    #[error("postcard decode failed: {extra} bytes left after the value")]
    PostcardTrailingBytes {
        /// Number of bytes after the end of the value.
        extra: usize,
    },

    /// A value could not be written as postcard.
    #[error("postcard encode failed: {0}")]
    PostcardEncode(#[source] postcard::Error),

    /// A payload's encoding is neither `application/json` nor `application/postcard`.
    #[error("unsupported encoding {0:?}")]
    UnsupportedEncoding(String),

    /// A query's `format` parameter is neither `json` nor `postcard`, or is given twice.
    #[error("query parameter format={0:?} is not one of json, postcard")]
    BadFormatParameter(String),
}
