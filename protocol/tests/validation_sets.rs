//! Validation rules of measurement sets, track sets, status and truth: one test per rule, with messages.

mod common;

use common::documents::*;
use protocol::{
    decode, MeasurementSet, SensorDescriptor, SensorId, Status, TrackSet, TruthSet, WireFormat,
    MAX_MEASUREMENTS,
};

fn parse<T: serde::de::DeserializeOwned>(literal: &str) -> T {
    decode(literal.as_bytes(), WireFormat::Json).unwrap()
}

fn camera_set() -> MeasurementSet {
    parse(MEASUREMENT_SET)
}

fn error_of(result: Result<(), protocol::ProtocolError>) -> String {
    result.expect_err("must be rejected").to_string()
}

#[test]
fn version_other_than_1_is_rejected_for_every_set() {
    let expected = "version 0 is not supported, expected 1";
    let mut set = camera_set();
    set.version = 0;
    assert_eq!(error_of(set.validate()), expected);
    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.version = 0;
    assert_eq!(error_of(tracks.validate()), expected);
    let mut status: Status = parse(STATUS);
    status.version = 0;
    assert_eq!(error_of(status.validate()), expected);
    let mut truth: TruthSet = parse(TRUTH_SET);
    truth.version = 0;
    assert_eq!(error_of(truth.validate()), expected);
}

#[test]
fn non_finite_numbers_in_sets_are_rejected() {
    let mut set = camera_set();
    set.measurements[1][0] = f64::NAN;
    assert_eq!(
        error_of(set.validate()),
        "field measurements[1][0] = NaN is not finite"
    );
    let mut set = camera_set();
    set.stamp = f64::INFINITY;
    assert_eq!(error_of(set.validate()), "field stamp = inf is not finite");
    let mut set: MeasurementSet = parse(MEASUREMENT_SET_WITH_COVARIANCES);
    set.covariances.as_mut().unwrap()[1][0][1] = f64::NAN;
    assert_eq!(
        error_of(set.validate()),
        "field covariances[1][0][1] = NaN is not finite"
    );

    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.tracks[0].velocity = Some([0.0, f64::NAN, 0.0]);
    assert_eq!(
        error_of(tracks.validate()),
        "field tracks[0].velocity[1] = NaN is not finite"
    );
    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.expected_count = f64::NAN;
    assert_eq!(
        error_of(tracks.validate()),
        "field expected_count = NaN is not finite"
    );

    let mut truth: TruthSet = parse(TRUTH_SET);
    truth.objects[0].position[2] = f64::NEG_INFINITY;
    assert_eq!(
        error_of(truth.validate()),
        "field objects[0].position[2] = -inf is not finite"
    );

    let mut status: Status = parse(STATUS);
    status.sensors[0].last_stamp = Some(f64::NAN);
    assert_eq!(
        error_of(status.validate()),
        "field sensors[0].last_stamp = NaN is not finite"
    );
    let mut status: Status = parse(STATUS);
    status.latency_ms.p99 = Some(f64::INFINITY);
    assert_eq!(
        error_of(status.validate()),
        "field latency_ms.p99 = inf is not finite"
    );
}

#[test]
fn measurement_length_must_fit_the_sensor_kind() {
    let camera: SensorDescriptor = parse(CAMERA_DESCRIPTOR);
    let mut set = camera_set();
    set.measurements.push(vec![1.0, 2.0]);
    set.measurements.push(vec![1.0, 2.0, 3.0]);
    assert_eq!(
        error_of(set.validate_against(&camera)),
        "measurement 3 has 3 values, a camera measurement has 2"
    );
    let mics: SensorDescriptor = parse(MIC_PAIR_DESCRIPTOR);
    let mut set = camera_set();
    set.sensor = mics.sensor.clone();
    assert_eq!(
        error_of(set.validate_against(&mics)),
        "measurement 0 has 2 values, a mic_pair measurement has 1"
    );
    set.measurements = vec![vec![1e-4], vec![-2e-4]];
    assert!(set.validate_against(&mics).is_ok());
}

#[test]
fn set_from_another_sensor_is_rejected() {
    let camera: SensorDescriptor = parse(CAMERA_DESCRIPTOR);
    let mut set = camera_set();
    set.sensor = SensorId::new("cam2").unwrap();
    assert_eq!(
        error_of(set.validate_against(&camera)),
        r#"measurement set is from sensor "cam2" but the descriptor is for sensor "cam1""#
    );
}

#[test]
fn covariance_of_the_wrong_size_is_rejected() {
    let camera: SensorDescriptor = parse(CAMERA_DESCRIPTOR);
    let mut set: MeasurementSet = parse(MEASUREMENT_SET_WITH_COVARIANCES);
    set.covariances.as_mut().unwrap()[0] = vec![
        vec![1.0, 0.0, 0.0],
        vec![0.0, 1.0, 0.0],
        vec![0.0, 0.0, 1.0],
    ];
    assert_eq!(
        error_of(set.validate_against(&camera)),
        "field covariances[0] must be 2×2, found 3 rows"
    );
    set.covariances.as_mut().unwrap()[0] = vec![vec![1.0, 0.0], vec![0.0]];
    assert_eq!(
        error_of(set.validate()),
        "field covariances[0] must be 2×2, found row 1 with 1 values"
    );
    set.covariances.as_mut().unwrap().pop();
    assert_eq!(
        error_of(set.validate()),
        "covariances holds 1 matrices for 2 measurements"
    );
}

#[test]
fn asymmetric_covariance_is_rejected() {
    let mut set: MeasurementSet = parse(MEASUREMENT_SET_WITH_COVARIANCES);
    set.covariances.as_mut().unwrap()[0] = vec![vec![9.0, 1.5], vec![1.4, 4.0]];
    assert_eq!(
        error_of(set.validate()),
        "field covariances[0] is not symmetric: [0][1] = 1.5 but [1][0] = 1.4"
    );
    // Rounding-level asymmetry is tolerated.
    set.covariances.as_mut().unwrap()[0] = vec![vec![9.0, 1.5], vec![1.5 + 1e-14, 4.0]];
    assert!(set.validate().is_ok());
}

#[test]
fn covariance_that_is_not_positive_definite_is_rejected() {
    let mut set: MeasurementSet = parse(MEASUREMENT_SET_WITH_COVARIANCES);
    set.covariances.as_mut().unwrap()[1] = vec![vec![1.0, 2.0], vec![2.0, 1.0]];
    assert_eq!(
        error_of(set.validate()),
        "field covariances[1] is not positive definite (Cholesky pivot 1 = -3)"
    );
    set.covariances.as_mut().unwrap()[1] = vec![vec![0.0, 0.0], vec![0.0, 0.0]];
    assert_eq!(
        error_of(set.validate()),
        "field covariances[1] is not positive definite (Cholesky pivot 0 = 0)"
    );
    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.tracks[0].position_covariance[2][2] = -0.02;
    assert_eq!(
        error_of(tracks.validate()),
        "field tracks[0].position_covariance is not positive definite (Cholesky pivot 2 = -0.02)"
    );
}

#[test]
fn more_than_10000_measurements_are_rejected() {
    let mut set = camera_set();
    set.measurements = vec![vec![1.0, 2.0]; MAX_MEASUREMENTS];
    assert!(set.validate().is_ok(), "exactly 10 000 is allowed");
    set.measurements.push(vec![1.0, 2.0]);
    assert_eq!(
        error_of(set.validate()),
        "set holds 10001 measurements, at most 10000 are allowed"
    );
    let camera: SensorDescriptor = parse(CAMERA_DESCRIPTOR);
    assert_eq!(
        error_of(set.validate_against(&camera)),
        "set holds 10001 measurements, at most 10000 are allowed"
    );
}

#[test]
fn payload_over_one_mib_is_rejected() {
    let payload = vec![b'['; 1_048_577];
    let error = decode::<MeasurementSet>(&payload, WireFormat::Json).unwrap_err();
    assert_eq!(
        error.to_string(),
        "payload of 1048577 bytes exceeds 1048576"
    );
}

#[test]
fn set_stamped_too_far_ahead_of_the_server_clock_is_rejected() {
    let set = camera_set();
    let now = set.stamp - 2.0;
    assert_eq!(
        error_of(set.validate_stamp(now, 0.5)),
        "stamp 1763700000.04 is 2.000 s ahead of the server clock 1763699998.04 (at most 0.5 s allowed)"
    );
    assert!(set.validate_stamp(now, 2.5).is_ok());
    assert!(
        set.validate_stamp(set.stamp + 100.0, 0.0).is_ok(),
        "old sets are not this rule's business"
    );
}

#[test]
fn empty_set_is_valid() {
    let camera: SensorDescriptor = parse(CAMERA_DESCRIPTOR);
    let mut set = camera_set();
    set.measurements.clear();
    assert!(set.validate_against(&camera).is_ok());
    set.covariances = Some(Vec::new());
    assert!(set.validate_against(&camera).is_ok());
}

#[test]
fn negative_track_weight_or_count_is_rejected() {
    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.tracks[0].weight = -0.1;
    assert_eq!(
        error_of(tracks.validate()),
        "field tracks[0].weight = -0.1 is outside [0, inf)"
    );
    let mut tracks: TrackSet = parse(TRACK_SET);
    tracks.expected_count = -1.0;
    assert_eq!(
        error_of(tracks.validate()),
        "field expected_count = -1 is outside [0, inf)"
    );
}

#[test]
fn negative_uptime_or_latency_is_rejected() {
    let mut status: Status = parse(STATUS);
    status.uptime_s = -1.0;
    assert_eq!(
        error_of(status.validate()),
        "field uptime_s = -1 is outside [0, inf)"
    );
    let mut status: Status = parse(STATUS);
    status.latency_ms.p50 = Some(-0.4);
    assert_eq!(
        error_of(status.validate()),
        "field latency_ms.p50 = -0.4 is outside [0, inf)"
    );
}
