//! Errors of the LIDAR front end: point-cloud files that cannot be read or written, and invalid configurations.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// A point-cloud file could not be read or written. The message starts with the file's path, then the problem,
/// e.g. `scan.bin: length 1001 bytes is not a multiple of 16 (one x, y, z, intensity record of 4 float32)`.
#[derive(Debug, Error)]
#[error("{}: {problem}", path.display())]
pub struct CloudFileError {
    /// The file that was being read or written.
    pub path: PathBuf,
    /// What was wrong with it.
    pub problem: CloudFileProblem,
}

impl CloudFileError {
    /// Ties a problem to the file it was found in.
    pub fn new(path: &Path, problem: CloudFileProblem) -> Self {
        Self {
            path: path.to_path_buf(),
            problem,
        }
    }
}

/// What was wrong with a point-cloud file (see [`CloudFileError`], which adds the file name).
///
/// Line numbers are 1-based lines of the file; PCD header and ASCII data lines share one count.
#[derive(Debug, Error)]
pub enum CloudFileProblem {
    /// The operating system refused to read or write the file.
    #[error("{0}")]
    Io(#[from] std::io::Error),

    /// The file's extension names no supported format.
    #[error("unknown point-cloud extension '{extension}' (expected .pcd or .bin)")]
    UnknownExtension {
        /// The extension found (lower case, empty if none).
        extension: String,
    },

    /// A KITTI velodyne file is not a whole number of 16-byte records.
    #[error("length {length} bytes is not a multiple of 16 (one x, y, z, intensity record of 4 float32)")]
    KittiLength {
        /// File length in bytes.
        length: usize,
    },

    /// The PCD header ended (end of file) before its `DATA` line.
    #[error("header ends at line {line} without a DATA line (truncated, or not a PCD file)")]
    PcdHeaderUnterminated {
        /// Last line of the file.
        line: usize,
    },

    /// A PCD header line is not valid UTF-8 text.
    #[error("header line {line} is not text (not a PCD file?)")]
    PcdHeaderNotText {
        /// The offending line.
        line: usize,
    },

    /// A PCD header line starts with a keyword the format does not define.
    #[error("header line {line}: unknown keyword '{keyword}'")]
    PcdUnknownKeyword {
        /// The offending line.
        line: usize,
        /// The keyword found.
        keyword: String,
    },

    /// A PCD header keyword appears twice.
    #[error("header line {line}: {keyword} appears a second time")]
    PcdDuplicateKeyword {
        /// The line of the second occurrence.
        line: usize,
        /// The repeated keyword.
        keyword: &'static str,
    },

    /// A required PCD header keyword is absent.
    #[error("header has no {keyword} line")]
    PcdMissingKeyword {
        /// The missing keyword.
        keyword: &'static str,
    },

    /// A PCD header value does not parse or is out of range.
    #[error("header line {line}: {keyword} value '{value}' is not {expected}")]
    PcdBadValue {
        /// The offending line.
        line: usize,
        /// The keyword whose value is bad.
        keyword: &'static str,
        /// The value found.
        value: String,
        /// What was expected, e.g. "a non-negative integer".
        expected: &'static str,
    },

    /// A PCD header line has the wrong number of values.
    #[error("header line {line}: {keyword} has {found} values, expected {expected}")]
    PcdValueCount {
        /// The offending line.
        line: usize,
        /// The keyword whose value list has the wrong length.
        keyword: &'static str,
        /// Number of values found.
        found: usize,
        /// Number of values expected (for SIZE, TYPE and COUNT: one per field).
        expected: usize,
    },

    /// A PCD `TYPE` entry is not `I`, `U` or `F`.
    #[error("header line {line}: unknown field type '{found}' (expected I, U or F)")]
    PcdUnknownFieldType {
        /// The TYPE line.
        line: usize,
        /// The type letter found.
        found: String,
    },

    /// A PCD field has a type/size combination no PCD writer produces (e.g. `F` of 2 bytes).
    #[error("header line {line}: field '{field}' of type {kind} cannot have size {size} bytes")]
    PcdUnsupportedFieldSize {
        /// The SIZE line.
        line: usize,
        /// The field's name.
        field: String,
        /// The field's type letter.
        kind: char,
        /// The size found.
        size: usize,
    },

    /// A coordinate or intensity field has `COUNT` other than 1.
    #[error("header line {line}: field '{field}' has COUNT {count}, expected 1")]
    PcdFieldCount {
        /// The COUNT line.
        line: usize,
        /// The field's name.
        field: String,
        /// The count found.
        count: usize,
    },

    /// The PCD file lacks one of the x, y, z fields.
    #[error("no '{field}' field (a cloud needs x, y and z)")]
    PcdMissingField {
        /// The missing field's name.
        field: &'static str,
    },

    /// `POINTS` disagrees with `WIDTH × HEIGHT`.
    #[error("header line {line}: POINTS {points} differs from WIDTH {width} × HEIGHT {height}")]
    PcdPointCount {
        /// The POINTS line.
        line: usize,
        /// POINTS value.
        points: usize,
        /// WIDTH value.
        width: usize,
        /// HEIGHT value.
        height: usize,
    },

    /// The PCD data encoding is one this reader does not decode.
    #[error(
        "header line {line}: DATA encoding '{encoding}' is not supported (use ascii or binary)"
    )]
    PcdUnsupportedEncoding {
        /// The DATA line.
        line: usize,
        /// The encoding found.
        encoding: String,
    },

    /// Binary PCD data is shorter or longer than the header promises.
    #[error(
        "binary data is {found} bytes but POINTS {points} × {stride} bytes per point needs {expected}"
    )]
    PcdBinaryLength {
        /// Bytes present after the header.
        found: usize,
        /// Bytes the header promises.
        expected: usize,
        /// POINTS value.
        points: usize,
        /// Bytes per point.
        stride: usize,
    },

    /// An ASCII PCD data line has the wrong number of values.
    #[error("data line {line}: {found} values, expected {expected}")]
    PcdAsciiValueCount {
        /// The offending line.
        line: usize,
        /// Values found.
        found: usize,
        /// Values per point the header promises.
        expected: usize,
    },

    /// An ASCII PCD value does not parse as its field's type.
    #[error("data line {line}: field '{field}' value '{value}' is not a number of type {kind}{size_bits}")]
    PcdAsciiBadNumber {
        /// The offending line.
        line: usize,
        /// The field's name.
        field: String,
        /// The text found.
        value: String,
        /// The field's type letter.
        kind: char,
        /// The field's width in bits.
        size_bits: usize,
    },

    /// ASCII PCD data has a different number of points than the header promises.
    #[error("ascii data has {found} points but POINTS says {expected}")]
    PcdAsciiPointCount {
        /// Points found.
        found: usize,
        /// POINTS value.
        expected: usize,
    },

    /// ASCII PCD data is not valid UTF-8 text.
    #[error("data line {line} is not text")]
    PcdAsciiNotText {
        /// The offending line.
        line: usize,
    },

    /// A cloud handed to a writer has an intensity channel of the wrong length.
    #[error("cloud has {points} points but {intensities} intensity values")]
    IntensityLength {
        /// Number of points.
        points: usize,
        /// Number of intensity values.
        intensities: usize,
    },
}

/// A [`crate::lidar::LidarConfig`] value that the pipeline cannot run with.
#[derive(Debug, Error, PartialEq)]
pub enum LidarConfigError {
    /// A length or threshold that must be a positive, finite number is not.
    #[error("{name} must be a positive finite number, got {value}")]
    NotPositive {
        /// The configuration key.
        name: &'static str,
        /// The value given.
        value: f64,
    },

    /// A height threshold is not finite.
    #[error("{name} must be finite, got {value}")]
    NotFinite {
        /// The configuration key.
        name: &'static str,
        /// The value given.
        value: f64,
    },

    /// A length that must be a finite number of at least 0 is not.
    #[error("{name} must be a finite number ≥ 0, got {value}")]
    Negative {
        /// The configuration key.
        name: &'static str,
        /// The value given.
        value: f64,
    },

    /// A count that must be at least some minimum is below it.
    #[error("{name} must be at least {minimum}, got {value}")]
    TooSmall {
        /// The configuration key.
        name: &'static str,
        /// The value given.
        value: usize,
        /// The smallest allowed value.
        minimum: usize,
    },

    /// The maximum cluster size is below the minimum.
    #[error("max_points ({max}) is below min_points ({min})")]
    ClusterSizeRange {
        /// Minimum points per cluster.
        min: usize,
        /// Maximum points per cluster.
        max: usize,
    },

    /// The RANSAC tilt limit is outside (0°, 90°].
    #[error("max_tilt_deg must be in (0, 90], got {0}")]
    TiltOutOfRange(f64),
}
