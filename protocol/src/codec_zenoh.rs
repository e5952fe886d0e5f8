//! Conversions between [`WireFormat`] and Zenoh's `Encoding` (feature `zenoh`).

use crate::codec::{WireFormat, POSTCARD_ENCODING};
use crate::error::ProtocolError;
use zenoh::bytes::Encoding;

impl WireFormat {
    /// The form named by a received sample's or reply's encoding; anything but JSON or postcard is an error.
    pub fn from_zenoh(encoding: &Encoding) -> Result<Self, ProtocolError> {
        Self::from_encoding_str(&encoding.to_string())
    }

    /// The encoding to attach to a `put` or reply in this form.
    pub fn to_zenoh(self) -> Encoding {
        match self {
            WireFormat::Json => Encoding::APPLICATION_JSON,
            WireFormat::Postcard => Encoding::from(POSTCARD_ENCODING),
        }
    }
}
