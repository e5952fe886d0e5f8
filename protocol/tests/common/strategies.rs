//! Proptest strategies for valid messages of every type (each one passes its `validate()`).

use proptest::collection::vec;
use proptest::prelude::*;
use protocol::{
    BearingRangeModel, CameraModel, LatencyMs, LidarModel, MeasurementSet, MicPairModel,
    PositionModel, Region, Rejected, ReplayLine, SensorDescriptor, SensorId, SensorKind,
    SensorModel, SensorStatus, ServerRole, Site, Status, Track, TrackSet, TruthObject, TruthSet,
    PROTOCOL_VERSION,
};

/// Any finite f64, tiny, huge or zero: what a round trip must carry unchanged.
pub fn finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

/// A plausible epoch stamp with sub-microsecond digits.
pub fn stamp() -> impl Strategy<Value = f64> {
    1.0e9..2.0e9_f64
}

/// A point in a 1 km cube.
pub fn point() -> impl Strategy<Value = [f64; 3]> {
    [-1e3..1e3_f64, -1e3..1e3_f64, -1e3..1e3_f64]
}

/// A valid site identifier.
pub fn site() -> impl Strategy<Value = Site> {
    "[A-Za-z0-9_-]{1,64}".prop_map(|s| Site::new(s).expect("the regex only yields valid chunks"))
}

/// A valid sensor identifier.
pub fn sensor_id() -> impl Strategy<Value = SensorId> {
    "[A-Za-z0-9_-]{1,64}"
        .prop_map(|s| SensorId::new(s).expect("the regex only yields valid chunks"))
}

fn camera() -> impl Strategy<Value = SensorModel> {
    (
        1.0..5e3_f64,
        -0.5..0.5_f64,
        point(),
        0.1..10.0_f64,
        1u32..8192,
        1u32..8192,
    )
        .prop_map(|(f, skew, [tx, ty, tz], noise, w, h)| {
            let (cx, cy) = (f64::from(w) / 2.0, f64::from(h) / 2.0);
            SensorModel::Camera(CameraModel {
                projection: [[f, skew, cx, tx], [0.0, f, cy, ty], [0.0, 0.0, 1.0, tz]],
                image_size: [w, h],
                noise_std: [noise, noise * 1.5],
            })
        })
}

fn mic_pair() -> impl Strategy<Value = SensorModel> {
    (
        point(),
        [0.01..2.0_f64, -2.0..2.0_f64, -2.0..2.0_f64],
        300.0..360.0_f64,
        1e-7..1e-3_f64,
    )
        .prop_map(|(m1, d, speed_of_sound, noise_std)| {
            SensorModel::MicPair(MicPairModel {
                mics: [m1, [m1[0] + d[0], m1[1] + d[1], m1[2] + d[2]]],
                speed_of_sound,
                noise_std,
            })
        })
}

fn unit_quaternion() -> impl Strategy<Value = [f64; 4]> {
    [-1.0..1.0_f64, -1.0..1.0_f64, -1.0..1.0_f64, -1.0..1.0_f64]
        .prop_filter("a direction needs a non-zero vector", |q| {
            q.iter().map(|v| v * v).sum::<f64>() > 1e-3
        })
        .prop_map(|q| {
            let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            q.map(|v| v / norm)
        })
}

fn lidar() -> impl Strategy<Value = SensorModel> {
    (
        point(),
        unit_quaternion(),
        [1e-3..1.0_f64, 1e-4..0.1_f64, 1e-4..0.1_f64],
        0.5..300.0_f64,
        -1.5..-0.01_f64,
        0.01..1.5_f64,
    )
        .prop_map(|(position, orientation, noise_std, max_range, min, max)| {
            SensorModel::Lidar(LidarModel {
                position,
                orientation,
                noise_std,
                max_range,
                elevation_limits: [min, max],
            })
        })
}

fn bearing_range() -> impl Strategy<Value = SensorModel> {
    (point(), [1e-4..0.5_f64, 1e-3..5.0_f64], 0.5..500.0_f64).prop_map(
        |(position, noise_std, max_range)| {
            SensorModel::BearingRange(BearingRangeModel {
                position,
                noise_std,
                max_range,
            })
        },
    )
}

fn position() -> impl Strategy<Value = SensorModel> {
    (
        [1e-3..2.0_f64, 1e-3..2.0_f64, 1e-3..2.0_f64],
        point(),
        [0.1..100.0_f64, 0.1..100.0_f64, 0.1..100.0_f64],
    )
        .prop_map(|(noise_std, min, size)| {
            SensorModel::Position(PositionModel {
                noise_std,
                region: Region {
                    min,
                    max: [min[0] + size[0], min[1] + size[1], min[2] + size[2]],
                },
            })
        })
}

/// A valid model of any kind.
pub fn sensor_model() -> impl Strategy<Value = SensorModel> {
    prop_oneof![camera(), mic_pair(), lidar(), bearing_range(), position()]
}

/// A valid descriptor of any kind.
pub fn descriptor() -> impl Strategy<Value = SensorDescriptor> {
    (
        site(),
        sensor_id(),
        sensor_model(),
        1e-3..=1.0_f64,
        0.0..50.0_f64,
    )
        .prop_map(|(site, sensor, model, pd, clutter)| {
            SensorDescriptor::new(site, sensor, model, pd, clutter)
        })
}

/// A symmetric positive definite `dim`×`dim` matrix, A·Aᵀ + 0.1·I (exactly symmetric in floating point).
pub fn spd(dim: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    vec(vec(-10.0..10.0_f64, dim), dim).prop_map(move |a| {
        (0..dim)
            .map(|i| {
                (0..dim)
                    .map(|j| {
                        let dot: f64 = (0..dim).map(|k| a[i][k] * a[j][k]).sum();
                        dot + if i == j { 0.1 } else { 0.0 }
                    })
                    .collect()
            })
            .collect()
    })
}

/// A descriptor and a valid set from its sensor, with or without covariances.
pub fn descriptor_and_set() -> impl Strategy<Value = (SensorDescriptor, MeasurementSet)> {
    descriptor().prop_flat_map(|descriptor| {
        let dim = descriptor.model.measurement_dim();
        let sensor = descriptor.sensor.clone();
        (0usize..12).prop_flat_map(move |n| {
            let measurements = vec(vec(finite(), dim), n);
            let covariances = prop::option::of(vec(spd(dim), n));
            let (descriptor, sensor) = (descriptor.clone(), sensor.clone());
            (any::<u64>(), stamp(), measurements, covariances).prop_map(
                move |(seq, stamp, measurements, covariances)| {
                    let set = MeasurementSet {
                        covariances,
                        ..MeasurementSet::new(sensor.clone(), seq, stamp, measurements)
                    };
                    (descriptor.clone(), set)
                },
            )
        })
    })
}

fn track() -> impl Strategy<Value = Track> {
    (
        any::<u64>(),
        point(),
        prop::option::of(point()),
        spd(3),
        0.0..1.0_f64,
        stamp(),
    )
        .prop_map(
            |(id, position, velocity, covariance, weight, first_seen)| Track {
                id,
                position,
                velocity,
                position_covariance: [0, 1, 2]
                    .map(|i| [covariance[i][0], covariance[i][1], covariance[i][2]]),
                weight,
                first_seen,
            },
        )
}

/// A valid track set.
pub fn track_set() -> impl Strategy<Value = TrackSet> {
    (
        site(),
        any::<u64>(),
        stamp(),
        0.0..100.0_f64,
        vec(track(), 0..8),
    )
        .prop_map(|(site, seq, stamp, expected_count, tracks)| TrackSet {
            version: PROTOCOL_VERSION,
            site,
            seq,
            stamp,
            expected_count,
            tracks,
        })
}

fn sensor_status() -> impl Strategy<Value = SensorStatus> {
    (
        sensor_id(),
        prop::sample::select(SensorKind::ALL.to_vec()),
        any::<bool>(),
        prop::option::of(stamp()),
        [any::<u64>(); 7],
    )
        .prop_map(
            |(
                sensor,
                kind,
                alive,
                last_stamp,
                [received, processed, late, invalid, lost, rollbacks, reprocessed],
            )| {
                SensorStatus {
                    sensor,
                    kind,
                    alive,
                    last_stamp,
                    received,
                    processed,
                    late,
                    invalid,
                    lost,
                    rollbacks,
                    reprocessed,
                }
            },
        )
}

/// A valid status report.
pub fn status() -> impl Strategy<Value = Status> {
    (
        site(),
        0.0..1e7_f64,
        stamp(),
        [any::<u64>(); 2],
        vec(sensor_status(), 0..5),
        [any::<u64>(); 4],
        prop::option::of(0.0..1e3_f64),
        prop::option::of(0.0..1e3_f64),
        prop_oneof![Just(ServerRole::Active), Just(ServerRole::Standby)],
    )
        .prop_map(
            |(site, uptime_s, stamp, [components, tracks], sensors, rejected, p50, p99, role)| {
                Status {
                    version: PROTOCOL_VERSION,
                    site,
                    uptime_s,
                    stamp,
                    components,
                    tracks,
                    sensors,
                    rejected: Rejected {
                        undecodable: rejected[0],
                        unknown_sensor: rejected[1],
                        invalid: rejected[2],
                        late: rejected[3],
                    },
                    latency_ms: LatencyMs { p50, p99 },
                    role,
                }
            },
        )
}

/// A valid truth set.
pub fn truth_set() -> impl Strategy<Value = TruthSet> {
    (
        stamp(),
        vec((any::<u64>(), [finite(), finite(), finite()]), 0..8),
    )
        .prop_map(|(stamp, objects)| TruthSet {
            version: PROTOCOL_VERSION,
            stamp,
            objects: objects
                .into_iter()
                .map(|(id, position)| TruthObject { id, position })
                .collect(),
        })
}

/// A valid replay input line of any type.
pub fn replay_line() -> impl Strategy<Value = ReplayLine> {
    prop_oneof![
        descriptor().prop_map(ReplayLine::Descriptor),
        descriptor_and_set().prop_map(|(_, set)| ReplayLine::Measurements(set)),
        truth_set().prop_map(ReplayLine::Truth),
    ]
}
