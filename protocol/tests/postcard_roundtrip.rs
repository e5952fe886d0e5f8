//! Postcard: every literal document survives JSON → postcard → value unchanged, and models use the compact form.

mod common;

use common::assert_postcard_round_trip;
use common::documents::*;
use protocol::{
    decode, encode, MeasurementSet, ReplayLine, SensorDescriptor, SensorModel, Status, TrackSet,
    TruthSet, WireFormat,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::fmt::Debug;

fn from_json<T: DeserializeOwned>(literal: &str) -> T {
    decode(literal.as_bytes(), WireFormat::Json).unwrap()
}

fn check<T: Serialize + DeserializeOwned + PartialEq + Debug>(literal: &str) {
    assert_postcard_round_trip(&from_json::<T>(literal));
}

#[test]
fn descriptors_of_every_kind_round_trip() {
    for literal in [
        CAMERA_DESCRIPTOR,
        MIC_PAIR_DESCRIPTOR,
        LIDAR_DESCRIPTOR,
        BEARING_RANGE_DESCRIPTOR,
        POSITION_DESCRIPTOR,
    ] {
        check::<SensorDescriptor>(literal);
    }
}

#[test]
fn sets_round_trip() {
    check::<MeasurementSet>(MEASUREMENT_SET);
    check::<MeasurementSet>(MEASUREMENT_SET_WITH_COVARIANCES);
    check::<TrackSet>(TRACK_SET);
    check::<TrackSet>(TRACK_SET_WITHOUT_VELOCITY);
    check::<Status>(STATUS);
    check::<Status>(STATUS_AT_START);
    check::<TruthSet>(TRUTH_SET);
}

#[test]
fn replay_lines_round_trip() {
    for (key, inner) in [
        ("descriptor", LIDAR_DESCRIPTOR),
        ("measurements", MEASUREMENT_SET),
        ("truth", TRUTH_SET),
    ] {
        check::<ReplayLine>(&format!("{{\"{key}\": {inner}}}"));
    }
}

#[test]
fn models_are_externally_tagged_by_variant_index() {
    // Postcard writes an enum as its variant index (a varint) followed by the fields, never a `kind` string.
    let kinds = [
        (CAMERA_DESCRIPTOR, 0u8),
        (MIC_PAIR_DESCRIPTOR, 1),
        (LIDAR_DESCRIPTOR, 2),
        (BEARING_RANGE_DESCRIPTOR, 3),
        (POSITION_DESCRIPTOR, 4),
    ];
    for (literal, index) in kinds {
        let descriptor: SensorDescriptor = from_json(literal);
        let bytes = encode(&descriptor.model, WireFormat::Postcard).unwrap();
        assert_eq!(bytes[0], index, "{}", descriptor.model.kind_name());
        let back: SensorModel = decode(&bytes, WireFormat::Postcard).unwrap();
        assert_eq!(back, descriptor.model);
    }
}

#[test]
fn postcard_is_smaller_than_json() {
    let set: MeasurementSet = from_json(MEASUREMENT_SET_WITH_COVARIANCES);
    let json = encode(&set, WireFormat::Json).unwrap();
    let postcard = encode(&set, WireFormat::Postcard).unwrap();
    println!(
        "measurement set with covariances: json {} bytes, postcard {} bytes",
        json.len(),
        postcard.len()
    );
    assert!(postcard.len() < json.len());
}
