//! Wire formats: encoding strings, query parameters, size limit, and decode errors.

mod common;

use common::documents::{MEASUREMENT_SET, TRUTH_SET};
use protocol::codec::check_payload_size;
use protocol::{
    decode, encode, MeasurementSet, ProtocolError, SensorId, TruthSet, WireFormat,
    MAX_PAYLOAD_BYTES,
};

#[test]
fn encoding_strings_name_the_formats() {
    assert_eq!(WireFormat::Json.encoding_str(), "application/json");
    assert_eq!(WireFormat::Postcard.encoding_str(), "application/postcard");
    for format in [WireFormat::Json, WireFormat::Postcard] {
        assert_eq!(
            WireFormat::from_encoding_str(format.encoding_str()).unwrap(),
            format
        );
    }
    assert_eq!(WireFormat::default(), WireFormat::Postcard);
}

#[test]
fn encoding_parameters_and_case_are_ignored() {
    let json = [
        "application/json;charset=utf-8",
        "application/json; charset=utf-8",
        "Application/JSON",
    ];
    for encoding in json {
        assert_eq!(
            WireFormat::from_encoding_str(encoding).unwrap(),
            WireFormat::Json,
            "{encoding}"
        );
    }
    assert_eq!(
        WireFormat::from_encoding_str("application/postcard;protocol-v1").unwrap(),
        WireFormat::Postcard
    );
}

#[test]
fn unknown_encodings_are_rejected() {
    for encoding in [
        "text/plain",
        "",
        "text/json",
        "application/jsonx",
        "application/cbor",
    ] {
        let error = WireFormat::from_encoding_str(encoding).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!("unsupported encoding {encoding:?}")
        );
    }
}

#[test]
fn query_parameters_choose_the_reply_format() {
    assert_eq!(
        WireFormat::from_query_parameters("").unwrap(),
        WireFormat::Postcard
    );
    assert_eq!(
        WireFormat::from_query_parameters("format=json").unwrap(),
        WireFormat::Json
    );
    assert_eq!(
        WireFormat::from_query_parameters("format=postcard").unwrap(),
        WireFormat::Postcard
    );
    assert_eq!(
        WireFormat::from_query_parameters("a=1;format=json;b").unwrap(),
        WireFormat::Json
    );
    assert_eq!(
        WireFormat::from_query_parameters("a=1&format=json").unwrap(),
        WireFormat::Json
    );
    assert_eq!(
        WireFormat::from_query_parameters("formats=json").unwrap(),
        WireFormat::Postcard
    );
}

#[test]
fn bad_query_parameters_are_rejected() {
    assert_eq!(
        WireFormat::from_query_parameters("format=xml")
            .unwrap_err()
            .to_string(),
        r#"query parameter format="xml" is not one of json, postcard"#
    );
    assert_eq!(
        WireFormat::from_query_parameters("format")
            .unwrap_err()
            .to_string(),
        r#"query parameter format="" is not one of json, postcard"#
    );
    let twice = WireFormat::from_query_parameters("format=json;format=postcard").unwrap_err();
    assert!(
        matches!(twice, ProtocolError::BadFormatParameter(_)),
        "{twice}"
    );
    assert!(twice.to_string().contains("given twice"), "{twice}");
}

#[test]
fn payloads_over_one_mib_are_refused_before_decoding() {
    assert_eq!(MAX_PAYLOAD_BYTES, 1_048_576);
    assert!(check_payload_size(MAX_PAYLOAD_BYTES).is_ok());
    let big = vec![b' '; 2_000_000];
    for format in [WireFormat::Json, WireFormat::Postcard] {
        let error = decode::<TruthSet>(&big, format).unwrap_err();
        assert_eq!(
            error.to_string(),
            "payload of 2000000 bytes exceeds 1048576"
        );
    }
}

#[test]
fn encoding_a_message_over_one_mib_fails() {
    let sensor = SensorId::new("cam1").unwrap();
    let measurements = vec![vec![1.234_567_890_123_4, 2.345_678_901_234_5]; 40_000];
    let set = MeasurementSet::new(sensor, 0, 1.0, measurements);
    let error = encode(&set, WireFormat::Json).unwrap_err();
    assert!(
        matches!(error, ProtocolError::PayloadTooLarge { max: 1_048_576, .. }),
        "{error}"
    );
}

#[test]
fn decode_errors_say_which_format_failed() {
    let error = decode::<TruthSet>(b"{\"version\": 1", WireFormat::Json).unwrap_err();
    assert!(
        error.to_string().starts_with("json decode failed: "),
        "{error}"
    );
    let error = decode::<TruthSet>(&[1, 2], WireFormat::Postcard).unwrap_err();
    assert!(
        error.to_string().starts_with("postcard decode failed: "),
        "{error}"
    );
    // A receiver decides by the encoding, never by sniffing: JSON bytes declared as postcard fail.
    let error =
        decode::<MeasurementSet>(MEASUREMENT_SET.as_bytes(), WireFormat::Postcard).unwrap_err();
    assert!(
        error.to_string().starts_with("postcard decode failed: "),
        "{error}"
    );
}

#[test]
fn trailing_bytes_are_rejected() {
    let truth: TruthSet = decode(TRUTH_SET.as_bytes(), WireFormat::Json).unwrap();
    let mut bytes = encode(&truth, WireFormat::Postcard).unwrap();
    bytes.extend_from_slice(&[0, 0]);
    let error = decode::<TruthSet>(&bytes, WireFormat::Postcard).unwrap_err();
    assert_eq!(
        error.to_string(),
        "postcard decode failed: 2 bytes left after the value"
    );
    let error =
        decode::<TruthSet>(format!("{TRUTH_SET} {{}}").as_bytes(), WireFormat::Json).unwrap_err();
    assert!(error.to_string().contains("trailing characters"), "{error}");
}
