//! The two wire forms (JSON and postcard), how a payload says which one it is, and encode/decode.
//!
//! A receiver decides by the payload's encoding, never by sniffing the bytes. Payloads over
//! [`MAX_PAYLOAD_BYTES`] are refused both ways: before decoding, and after encoding (a receiver would drop them).

use crate::error::ProtocolError;
use crate::MAX_PAYLOAD_BYTES;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Encoding string of the JSON form.
pub const JSON_ENCODING: &str = "application/json";

/// Encoding string of the postcard form (a custom encoding string for Zenoh).
pub const POSTCARD_ENCODING: &str = "application/postcard";

/// Name of the query parameter choosing the reply's form.
pub const FORMAT_PARAMETER: &str = "format";

/// The form a payload is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum WireFormat {
    /// UTF-8 JSON in the forms of shared/PROTOCOL.md.
    Json,
    /// The same types serialised with postcard; the default between this project's programs.
    #[default]
    Postcard,
}

impl WireFormat {
    /// The encoding string a payload of this form carries.
    pub fn encoding_str(self) -> &'static str {
        match self {
            WireFormat::Json => JSON_ENCODING,
            WireFormat::Postcard => POSTCARD_ENCODING,
        }
    }

    /// The form named by an encoding string. Parameters after `;` (e.g. `application/json;charset=utf-8`)
    /// are ignored, as are surrounding blanks and ASCII case; any other media type is an error.
    pub fn from_encoding_str(encoding: &str) -> Result<Self, ProtocolError> {
        let media_type = encoding.split(';').next().unwrap_or("").trim();
        if media_type.eq_ignore_ascii_case(JSON_ENCODING) {
            Ok(WireFormat::Json)
        } else if media_type.eq_ignore_ascii_case(POSTCARD_ENCODING) {
            Ok(WireFormat::Postcard)
        } else {
            Err(ProtocolError::UnsupportedEncoding(encoding.to_owned()))
        }
    }

    /// The reply form a query asks for with `format=json` or `format=postcard` (postcard when absent).
    ///
    /// `parameters` is the query's parameter string, pairs separated by `;` (Zenoh's separator) or `&`.
    /// Other parameters are ignored; another value, or `format` given twice, is an error.
    pub fn from_query_parameters(parameters: &str) -> Result<Self, ProtocolError> {
        let mut chosen: Option<WireFormat> = None;
        for pair in parameters.split([';', '&']) {
            let (name, value) = pair.split_once('=').unwrap_or((pair, ""));
            if name.trim() != FORMAT_PARAMETER {
                continue;
            }
            let format = match value.trim() {
                "json" => WireFormat::Json,
                "postcard" => WireFormat::Postcard,
                other => return Err(ProtocolError::BadFormatParameter(other.to_owned())),
            };
            if chosen.is_some() {
                return Err(ProtocolError::BadFormatParameter(format!(
                    "{} (given twice)",
                    value.trim()
                )));
            }
            chosen = Some(format);
        }
        Ok(chosen.unwrap_or_default())
    }
}

/// Refuses a payload larger than [`MAX_PAYLOAD_BYTES`].
pub fn check_payload_size(size: usize) -> Result<(), ProtocolError> {
    if size > MAX_PAYLOAD_BYTES {
        return Err(ProtocolError::PayloadTooLarge {
            size,
            max: MAX_PAYLOAD_BYTES,
        });
    }
    Ok(())
}

/// Writes `value` in `format`; fails if the result would exceed [`MAX_PAYLOAD_BYTES`].
///
/// This does not validate: call the message's `validate()` first (JSON, for one, writes a NaN as `null`).
pub fn encode<T: Serialize>(value: &T, format: WireFormat) -> Result<Vec<u8>, ProtocolError> {
    let bytes = match format {
        WireFormat::Json => serde_json::to_vec(value).map_err(ProtocolError::JsonEncode)?,
        WireFormat::Postcard => {
            postcard::to_stdvec(value).map_err(ProtocolError::PostcardEncode)?
        }
    };
    check_payload_size(bytes.len())?;
    Ok(bytes)
}

/// Reads a `T` written in `format`, refusing payloads over [`MAX_PAYLOAD_BYTES`] before looking at them.
///
/// A decoded value is well-formed but not yet validated: call its `validate()` next.
/// Postcard bytes left over after the value are an error, as is trailing non-blank text after JSON.
pub fn decode<T: DeserializeOwned>(bytes: &[u8], format: WireFormat) -> Result<T, ProtocolError> {
    check_payload_size(bytes.len())?;
    match format {
        WireFormat::Json => serde_json::from_slice(bytes).map_err(ProtocolError::JsonDecode),
        WireFormat::Postcard => {
            let (value, rest) =
                postcard::take_from_bytes(bytes).map_err(ProtocolError::PostcardDecode)?;
            if rest.is_empty() {
                Ok(value)
            } else {
                Err(ProtocolError::PostcardTrailingBytes { extra: rest.len() })
            }
        }
    }
}
