//! The text header of a PCD (Point Cloud Library) file: parsing and validation.
//!
//! A header is a sequence of `KEYWORD values…` lines (comments start with `#`), ending with the `DATA` line; the
//! point data follows right after that line. See the PCL file-format documentation for the keywords.

use super::error::CloudFileProblem;

/// How a PCD field's values are stored: signed integer, unsigned integer or IEEE float.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum FieldKind {
    /// `I`: signed integer.
    Signed,
    /// `U`: unsigned integer.
    Unsigned,
    /// `F`: floating point.
    Float,
}

impl FieldKind {
    /// The header's letter for this kind.
    pub(super) fn letter(self) -> char {
        match self {
            Self::Signed => 'I',
            Self::Unsigned => 'U',
            Self::Float => 'F',
        }
    }
}

/// One field (column) of a PCD record.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PcdField {
    /// Field name, e.g. `x` or `intensity` (`_` marks padding).
    pub name: String,
    /// Storage kind.
    pub kind: FieldKind,
    /// Bytes per element.
    pub size: usize,
    /// Elements per point.
    pub count: usize,
}

/// How the point data after the header is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PcdEncoding {
    /// One text line per point, values separated by spaces.
    Ascii,
    /// Packed little-endian records, one per point, fields in header order.
    Binary,
}

/// A validated PCD header and where its data starts.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct PcdHeader {
    /// Fields in record order.
    pub fields: Vec<PcdField>,
    /// Number of points (`POINTS`, equal to `WIDTH × HEIGHT`).
    pub points: usize,
    /// Data encoding.
    pub encoding: PcdEncoding,
    /// Byte offset of the first data byte in the file.
    pub data_offset: usize,
    /// File line number of the first data line (for ASCII error messages).
    pub data_first_line: usize,
    /// File line number of the COUNT line, if the header has one (for error messages).
    pub count_line: Option<usize>,
}

/// A header line's values with the line number they came from.
type HeaderEntry = Option<(usize, Vec<String>)>;

/// Raw header entries, before validation.
#[derive(Default)]
struct RawHeader {
    version: HeaderEntry,
    fields: HeaderEntry,
    size: HeaderEntry,
    kind: HeaderEntry,
    count: HeaderEntry,
    width: HeaderEntry,
    height: HeaderEntry,
    viewpoint: HeaderEntry,
    points: HeaderEntry,
    data: HeaderEntry,
}

/// Parses and validates the header at the start of `bytes`.
pub(super) fn parse_header(bytes: &[u8]) -> Result<PcdHeader, CloudFileProblem> {
    let mut raw = RawHeader::default();
    let mut offset = 0;
    let mut line = 0;
    while raw.data.is_none() {
        if offset >= bytes.len() {
            return Err(CloudFileProblem::PcdHeaderUnterminated { line });
        }
        line += 1;
        let end = bytes[offset..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |p| offset + p);
        let text = std::str::from_utf8(&bytes[offset..end])
            .map_err(|_| CloudFileProblem::PcdHeaderNotText { line })?;
        offset = (end + 1).min(bytes.len());
        let mut tokens = text.split_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        if keyword.starts_with('#') {
            continue;
        }
        let (name, slot) = match keyword {
            "VERSION" => ("VERSION", &mut raw.version),
            // COLUMNS is the pre-0.7 spelling of FIELDS.
            "FIELDS" | "COLUMNS" => ("FIELDS", &mut raw.fields),
            "SIZE" => ("SIZE", &mut raw.size),
            "TYPE" => ("TYPE", &mut raw.kind),
            "COUNT" => ("COUNT", &mut raw.count),
            "WIDTH" => ("WIDTH", &mut raw.width),
            "HEIGHT" => ("HEIGHT", &mut raw.height),
            "VIEWPOINT" => ("VIEWPOINT", &mut raw.viewpoint),
            "POINTS" => ("POINTS", &mut raw.points),
            "DATA" => ("DATA", &mut raw.data),
            other => {
                return Err(CloudFileProblem::PcdUnknownKeyword {
                    line,
                    keyword: other.chars().take(40).collect(),
                })
            }
        };
        if slot.is_some() {
            return Err(CloudFileProblem::PcdDuplicateKeyword {
                line,
                keyword: name,
            });
        }
        *slot = Some((line, tokens.map(str::to_owned).collect()));
    }
    validate(raw, offset, line + 1)
}

/// Checks the raw entries against each other and builds the header.
fn validate(
    raw: RawHeader,
    data_offset: usize,
    data_first_line: usize,
) -> Result<PcdHeader, CloudFileProblem> {
    if let Some((line, values)) = &raw.version {
        let version = single_value("VERSION", *line, values)?;
        if !matches!(version, "0.7" | ".7" | "0.6" | ".6" | "0.5" | ".5") {
            return Err(bad_value("VERSION", *line, version, "0.5, 0.6 or 0.7"));
        }
    }
    let fields = parse_fields(&raw)?;
    let (width_line, width_values) = required("WIDTH", &raw.width)?;
    let width = parse_count(
        "WIDTH",
        *width_line,
        single_value("WIDTH", *width_line, width_values)?,
    )?;
    let height = match &raw.height {
        Some((line, values)) => {
            parse_count("HEIGHT", *line, single_value("HEIGHT", *line, values)?)?
        }
        // Files older than v0.7 may omit HEIGHT; such clouds are unorganised (one row).
        None => 1,
    };
    if let Some((line, values)) = &raw.viewpoint {
        // The viewpoint is the acquisition pose; the points are not expressed relative to it, so it is only checked.
        if values.len() != 7 {
            return Err(value_count("VIEWPOINT", *line, values.len(), 7));
        }
        if let Some(bad) = values.iter().find(|v| v.parse::<f64>().is_err()) {
            return Err(bad_value("VIEWPOINT", *line, bad, "a number"));
        }
    }
    let points = match &raw.points {
        Some((line, values)) => {
            let points = parse_count("POINTS", *line, single_value("POINTS", *line, values)?)?;
            if width.checked_mul(height) != Some(points) {
                return Err(CloudFileProblem::PcdPointCount {
                    line: *line,
                    points,
                    width,
                    height,
                });
            }
            points
        }
        None => width.saturating_mul(height),
    };
    let (data_line, data_values) = required("DATA", &raw.data)?;
    let encoding = match single_value("DATA", *data_line, data_values)? {
        "ascii" => PcdEncoding::Ascii,
        "binary" => PcdEncoding::Binary,
        "binary_compressed" => {
            return Err(CloudFileProblem::PcdUnsupportedEncoding {
                line: *data_line,
                encoding: "binary_compressed".to_owned(),
            })
        }
        other => return Err(bad_value("DATA", *data_line, other, "ascii or binary")),
    };
    Ok(PcdHeader {
        fields,
        points,
        encoding,
        data_offset,
        data_first_line,
        count_line: raw.count.as_ref().map(|(line, _)| *line),
    })
}

/// Builds the field list from FIELDS, SIZE, TYPE and COUNT.
fn parse_fields(raw: &RawHeader) -> Result<Vec<PcdField>, CloudFileProblem> {
    let (fields_line, names) = required("FIELDS", &raw.fields)?;
    if names.is_empty() {
        return Err(value_count("FIELDS", *fields_line, 0, 1));
    }
    for (index, name) in names.iter().enumerate() {
        // `_` marks padding and may repeat; any other name must be unique.
        if name != "_" && names[..index].contains(name) {
            return Err(bad_value(
                "FIELDS",
                *fields_line,
                name,
                "a field name not listed before",
            ));
        }
    }
    let (size_line, sizes) = per_field("SIZE", &raw.size, names.len())?.ok_or(missing("SIZE"))?;
    let (type_line, kinds) = per_field("TYPE", &raw.kind, names.len())?.ok_or(missing("TYPE"))?;
    let counts = per_field("COUNT", &raw.count, names.len())?;

    let mut fields = Vec::with_capacity(names.len());
    for (index, name) in names.iter().enumerate() {
        let kind = match kinds[index].as_str() {
            "I" => FieldKind::Signed,
            "U" => FieldKind::Unsigned,
            "F" => FieldKind::Float,
            other => {
                return Err(CloudFileProblem::PcdUnknownFieldType {
                    line: type_line,
                    found: other.chars().take(20).collect(),
                })
            }
        };
        let size = parse_count("SIZE", size_line, &sizes[index])?;
        let size_ok = match kind {
            FieldKind::Float => matches!(size, 4 | 8),
            FieldKind::Signed | FieldKind::Unsigned => matches!(size, 1 | 2 | 4 | 8),
        };
        if !size_ok {
            return Err(CloudFileProblem::PcdUnsupportedFieldSize {
                line: size_line,
                field: name.clone(),
                kind: kind.letter(),
                size,
            });
        }
        let count = match counts {
            Some((line, values)) => {
                let count = parse_count("COUNT", line, &values[index])?;
                if count == 0 {
                    return Err(bad_value(
                        "COUNT",
                        line,
                        &values[index],
                        "a positive integer",
                    ));
                }
                count
            }
            None => 1,
        };
        fields.push(PcdField {
            name: name.clone(),
            kind,
            size,
            count,
        });
    }
    Ok(fields)
}

/// The line and values of a keyword that lists one value per field, if present.
fn per_field<'a>(
    keyword: &'static str,
    entry: &'a HeaderEntry,
    field_count: usize,
) -> Result<Option<(usize, &'a [String])>, CloudFileProblem> {
    match entry {
        Some((line, values)) if values.len() != field_count => {
            Err(value_count(keyword, *line, values.len(), field_count))
        }
        Some((line, values)) => Ok(Some((*line, values))),
        None => Ok(None),
    }
}

/// The entry of a required keyword.
fn required<'a>(
    keyword: &'static str,
    entry: &'a HeaderEntry,
) -> Result<&'a (usize, Vec<String>), CloudFileProblem> {
    entry.as_ref().ok_or(missing(keyword))
}

/// The one value of a single-valued keyword.
fn single_value<'a>(
    keyword: &'static str,
    line: usize,
    values: &'a [String],
) -> Result<&'a str, CloudFileProblem> {
    match values {
        [value] => Ok(value),
        _ => Err(value_count(keyword, line, values.len(), 1)),
    }
}

/// Parses a non-negative integer header value.
fn parse_count(keyword: &'static str, line: usize, value: &str) -> Result<usize, CloudFileProblem> {
    value
        .parse()
        .map_err(|_| bad_value(keyword, line, value, "a non-negative integer"))
}

fn missing(keyword: &'static str) -> CloudFileProblem {
    CloudFileProblem::PcdMissingKeyword { keyword }
}

fn bad_value(
    keyword: &'static str,
    line: usize,
    value: &str,
    expected: &'static str,
) -> CloudFileProblem {
    CloudFileProblem::PcdBadValue {
        line,
        keyword,
        // A garbage file can put megabytes on one "line"; the message needs only its start.
        value: value.chars().take(40).collect(),
        expected,
    }
}

fn value_count(
    keyword: &'static str,
    line: usize,
    found: usize,
    expected: usize,
) -> CloudFileProblem {
    CloudFileProblem::PcdValueCount {
        line,
        keyword,
        found,
        expected,
    }
}
