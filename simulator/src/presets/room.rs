//! The default scenario: three people in a small instrumented room, after Pham's
//! multi-camera experiments (thesis ch. 7: a 3 m × 2 m tracking area watched by two
//! calibrated cameras) and his speaker-tracking room (ch. 5.6: four microphone pairs with
//! 0.5 m spacing, 256 ms frames, p_D 0.7), plus a ceiling LIDAR.

use std::f64::consts::FRAC_PI_2;

use protocol::{CameraModel, LidarModel, MicPairModel, SensorModel, Site, DEFAULT_SPEED_OF_SOUND};

use crate::bounds::BoundsBox;
use crate::camera_pose::{look_at_projection, LookAt};
use crate::motion::{Motion, Waypoints};
use crate::presets::preset_sensor_id;
use crate::random_walk::RandomWalk;
use crate::scenario::Scenario;
use crate::sensor_spec::SensorSpec;
use crate::target::Target;

/// The room's floor, `[x_min, y_min]`–`[x_max, y_max]` in metres (3 m × 2 m).
pub const ROOM_FLOOR: [[f64; 2]; 2] = [[0.0, 0.0], [3.0, 2.0]];
/// The ceiling height in metres; cameras hang just below it.
pub const ROOM_HEIGHT: f64 = 2.5;

/// Where both cameras point: the middle of the floor, a little below head height.
const LOOK_AT: [f64; 3] = [1.5, 1.0, 1.2];
/// How close two people's heads come, m: about a shoulder breadth (people stand shoulder to shoulder
/// at most; walking side by side they keep some 0.7 m).
const PERSONAL_SPACE_M: f64 = 0.5;
/// An audio frame of 256 ms (4096 samples at 16 kHz), as in Pham ch. 5.6.
const AUDIO_FRAME_S: f64 = 0.256;

/// The default room (also `simulator/scenarios/room.toml`): a 3 m × 2 m floor, 2.5 m
/// high, 60 s long, truth at 25 Hz.
///
/// * People: #1 walks a loop of waypoints from 0.5 s, #2 is a random walk from 2 s,
///   #3 walks waypoints from 4.5 s and leaves at 52 s; heads at 1.6–1.8 m. Those are where they
///   mean to go: they step aside rather than come within 0.5 m of one another (`personal_space_m`).
/// * `cam1`, `cam2`: 640×480, f = 500 px, in opposite top corners looking at the room
///   centre; noise 3 px, p_D 0.95, clutter 2, 25 Hz, half a frame apart.
/// * `mics_s`, `mics_e`, `mics_n`, `mics_w`: one pair on each wall, 0.5 m baseline at
///   1.5 m height; noise 6.25e-5 s, p_D 0.7, clutter 1, one frame per 256 ms.
/// * `lidar`: on the ceiling's centre looking down; noise [0.05 m, 0.01 rad, 0.01 rad],
///   p_D 0.9, clutter 3, 10 Hz.
pub fn default_room() -> Scenario {
    Scenario {
        site: room_site(),
        start: None,
        duration_s: 60.0,
        truth_rate_hz: 25.0,
        targets: people(),
        sensors: [cameras(), microphone_pairs(), vec![ceiling_lidar()]].concat(),
        personal_space_m: Some(PERSONAL_SPACE_M),
        crowd: Default::default(),
    }
}

/// The site `room`.
fn room_site() -> Site {
    // A literal of `[a-z]` characters is a valid chunk; the presets' tests build it.
    Site::new("default").expect("`default` is a valid site chunk")
}

/// Three people whose heads stay inside the floor area.
fn people() -> Vec<Target> {
    let loop_walker = Waypoints {
        points: vec![
            (0.5, [0.3, 1.0, 1.75]),
            (4.0, [1.0, 0.5, 1.75]),
            (8.0, [2.0, 0.4, 1.75]),
            (12.0, [2.5, 1.0, 1.75]),
            (16.0, [2.0, 1.6, 1.75]),
            (20.0, [1.0, 1.5, 1.75]),
            (24.0, [0.6, 1.0, 1.75]),
            (28.0, [1.2, 0.6, 1.75]),
            (32.0, [2.2, 0.5, 1.75]),
            (36.0, [2.5, 1.2, 1.75]),
            (40.0, [1.8, 1.5, 1.75]),
            (44.0, [0.9, 1.4, 1.75]),
            (48.0, [0.7, 0.8, 1.75]),
            (54.0, [1.5, 1.0, 1.75]),
            (60.0, [2.3, 0.8, 1.75]),
        ],
    };
    let wanderer = RandomWalk {
        position: [2.2, 0.7, 1.65],
        std: [0.3, 0.3, 0.02],
        bounds: BoundsBox {
            min: [0.5, 0.4, 1.6],
            max: [2.5, 1.6, 1.7],
        },
        knot_interval_s: Some(1.0),
    };
    let visitor = Waypoints {
        points: vec![
            (4.5, [2.7, 1.0, 1.68]),
            (9.0, [2.0, 1.2, 1.68]),
            (14.0, [1.3, 0.7, 1.68]),
            (19.0, [0.8, 1.2, 1.68]),
            (25.0, [1.5, 1.5, 1.68]),
            (31.0, [2.3, 1.1, 1.68]),
            (37.0, [1.6, 0.5, 1.68]),
            (43.0, [0.8, 0.9, 1.68]),
            (48.0, [1.5, 1.3, 1.68]),
            (52.0, [2.7, 1.0, 1.68]),
        ],
    };
    vec![
        Target {
            id: 1,
            appear_s: 0.5,
            disappear_s: None,
            motion: Motion::Waypoints(loop_walker),
        },
        Target {
            id: 2,
            appear_s: 2.0,
            disappear_s: None,
            motion: Motion::RandomWalk(wanderer),
        },
        Target {
            id: 3,
            appear_s: 4.5,
            disappear_s: Some(52.0),
            motion: Motion::Waypoints(visitor),
        },
    ]
}

/// Two cameras in opposite top corners, both looking at the room centre.
fn cameras() -> Vec<SensorSpec> {
    let corners = [("cam1", [0.0, 0.0], 0.0), ("cam2", [3.0, 2.0], 0.02)];
    corners
        .into_iter()
        .map(|(name, [x, y], phase_s)| {
            let pose = LookAt {
                eye: [x, y, ROOM_HEIGHT],
                target: LOOK_AT,
                focal_px: 500.0,
                image_size: [640, 480],
            };
            SensorSpec {
                sensor: preset_sensor_id(name),
                detection_probability: 0.95,
                clutter_rate: 2.0,
                rate_hz: 25.0,
                phase_s,
                model: SensorModel::Camera(CameraModel {
                    projection: look_at_projection(&pose),
                    image_size: pose.image_size,
                    noise_std: [3.0, 3.0],
                }),
            }
        })
        .collect()
}

/// One microphone pair in the middle of each wall, 0.5 m apart, 1.5 m above the floor.
fn microphone_pairs() -> Vec<SensorSpec> {
    let walls = [
        ("mics_s", [[1.25, 0.0, 1.5], [1.75, 0.0, 1.5]], 0.005),
        ("mics_e", [[3.0, 0.75, 1.5], [3.0, 1.25, 1.5]], 0.069),
        ("mics_n", [[1.75, 2.0, 1.5], [1.25, 2.0, 1.5]], 0.133),
        ("mics_w", [[0.0, 1.25, 1.5], [0.0, 0.75, 1.5]], 0.197),
    ];
    walls
        .into_iter()
        .map(|(name, mics, phase_s)| SensorSpec {
            sensor: preset_sensor_id(name),
            detection_probability: 0.7,
            clutter_rate: 1.0,
            rate_hz: 1.0 / AUDIO_FRAME_S,
            phase_s,
            model: SensorModel::MicPair(MicPairModel {
                mics,
                speed_of_sound: DEFAULT_SPEED_OF_SOUND,
                noise_std: 6.25e-5,
            }),
        })
        .collect()
}

/// A LIDAR in the middle of the ceiling, upside down (turned 180° about x, so its +z
/// axis points at the floor and heads are at positive elevations).
fn ceiling_lidar() -> SensorSpec {
    SensorSpec {
        sensor: preset_sensor_id("lidar"),
        detection_probability: 0.9,
        clutter_rate: 3.0,
        rate_hz: 10.0,
        phase_s: 0.01,
        model: SensorModel::Lidar(LidarModel {
            position: [1.5, 1.0, ROOM_HEIGHT],
            orientation: [0.0, 1.0, 0.0, 0.0],
            noise_std: [0.05, 0.01, 0.01],
            max_range: 4.0,
            elevation_limits: [0.2, FRAC_PI_2],
        }),
    }
}
