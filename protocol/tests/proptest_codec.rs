//! Property tests: decoding anything never panics; valid messages survive both round trips unchanged.

mod common;

use common::strategies::*;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use protocol::{
    decode, encode, MeasurementSet, ReplayLine, SensorDescriptor, SensorModel, Status, TrackSet,
    TruthSet, WireFormat,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;
use std::fmt::Debug;

/// Fixed seeds keep every run the same; failures are not written to disk.
fn config(cases: u32, seed: u64) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Decodes `bytes` as every message type in `format`; whatever decodes is validated. Must never panic.
fn decode_as_everything(bytes: &[u8], format: WireFormat) {
    fn one<T: DeserializeOwned>(bytes: &[u8], format: WireFormat) -> Option<T> {
        decode::<T>(bytes, format).ok()
    }
    if let Some(d) = one::<SensorDescriptor>(bytes, format) {
        let _ = d.validate();
    }
    if let Some(s) = one::<MeasurementSet>(bytes, format) {
        let _ = s.validate();
        let _ = s.validate_stamp(0.0, 1.0);
    }
    if let Some(t) = one::<TrackSet>(bytes, format) {
        let _ = t.validate();
    }
    if let Some(s) = one::<Status>(bytes, format) {
        let _ = s.validate();
    }
    if let Some(t) = one::<TruthSet>(bytes, format) {
        let _ = t.validate();
    }
    if let Some(line) = one::<ReplayLine>(bytes, format) {
        let _ = line.validate();
    }
    let _ = one::<SensorModel>(bytes, format);
}

/// Checks that `value` comes back equal from JSON and from postcard.
fn round_trips<T: Serialize + DeserializeOwned + PartialEq + Debug>(
    value: &T,
) -> Result<(), TestCaseError> {
    for format in [WireFormat::Json, WireFormat::Postcard] {
        let bytes = encode(value, format).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let back: T =
            decode(&bytes, format).map_err(|e| TestCaseError::fail(format!("{format:?}: {e}")))?;
        prop_assert_eq!(&back, value, "{:?}", format);
    }
    Ok(())
}

/// Arbitrary JSON documents whose objects often use the contract's field names.
fn json_value() -> impl Strategy<Value = Value> {
    let key = prop_oneof![
        prop::sample::select(vec![
            "version",
            "site",
            "sensor",
            "model",
            "kind",
            "camera",
            "mic_pair",
            "lidar",
            "position",
            "measurements",
            "covariances",
            "descriptor",
            "truth",
            "tracks",
            "stamp",
            "seq",
            "objects",
            "id",
            "region",
            "min",
            "max",
        ])
        .prop_map(str::to_owned),
        "[a-z_]{0,8}",
    ];
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(Value::from),
        any::<u64>().prop_map(Value::from),
        finite().prop_map(Value::from),
        ".{0,12}".prop_map(Value::String),
    ];
    leaf.prop_recursive(5, 64, 8, move |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..8).prop_map(Value::Array),
            prop::collection::btree_map(key.clone(), inner, 0..8)
                .prop_map(|m| Value::Object(m.into_iter().collect())),
        ]
    })
}

proptest! {
    #![proptest_config(config(2000, 0x5EED_0001))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        decode_as_everything(&bytes, WireFormat::Postcard);
        decode_as_everything(&bytes, WireFormat::Json);
    }

    #[test]
    fn arbitrary_strings_never_panic(text in "\\PC{0,256}") {
        decode_as_everything(text.as_bytes(), WireFormat::Json);
    }
}

proptest! {
    #![proptest_config(config(1000, 0x5EED_0002))]

    #[test]
    fn arbitrary_json_documents_never_panic(value in json_value()) {
        let text = serde_json::to_string(&value).unwrap();
        decode_as_everything(text.as_bytes(), WireFormat::Json);
    }

    #[test]
    fn corrupted_valid_postcard_never_panics(
        (_, set) in descriptor_and_set(),
        flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
    ) {
        let mut bytes = encode(&ReplayLine::Measurements(set), WireFormat::Postcard).unwrap();
        for (index, value) in flips {
            let i = index.index(bytes.len());
            bytes[i] = value;
        }
        decode_as_everything(&bytes, WireFormat::Postcard);
        decode_as_everything(&bytes[..bytes.len() / 2], WireFormat::Postcard);
    }
}

proptest! {
    #![proptest_config(config(300, 0x5EED_0003))]

    #[test]
    fn valid_descriptors_and_sets_round_trip((descriptor, set) in descriptor_and_set()) {
        descriptor.validate().map_err(|e| TestCaseError::fail(e.to_string()))?;
        set.validate_against(&descriptor).map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trips(&descriptor)?;
        round_trips(&set)?;
    }

    #[test]
    fn valid_track_sets_round_trip(tracks in track_set()) {
        tracks.validate().map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trips(&tracks)?;
    }

    #[test]
    fn valid_status_round_trips(status in status()) {
        status.validate().map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trips(&status)?;
    }

    #[test]
    fn valid_truth_sets_round_trip(truth in truth_set()) {
        truth.validate().map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trips(&truth)?;
    }

    #[test]
    fn valid_replay_lines_round_trip(line in replay_line()) {
        line.validate().map_err(|e| TestCaseError::fail(e.to_string()))?;
        round_trips(&line)?;
    }
}
