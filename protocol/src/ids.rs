//! Validated identifiers: a `<site>`, `<sensor>` or server `<instance>` is one key chunk of `[A-Za-z0-9_-]`, 1 to 64 characters.
//!
//! Both types check their text when built and when deserialised, so a message that decoded always carries
//! identifiers that can be put into a key expression.

use crate::error::{ChunkRole, ProtocolError};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Longest allowed site or sensor identifier, in characters.
pub const MAX_CHUNK_LEN: usize = 64;

/// The site used when none is configured.
pub const DEFAULT_SITE: &str = "default";

/// Checks that `value` is a single key chunk of `[A-Za-z0-9_-]` with 1 to [`MAX_CHUNK_LEN`] characters.
fn check_chunk(value: &str, role: ChunkRole) -> Result<(), ProtocolError> {
    if value.is_empty() {
        return Err(ProtocolError::EmptyChunk { role });
    }
    // A bad character is the more useful message (e.g. a '/' in a would-be chunk), so look for it first.
    if let Some(bad) = value
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(ProtocolError::ChunkBadCharacter {
            role,
            value: value.to_owned(),
            bad,
        });
    }
    // Only ASCII is left, so bytes are characters.
    if value.len() > MAX_CHUNK_LEN {
        return Err(ProtocolError::ChunkTooLong {
            role,
            value: value.to_owned(),
            len: value.len(),
            max: MAX_CHUNK_LEN,
        });
    }
    Ok(())
}

/// Declares a validated chunk newtype; the two identifiers differ only in name and role.
macro_rules! chunk_newtype {
    ($(#[$doc:meta])* $name:ident, $role:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
        #[serde(try_from = "String", into = "String")]
        pub struct $name(String);

        impl $name {
            /// Builds the identifier, rejecting anything that is not one chunk of `[A-Za-z0-9_-]`, 1..=64 long.
            pub fn new(value: impl Into<String>) -> Result<Self, ProtocolError> {
                let value = value.into();
                check_chunk(&value, $role)?;
                Ok(Self(value))
            }

            /// The identifier as text.
            pub fn as_str(&self) -> &str {
                &self.0
            }
        }

        impl TryFrom<String> for $name {
            type Error = ProtocolError;
            fn try_from(value: String) -> Result<Self, Self::Error> {
                Self::new(value)
            }
        }

        impl TryFrom<&str> for $name {
            type Error = ProtocolError;
            fn try_from(value: &str) -> Result<Self, Self::Error> {
                Self::new(value)
            }
        }

        impl std::str::FromStr for $name {
            type Err = ProtocolError;
            fn from_str(value: &str) -> Result<Self, Self::Err> {
                Self::new(value)
            }
        }

        impl From<$name> for String {
            fn from(id: $name) -> String {
                id.0
            }
        }

        impl AsRef<str> for $name {
            fn as_ref(&self) -> &str {
                &self.0
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(&self.0)
            }
        }
    };
}

chunk_newtype!(
    /// A deployment's name: the `<site>` chunk of `fusion/<site>/...`. Defaults to `default`.
    Site,
    ChunkRole::Site
);

chunk_newtype!(
    /// A sensor's name, unique within its site: the `<sensor>` chunk of `fusion/<site>/sensors/<sensor>/...`.
    SensorId,
    ChunkRole::Sensor
);

chunk_newtype!(
    /// One fusion server of a site, when an active server and hot standbys run side by side: the
    /// `<instance>` chunk of `fusion/<site>/server/<instance>/...`.
    InstanceId,
    ChunkRole::Instance
);

impl Default for Site {
    fn default() -> Self {
        Site(DEFAULT_SITE.to_owned())
    }
}
