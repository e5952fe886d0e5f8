//! JSON forms: every literal document decodes, re-encodes to the same document, and validates.

mod common;

use common::documents::*;
use common::{assert_json_round_trip, json_difference};
use protocol::{
    decode, encode, MeasurementSet, ReplayLine, SensorDescriptor, SensorKind, SensorModel, Status,
    TrackSet, TruthSet, WireFormat, DEFAULT_SPEED_OF_SOUND,
};
use serde_json::{json, Value};

#[test]
fn protocol_md_camera_descriptor_round_trips() {
    let descriptor: SensorDescriptor = assert_json_round_trip(CAMERA_DESCRIPTOR);
    descriptor.validate().expect("the page's example is valid");
    let SensorModel::Camera(camera) = &descriptor.model else {
        panic!("expected a camera, got {:?}", descriptor.model)
    };
    assert_eq!(camera.projection[0], [800.0, 0.0, 320.0, -400.0]);
    assert_eq!(camera.image_size, [640, 480]);
    assert_eq!(descriptor.model.kind_name(), "camera");
    assert_eq!(descriptor.model.measurement_dim(), 2);
}

#[test]
fn protocol_md_measurement_set_round_trips_with_null_covariances() {
    let set: MeasurementSet = assert_json_round_trip(MEASUREMENT_SET);
    assert_eq!(set.covariances, None);
    assert_eq!(set.seq, 42);
    let written: Value = serde_json::from_slice(&encode(&set, WireFormat::Json).unwrap()).unwrap();
    assert_eq!(
        written["covariances"],
        Value::Null,
        "null is written, not omitted"
    );
    let descriptor: SensorDescriptor =
        decode(CAMERA_DESCRIPTOR.as_bytes(), WireFormat::Json).unwrap();
    set.validate_against(&descriptor)
        .expect("the page's set fits the page's camera");
}

#[test]
fn protocol_md_track_set_round_trips() {
    let tracks: TrackSet = assert_json_round_trip(TRACK_SET);
    tracks.validate().expect("the page's example is valid");
    assert_eq!(tracks.tracks[0].velocity, Some([0.1, 0.0, 0.0]));
    assert_eq!(tracks.tracks[0].position_covariance[2][2], 0.02);
}

#[test]
fn protocol_md_status_decodes_and_the_added_counters_default_to_zero() {
    // The page's example predates the per-sensor `rollbacks` and `reprocessed` counters (fields
    // added within version 1): it still decodes, and re-encoding writes them out.
    let status: Status =
        decode(STATUS.as_bytes(), WireFormat::Json).expect("the page's example decodes");
    assert_eq!(
        (status.sensors[0].rollbacks, status.sensors[0].reprocessed),
        (0, 0)
    );
    let written: serde_json::Value =
        serde_json::from_slice(&encode(&status, WireFormat::Json).unwrap()).unwrap();
    assert_eq!(written["sensors"][0]["rollbacks"], 0);
    status.validate().expect("the page's example is valid");
    assert_eq!(status.sensors[0].kind, SensorKind::Camera);
    assert_eq!(status.rejected.invalid, 1);
    assert_eq!(status.latency_ms.p99, Some(1.9));
}

#[test]
fn protocol_md_truth_set_round_trips() {
    let truth: TruthSet = assert_json_round_trip(TRUTH_SET);
    truth.validate().expect("the page's example is valid");
    assert_eq!(truth.objects[0].position, [1.0, 0.5, 1.7]);
}

#[test]
fn every_sensor_kind_round_trips_and_validates() {
    let cases = [
        (CAMERA_DESCRIPTOR, SensorKind::Camera, 2),
        (MIC_PAIR_DESCRIPTOR, SensorKind::MicPair, 1),
        (LIDAR_DESCRIPTOR, SensorKind::Lidar, 3),
        (BEARING_RANGE_DESCRIPTOR, SensorKind::BearingRange, 2),
        (POSITION_DESCRIPTOR, SensorKind::Position, 3),
    ];
    for (literal, kind, dim) in cases {
        let descriptor: SensorDescriptor = assert_json_round_trip(literal);
        descriptor
            .validate()
            .unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!(descriptor.model.kind(), kind);
        assert_eq!(descriptor.model.measurement_dim(), dim);
        let model: Value = serde_json::from_str(literal).unwrap();
        assert_eq!(model["model"]["kind"], descriptor.model.kind_name());
    }
}

#[test]
fn mic_pair_speed_of_sound_defaults_to_343() {
    let literal = r#"{"version": 1, "site": "default", "sensor": "m",
        "model": {"kind": "mic_pair", "mics": [[0,0,0],[0.3,0,0]], "noise_std": 1e-5},
        "detection_probability": 0.9, "clutter_rate": 1.0}"#;
    let descriptor: SensorDescriptor = decode(literal.as_bytes(), WireFormat::Json).unwrap();
    let SensorModel::MicPair(mics) = &descriptor.model else {
        panic!("expected a mic pair")
    };
    assert_eq!(mics.speed_of_sound, DEFAULT_SPEED_OF_SOUND);
    assert_eq!(DEFAULT_SPEED_OF_SOUND, 343.0);
    let written: Value = serde_json::to_value(&descriptor).unwrap();
    assert_eq!(
        written["model"]["speed_of_sound"],
        json!(343.0),
        "the default is written out"
    );
}

#[test]
fn covariances_and_null_velocity_round_trip() {
    let set: MeasurementSet = assert_json_round_trip(MEASUREMENT_SET_WITH_COVARIANCES);
    set.validate().expect("valid covariances");
    assert_eq!(set.covariances.as_ref().unwrap()[0][0], vec![9.0, 1.5]);
    let tracks: TrackSet = assert_json_round_trip(TRACK_SET_WITHOUT_VELOCITY);
    tracks.validate().expect("valid tracks");
    assert_eq!(tracks.tracks[0].velocity, None);
    let status: Status = assert_json_round_trip(STATUS_AT_START);
    status.validate().expect("valid status");
    assert_eq!(status.sensors[0].last_stamp, None);
}

#[test]
fn replay_lines_of_each_type_round_trip() {
    let cases = [
        ("descriptor", POSITION_DESCRIPTOR),
        ("measurements", MEASUREMENT_SET),
        ("truth", TRUTH_SET),
    ];
    for (key, inner) in cases {
        let line = format!("{{\"{key}\": {inner}}}");
        let decoded: ReplayLine = assert_json_round_trip(&line);
        decoded.validate().unwrap_or_else(|e| panic!("{key}: {e}"));
        let matches = matches!(
            (key, &decoded),
            ("descriptor", ReplayLine::Descriptor(_))
                | ("measurements", ReplayLine::Measurements(_))
                | ("truth", ReplayLine::Truth(_))
        );
        assert!(matches, "{key} decoded as {decoded:?}");
    }
    // An output line is a bare TrackSet.
    let output: TrackSet = assert_json_round_trip(TRACK_SET);
    assert_eq!(output.seq, 7);
}

#[test]
fn replay_line_stamp_comes_from_the_set() {
    let line = format!("{{\"truth\": {TRUTH_SET}}}");
    let decoded: ReplayLine = decode(line.as_bytes(), WireFormat::Json).unwrap();
    assert_eq!(decoded.stamp(), Some(1763700000.040));
    let line = format!("{{\"descriptor\": {CAMERA_DESCRIPTOR}}}");
    let decoded: ReplayLine = decode(line.as_bytes(), WireFormat::Json).unwrap();
    assert_eq!(decoded.stamp(), None);
}

/// Decodes `literal` as `T` and returns the error message.
fn json_error<T: serde::de::DeserializeOwned + std::fmt::Debug>(literal: &str) -> String {
    decode::<T>(literal.as_bytes(), WireFormat::Json)
        .expect_err("must not decode")
        .to_string()
}

#[test]
fn replay_line_with_two_messages_or_unknown_key_is_rejected() {
    let two = format!("{{\"truth\": {TRUTH_SET}, \"measurements\": {MEASUREMENT_SET}}}");
    let message = json_error::<ReplayLine>(&two);
    assert!(message.starts_with("json decode failed: "), "{message}");
    let unknown = format!("{{\"tracks\": {TRACK_SET}}}");
    let message = json_error::<ReplayLine>(&unknown);
    assert!(message.contains("unknown variant `tracks`"), "{message}");
}

#[test]
fn unknown_field_and_unknown_kind_are_rejected_with_their_names() {
    let misspelt = MEASUREMENT_SET.replace("\"covariances\"", "\"covariance\"");
    let message = json_error::<MeasurementSet>(&misspelt);
    assert!(message.contains("unknown field `covariance`"), "{message}");

    let extra_model_field =
        CAMERA_DESCRIPTOR.replace("\"image_size\"", "\"fov\": 1.0, \"image_size\"");
    let message = json_error::<SensorDescriptor>(&extra_model_field);
    assert!(message.contains("unknown field `fov`"), "{message}");

    let sonar = CAMERA_DESCRIPTOR.replace("\"camera\"", "\"sonar\"");
    let message = json_error::<SensorDescriptor>(&sonar);
    assert!(message.contains("unknown variant `sonar`"), "{message}");

    let no_kind = CAMERA_DESCRIPTOR.replace("\"kind\": \"camera\", ", "");
    let message = json_error::<SensorDescriptor>(&no_kind);
    assert!(message.contains("missing field `kind`"), "{message}");
}

#[test]
fn wrong_shapes_are_json_decode_errors() {
    let short_projection = CAMERA_DESCRIPTOR.replace("[0,0,1,-2]", "[0,0,1]");
    let message = json_error::<SensorDescriptor>(&short_projection);
    assert!(message.starts_with("json decode failed: "), "{message}");
    let fractional_size = CAMERA_DESCRIPTOR.replace("[640, 480]", "[640.5, 480]");
    let message = json_error::<SensorDescriptor>(&fractional_size);
    assert!(message.starts_with("json decode failed: "), "{message}");
}

#[test]
fn json_comparison_helper_sees_differences() {
    let a = json!({"x": [1, 2.0], "y": null});
    assert_eq!(
        json_difference(&a, &json!({"x": [1.0, 2], "y": null}), "$"),
        None
    );
    assert!(json_difference(&a, &json!({"x": [1, 2.5], "y": null}), "$").is_some());
    assert!(json_difference(&a, &json!({"x": [1, 2]}), "$").is_some());
    assert!(json_difference(&a, &json!({"x": [1, 2], "y": 0}), "$").is_some());
}

#[test]
fn omitted_optional_fields_read_as_null() {
    let without = MEASUREMENT_SET.replace(",\n \"covariances\": null", "");
    assert!(!without.contains("covariances"), "{without}");
    let set: MeasurementSet = decode(without.as_bytes(), WireFormat::Json).unwrap();
    assert_eq!(set.covariances, None);
}
