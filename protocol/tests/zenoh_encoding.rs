//! `WireFormat` ↔ Zenoh `Encoding` (only with the `zenoh` feature).
#![cfg(feature = "zenoh")]

use protocol::WireFormat;
use zenoh::bytes::Encoding;

#[test]
fn formats_map_to_zenoh_encodings_and_back() {
    assert_eq!(WireFormat::Json.to_zenoh(), Encoding::APPLICATION_JSON);
    assert_eq!(
        WireFormat::Postcard.to_zenoh().to_string(),
        "application/postcard"
    );
    for format in [WireFormat::Json, WireFormat::Postcard] {
        assert_eq!(WireFormat::from_zenoh(&format.to_zenoh()).unwrap(), format);
    }
}

#[test]
fn zenoh_encodings_with_a_schema_are_accepted() {
    let json = Encoding::APPLICATION_JSON.with_schema("charset=utf-8");
    assert_eq!(WireFormat::from_zenoh(&json).unwrap(), WireFormat::Json);
}

#[test]
fn other_zenoh_encodings_are_rejected() {
    for encoding in [
        Encoding::TEXT_PLAIN,
        Encoding::TEXT_JSON,
        Encoding::ZENOH_BYTES,
        Encoding::default(),
    ] {
        let error = WireFormat::from_zenoh(&encoding).unwrap_err();
        assert!(
            error.to_string().starts_with("unsupported encoding"),
            "{error}"
        );
    }
}
