//! PCD (Point Cloud Library) files: reading the `x y z [intensity]` fields of ASCII and binary PCD, and writing
//! clouds in either encoding.
//!
//! Written here rather than taken from `pcd-rs` so that every malformed file yields an error naming the exact
//! header line or data line at fault, and so that no size read from a file is trusted before the file is checked
//! to hold that much data. Fields other than x, y, z and intensity (`i` is accepted as an alias) are skipped;
//! values of any numeric type are converted to `f32`. Binary data is read as little-endian, as PCL writes it on
//! every platform it runs on. `binary_compressed` is reported as unsupported.

use super::error::{CloudFileError, CloudFileProblem};
pub use super::pcd_header::PcdEncoding;
use super::pcd_header::{parse_header, FieldKind, PcdField, PcdHeader};
use super::point_cloud::PointCloud;
use std::fmt::Write as _;
use std::path::Path;

/// Reads a PCD file (ASCII or binary) into a cloud; it has intensity if the file has an `intensity` (or `i`) field.
///
/// # Errors
/// [`CloudFileError`] naming the file and the problem: unreadable file, malformed header (with its line), missing
/// x/y/z field, truncated or oversized data, unparsable ASCII values (with their line).
pub fn read_pcd(path: impl AsRef<Path>) -> Result<PointCloud, CloudFileError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| CloudFileError::new(path, e.into()))?;
    decode_pcd(&bytes).map_err(|problem| CloudFileError::new(path, problem))
}

/// Decodes the bytes of a PCD file (see [`read_pcd`]).
///
/// # Errors
/// The [`CloudFileProblem`] found, as for [`read_pcd`].
pub fn decode_pcd(bytes: &[u8]) -> Result<PointCloud, CloudFileProblem> {
    let header = parse_header(bytes)?;
    let layout = RecordLayout::new(&header)?;
    let data = &bytes[header.data_offset..];
    match header.encoding {
        PcdEncoding::Binary => decode_binary(&header, &layout, data),
        PcdEncoding::Ascii => decode_ascii(&header, &layout, data),
    }
}

/// Where one wanted field sits in a record.
#[derive(Debug, Clone)]
struct FieldSlot {
    /// The field's definition.
    field: PcdField,
    /// Byte offset within a binary record.
    byte_offset: usize,
    /// Value index within an ASCII line.
    value_index: usize,
}

/// Positions of x, y, z and the optional intensity within a record, and the record's size.
struct RecordLayout {
    /// x, y, z in that order.
    coordinates: [FieldSlot; 3],
    /// Intensity, if the file has it.
    intensity: Option<FieldSlot>,
    /// Bytes per binary record.
    stride: usize,
    /// Values per ASCII line.
    values_per_point: usize,
}

impl RecordLayout {
    fn new(header: &PcdHeader) -> Result<Self, CloudFileProblem> {
        let mut slots = Vec::with_capacity(header.fields.len());
        let (mut byte_offset, mut value_index) = (0usize, 0usize);
        for field in &header.fields {
            slots.push(FieldSlot {
                field: field.clone(),
                byte_offset,
                value_index,
            });
            // Saturating: absurd COUNTs then show up as a data length mismatch instead of an overflow.
            byte_offset = byte_offset.saturating_add(field.size.saturating_mul(field.count));
            value_index = value_index.saturating_add(field.count);
        }
        let find = |names: &[&str]| {
            slots
                .iter()
                .find(|s| names.contains(&s.field.name.as_str()))
        };
        let single = |slot: &FieldSlot| {
            if slot.field.count == 1 {
                Ok(slot.clone())
            } else {
                Err(CloudFileProblem::PcdFieldCount {
                    // A count other than 1 can only come from a COUNT line, so it is present.
                    line: header.count_line.unwrap_or_default(),
                    field: slot.field.name.clone(),
                    count: slot.field.count,
                })
            }
        };
        let coordinate = |name: &'static str| {
            find(&[name])
                .ok_or(CloudFileProblem::PcdMissingField { field: name })
                .and_then(single)
        };
        Ok(Self {
            coordinates: [coordinate("x")?, coordinate("y")?, coordinate("z")?],
            intensity: find(&["intensity", "i"]).map(single).transpose()?,
            stride: byte_offset,
            values_per_point: value_index,
        })
    }
}

fn decode_binary(
    header: &PcdHeader,
    layout: &RecordLayout,
    data: &[u8],
) -> Result<PointCloud, CloudFileProblem> {
    let expected = header.points.saturating_mul(layout.stride);
    if data.len() != expected {
        return Err(CloudFileProblem::PcdBinaryLength {
            found: data.len(),
            expected,
            points: header.points,
            stride: layout.stride,
        });
    }
    // The length check bounds `points` by the file size, so this allocation is safe.
    let mut points = Vec::with_capacity(header.points);
    let mut intensity = layout
        .intensity
        .as_ref()
        .map(|_| Vec::with_capacity(header.points));
    for record in data.chunks_exact(layout.stride.max(1)).take(header.points) {
        let value = |slot: &FieldSlot| binary_value(&record[slot.byte_offset..], &slot.field);
        let [x, y, z] = &layout.coordinates;
        points.push([value(x), value(y), value(z)]);
        if let (Some(values), Some(slot)) = (intensity.as_mut(), &layout.intensity) {
            values.push(value(slot));
        }
    }
    Ok(PointCloud { points, intensity })
}

/// Decodes one little-endian value of `field` at the start of `bytes` (which holds at least `field.size` bytes).
fn binary_value(bytes: &[u8], field: &PcdField) -> f32 {
    let mut word = [0u8; 8];
    word[..field.size].copy_from_slice(&bytes[..field.size]);
    match (field.kind, field.size) {
        (FieldKind::Float, 4) => f32::from_le_bytes([word[0], word[1], word[2], word[3]]),
        (FieldKind::Float, _) => f64::from_le_bytes(word) as f32,
        (FieldKind::Unsigned, _) => u64::from_le_bytes(word) as f32,
        (FieldKind::Signed, size) => {
            // Sign-extend from the field's width.
            let shift = 64 - 8 * size as u32;
            ((i64::from_le_bytes(word) << shift) >> shift) as f32
        }
    }
}

fn decode_ascii(
    header: &PcdHeader,
    layout: &RecordLayout,
    data: &[u8],
) -> Result<PointCloud, CloudFileProblem> {
    let mut points = Vec::new();
    let mut intensity = layout.intensity.as_ref().map(|_| Vec::new());
    for (index, raw_line) in data.split(|&b| b == b'\n').enumerate() {
        let line = header.data_first_line + index;
        let text = std::str::from_utf8(raw_line)
            .map_err(|_| CloudFileProblem::PcdAsciiNotText { line })?;
        let values: Vec<&str> = text.split_whitespace().collect();
        if values.is_empty() {
            continue;
        }
        if values.len() != layout.values_per_point {
            return Err(CloudFileProblem::PcdAsciiValueCount {
                line,
                found: values.len(),
                expected: layout.values_per_point,
            });
        }
        if points.len() == header.points {
            // One point too many: report it now rather than after parsing the rest.
            return Err(CloudFileProblem::PcdAsciiPointCount {
                found: points.len() + 1,
                expected: header.points,
            });
        }
        let value = |slot: &FieldSlot| ascii_value(values[slot.value_index], &slot.field, line);
        let [x, y, z] = &layout.coordinates;
        points.push([value(x)?, value(y)?, value(z)?]);
        if let (Some(column), Some(slot)) = (intensity.as_mut(), &layout.intensity) {
            column.push(value(slot)?);
        }
    }
    if points.len() != header.points {
        return Err(CloudFileProblem::PcdAsciiPointCount {
            found: points.len(),
            expected: header.points,
        });
    }
    Ok(PointCloud { points, intensity })
}

/// Parses one ASCII value of `field`, checking that it fits the field's declared type.
fn ascii_value(text: &str, field: &PcdField, line: usize) -> Result<f32, CloudFileProblem> {
    let bits = 8 * field.size as u32;
    let parsed = match (field.kind, field.size) {
        // Parsed straight to f32: going through f64 could round twice and miss the written value.
        (FieldKind::Float, 4) => text.parse::<f32>().ok(),
        (FieldKind::Float, _) => text.parse::<f64>().ok().map(|v| v as f32),
        (FieldKind::Unsigned, _) => text
            .parse::<u64>()
            .ok()
            .filter(|&v| bits == 64 || v >> bits == 0)
            .map(|v| v as f32),
        (FieldKind::Signed, _) => text
            .parse::<i64>()
            .ok()
            .filter(|&v| bits == 64 || (v >> (bits - 1) == 0 || v >> (bits - 1) == -1))
            .map(|v| v as f32),
    };
    parsed.ok_or_else(|| CloudFileProblem::PcdAsciiBadNumber {
        line,
        field: field.name.clone(),
        value: text.chars().take(40).collect(),
        kind: field.kind.letter(),
        size_bits: bits as usize,
    })
}

/// Writes a cloud as a PCD v0.7 file with float32 fields `x y z` (and `intensity` when the cloud has it), as an
/// unorganised cloud (`HEIGHT 1`). ASCII values are written in the shortest form that reads back to the same
/// `f32`, so both encodings round-trip exactly.
///
/// # Errors
/// [`CloudFileError`] naming the file when it cannot be written or the intensity channel has the wrong length.
pub fn write_pcd(
    path: impl AsRef<Path>,
    cloud: &PointCloud,
    encoding: PcdEncoding,
) -> Result<(), CloudFileError> {
    let path = path.as_ref();
    let bytes =
        encode_pcd(cloud, encoding).map_err(|problem| CloudFileError::new(path, problem))?;
    std::fs::write(path, bytes).map_err(|e| CloudFileError::new(path, e.into()))
}

/// Encodes a cloud as the bytes of a PCD file (see [`write_pcd`]).
///
/// # Errors
/// [`CloudFileProblem::IntensityLength`] when the intensity channel does not have one value per point.
pub fn encode_pcd(cloud: &PointCloud, encoding: PcdEncoding) -> Result<Vec<u8>, CloudFileProblem> {
    if !cloud.intensity_matches_points() {
        return Err(CloudFileProblem::IntensityLength {
            points: cloud.points.len(),
            intensities: cloud.intensity.as_ref().map_or(0, Vec::len),
        });
    }
    let (fields, sizes, types, counts) = match cloud.intensity {
        Some(_) => ("x y z intensity", "4 4 4 4", "F F F F", "1 1 1 1"),
        None => ("x y z", "4 4 4", "F F F", "1 1 1"),
    };
    let n = cloud.points.len();
    let data_word = match encoding {
        PcdEncoding::Ascii => "ascii",
        PcdEncoding::Binary => "binary",
    };
    let mut text = format!(
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {fields}\nSIZE {sizes}\nTYPE {types}\n\
         COUNT {counts}\nWIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data_word}\n"
    );
    let record = |index: usize| {
        let [x, y, z] = cloud.points[index];
        let intensity = cloud.intensity.as_ref().map(|values| values[index]);
        ([x, y, z], intensity)
    };
    match encoding {
        PcdEncoding::Ascii => {
            for index in 0..n {
                let ([x, y, z], intensity) = record(index);
                // Display of f32 is the shortest decimal that parses back to the same value.
                let _ = write!(text, "{x} {y} {z}");
                if let Some(value) = intensity {
                    let _ = write!(text, " {value}");
                }
                text.push('\n');
            }
            Ok(text.into_bytes())
        }
        PcdEncoding::Binary => {
            let mut bytes = text.into_bytes();
            for index in 0..n {
                let ([x, y, z], intensity) = record(index);
                for value in [x, y, z].into_iter().chain(intensity) {
                    bytes.extend_from_slice(&value.to_le_bytes());
                }
            }
            Ok(bytes)
        }
    }
}
