//! Literal JSON documents: the examples of shared/PROTOCOL.md verbatim, and one descriptor per sensor kind.

/// PROTOCOL.md, SensorDescriptor (a camera), verbatim.
pub const CAMERA_DESCRIPTOR: &str = r#"{"version": 1, "site": "default", "sensor": "cam1",
 "model": {"kind": "camera", "projection": [[800,0,320,-400],[0,800,240,-300],[0,0,1,-2]],
           "image_size": [640, 480], "noise_std": [3.0, 3.0]},
 "detection_probability": 0.95, "clutter_rate": 2.0}"#;

/// PROTOCOL.md, MeasurementSet, verbatim.
pub const MEASUREMENT_SET: &str = r#"{"version": 1, "sensor": "cam1", "seq": 42, "stamp": 1763700000.040,
 "measurements": [[320.5, 240.1], [101.0, 57.5]],
 "covariances": null}"#;

/// PROTOCOL.md, TrackSet, verbatim.
pub const TRACK_SET: &str = r#"{"version": 1, "site": "default", "seq": 7, "stamp": 1763700000.040,
 "expected_count": 2.03,
 "tracks": [{"id": 3, "position": [1.2, 0.8, 1.7], "velocity": [0.1, 0.0, 0.0],
             "position_covariance": [[0.01,0,0],[0,0.01,0],[0,0,0.02]],
             "weight": 0.98, "first_seen": 1763699990.120}]}"#;

/// PROTOCOL.md, Status, verbatim.
pub const STATUS: &str = r#"{"version": 1, "site": "default", "uptime_s": 12.5, "stamp": 1763700000.040,
 "components": 57, "tracks": 2,
 "sensors": [{"sensor": "cam1", "kind": "camera", "alive": true, "last_stamp": 1763700000.040,
              "received": 300, "processed": 298, "late": 1, "invalid": 1, "lost": 0}],
 "rejected": {"undecodable": 0, "unknown_sensor": 0, "invalid": 1, "late": 1},
 "latency_ms": {"p50": 0.4, "p99": 1.9}}"#;

/// PROTOCOL.md, TruthSet, verbatim.
pub const TRUTH_SET: &str = r#"{"version": 1, "stamp": 1763700000.040, "objects": [{"id": 1, "position": [1.0, 0.5, 1.7]}]}"#;

/// A mic pair 0.2 m apart with an explicit speed of sound.
pub const MIC_PAIR_DESCRIPTOR: &str = r#"{"version": 1, "site": "lab-2", "sensor": "mics_left",
 "model": {"kind": "mic_pair", "mics": [[0.0, 0.0, 1.0], [0.2, 0.0, 1.0]], "speed_of_sound": 340.0,
           "noise_std": 2.0e-5},
 "detection_probability": 0.8, "clutter_rate": 0.5}"#;

/// A lidar 2 m up, rotated 90° about z.
pub const LIDAR_DESCRIPTOR: &str = r#"{"version": 1, "site": "default", "sensor": "lidar_1",
 "model": {"kind": "lidar", "position": [0.0, 0.0, 2.0],
           "orientation": [0.7071067811865476, 0.0, 0.0, 0.7071067811865476],
           "noise_std": [0.05, 0.01, 0.01], "max_range": 50.0, "elevation_limits": [-0.3, 0.3]},
 "detection_probability": 0.9, "clutter_rate": 5.0}"#;

/// A planar radar.
pub const BEARING_RANGE_DESCRIPTOR: &str = r#"{"version": 1, "site": "default", "sensor": "radar-A",
 "model": {"kind": "bearing_range", "position": [10.0, -5.0, 0.5], "noise_std": [0.02, 0.3],
           "max_range": 80.0},
 "detection_probability": 0.7, "clutter_rate": 0.0}"#;

/// A position sensor covering a 10 m × 8 m × 3 m room.
pub const POSITION_DESCRIPTOR: &str = r#"{"version": 1, "site": "default", "sensor": "uwb",
 "model": {"kind": "position", "noise_std": [0.1, 0.1, 0.2],
           "region": {"min": [0.0, 0.0, 0.0], "max": [10.0, 8.0, 3.0]}},
 "detection_probability": 1.0, "clutter_rate": 0.1}"#;

/// A camera set carrying its own covariances.
pub const MEASUREMENT_SET_WITH_COVARIANCES: &str = r#"{"version": 1, "sensor": "cam1", "seq": 43,
 "stamp": 1763700000.080, "measurements": [[320.5, 240.1], [101.0, 57.5]],
 "covariances": [[[9.0, 1.5], [1.5, 4.0]], [[2.25, 0.0], [0.0, 2.25]]]}"#;

/// A track set whose motion model has no velocity.
pub const TRACK_SET_WITHOUT_VELOCITY: &str = r#"{"version": 1, "site": "default", "seq": 8,
 "stamp": 1763700000.080, "expected_count": 0.97,
 "tracks": [{"id": 11, "position": [4.0, 2.0, 0.0], "velocity": null,
             "position_covariance": [[0.04, 0.01, 0.0], [0.01, 0.04, 0.0], [0.0, 0.0, 0.09]],
             "weight": 0.97, "first_seen": 1763700000.0}]}"#;

/// A status before any set or publication: `last_stamp` and the latencies are `null`; `role`
/// is one of the fields version 1 has gained since the contract's own example.
pub const STATUS_AT_START: &str = r#"{"version": 1, "site": "default", "uptime_s": 0.1,
 "stamp": 0.0, "components": 0, "tracks": 0,
 "sensors": [{"sensor": "uwb", "kind": "position", "alive": false, "last_stamp": null,
              "received": 0, "processed": 0, "late": 0, "invalid": 0, "lost": 0,
              "rollbacks": 0, "reprocessed": 0}],
 "rejected": {"undecodable": 0, "unknown_sensor": 0, "invalid": 0, "late": 0},
 "latency_ms": {"p50": null, "p99": null}, "role": "active"}"#;
