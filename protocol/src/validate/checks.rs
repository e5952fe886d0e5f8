//! Small checks shared by the validation rules: version, finiteness, intervals.

use crate::error::ProtocolError;
use crate::PROTOCOL_VERSION;

/// Rejects any version but [`PROTOCOL_VERSION`].
pub(crate) fn check_version(found: u32) -> Result<(), ProtocolError> {
    if found != PROTOCOL_VERSION {
        return Err(ProtocolError::UnsupportedVersion {
            found,
            expected: PROTOCOL_VERSION,
        });
    }
    Ok(())
}

/// Rejects a NaN or infinite `value`; `field` names it (built only on failure).
pub(crate) fn check_finite(
    value: f64,
    field: impl FnOnce() -> String,
) -> Result<(), ProtocolError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ProtocolError::NonFinite {
            field: field(),
            value,
        })
    }
}

/// Rejects the first non-finite entry of `values`; `field(i)` names entry `i`.
pub(crate) fn check_all_finite(
    values: &[f64],
    field: impl Fn(usize) -> String,
) -> Result<(), ProtocolError> {
    for (i, &value) in values.iter().enumerate() {
        check_finite(value, || field(i))?;
    }
    Ok(())
}

/// Rejects a value that is not finite or does not satisfy `inside`; `allowed` describes the interval.
fn check_interval(
    value: f64,
    field: &str,
    allowed: &'static str,
    inside: impl Fn(f64) -> bool,
) -> Result<(), ProtocolError> {
    check_finite(value, || field.to_owned())?;
    if inside(value) {
        Ok(())
    } else {
        Err(ProtocolError::OutOfRange {
            field: field.to_owned(),
            value,
            allowed,
        })
    }
}

/// Requires a finite value > 0.
pub(crate) fn check_positive(value: f64, field: &str) -> Result<(), ProtocolError> {
    check_interval(value, field, "(0, inf)", |v| v > 0.0)
}

/// Requires a finite value ≥ 0.
pub(crate) fn check_non_negative(value: f64, field: &str) -> Result<(), ProtocolError> {
    check_interval(value, field, "[0, inf)", |v| v >= 0.0)
}

/// Requires a finite value in (0, 1].
pub(crate) fn check_probability(value: f64, field: &str) -> Result<(), ProtocolError> {
    check_interval(value, field, "(0, 1]", |v| v > 0.0 && v <= 1.0)
}

/// Requires every entry of `values` finite and > 0; the entries are named `field[i]`.
pub(crate) fn check_all_positive(values: &[f64], field: &str) -> Result<(), ProtocolError> {
    for (i, &value) in values.iter().enumerate() {
        check_positive(value, &format!("{field}[{i}]"))?;
    }
    Ok(())
}
