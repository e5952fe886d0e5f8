//! A dense benchmark scenario: many targets, many fast sensors, heavy clutter.

use protocol::{CameraModel, LidarModel, PositionModel, Region, SensorId, SensorModel, Site};

use crate::bounds::BoundsBox;
use crate::camera_pose::{look_at_projection, LookAt};
use crate::motion::{ConstantVelocity, Motion};
use crate::presets::preset_sensor_id;
use crate::random_walk::RandomWalk;
use crate::scenario::Scenario;
use crate::sensor_spec::SensorSpec;
use crate::target::Target;

/// The monitored volume: 40 m × 40 m, 10 m high.
const VOLUME: BoundsBox = BoundsBox {
    min: [0.0, 0.0, 0.0],
    max: [40.0, 40.0, 10.0],
};
/// Where the walkers are kept (1 m inside the volume, 1–9 m high).
const WALK_BOUNDS: BoundsBox = BoundsBox {
    min: [1.0, 1.0, 1.0],
    max: [39.0, 39.0, 9.0],
};
/// Number of targets.
const TARGETS: u64 = 50;
/// Frames per second of every sensor.
const SENSOR_RATE_HZ: f64 = 30.0;
/// Clutter points per set of every sensor.
const CLUTTER_RATE: f64 = 20.0;
/// Offset between consecutive sensors' frames, so the 8 sensors interleave.
const PHASE_STEP_S: f64 = 0.004;

/// The dense benchmark (also `simulator/scenarios/dense.toml`): 50 targets in a
/// 40 × 40 × 10 m volume over 60 s (truth at 30 Hz), seen by 8 sensors at 30 Hz each
/// (4 cameras, 2 LIDARs, 2 position sensors) with 20 clutter points per set.
///
/// Targets start on a 5 × 5 grid at four heights; every fifth crosses the volume at a
/// constant velocity, the others random-walk inside it. They appear over the first 4.5 s;
/// every seventh leaves at 40 s or later.
pub fn dense() -> Scenario {
    let sensors = [cameras(), lidars(), position_sensors()]
        .concat()
        .into_iter()
        .enumerate()
        .map(|(i, mut spec)| {
            spec.phase_s = i as f64 * PHASE_STEP_S;
            spec
        })
        .collect();
    Scenario {
        site: Site::new("dense").expect("`dense` is a valid site chunk"),
        start: None,
        duration_s: 60.0,
        truth_rate_hz: 30.0,
        targets: (0..TARGETS).map(target).collect(),
        sensors,
        personal_space_m: None,
        crowd: Default::default(),
    }
}

/// The dense scenario scaled to `targets` targets and `sensors` sensors, for measuring how the
/// cost grows: the targets follow the same pattern (each hundred beyond the first shifted 1.3 or
/// 2.6 m to one side or the other, so that none starts on another), and the sensors repeat the 8 of [`dense`] in turn
/// (copies named `<name>_<copy>`, their frames interleaved).
pub fn dense_scaled(targets: u64, sensors: usize) -> Scenario {
    let mut scenario = dense();
    let base = std::mem::take(&mut scenario.sensors);
    scenario.targets = (0..targets).map(scaled_target).collect();
    scenario.sensors = (0..sensors)
        .map(|i| {
            let mut spec = base[i % base.len()].clone();
            let copy = i / base.len();
            if copy > 0 {
                let name = format!("{}_{copy}", spec.sensor.as_str());
                spec.sensor = SensorId::new(&name).expect("a preset name with a number is valid");
            }
            spec.phase_s = i as f64 * PHASE_STEP_S;
            spec
        })
        .collect();
    scenario
}

fn scaled_target(i: u64) -> Target {
    let mut target = target(i);
    // Each further hundred sits 1.3 or 2.6 m off the first, alternately on either side, so that
    // the copies do not coincide and stay inside the walking bounds.
    const SHIFTS: [f64; 5] = [0.0, 1.3, -1.3, 2.6, -2.6];
    let shift = SHIFTS[(i / 100) as usize % SHIFTS.len()];
    match &mut target.motion {
        Motion::ConstantVelocity(cv) => {
            cv.position[0] += shift;
            cv.position[1] += shift;
        }
        Motion::RandomWalk(walk) => {
            walk.position[0] += shift;
            walk.position[1] += shift;
        }
        _ => {}
    }
    target
}

/// Target number `i` (id `i + 1`).
fn target(i: u64) -> Target {
    let cell = i % 25;
    let position = [
        4.0 + 8.0 * (cell % 5) as f64,
        4.0 + 8.0 * (cell / 5) as f64,
        2.0 + 2.0 * (i % 4) as f64,
    ];
    let crosses = i.is_multiple_of(5);
    let motion = if crosses {
        // These start on the west edge (x = 4) and cross eastwards at 0.5 m/s, drifting
        // towards the middle row so that they stay inside the volume for the whole run.
        Motion::ConstantVelocity(ConstantVelocity {
            position,
            velocity: [0.5, (20.0 - position[1]) / 80.0, 0.0],
        })
    } else {
        Motion::RandomWalk(RandomWalk {
            position,
            std: [0.5, 0.5, 0.1],
            bounds: WALK_BOUNDS,
            knot_interval_s: Some(0.5),
        })
    };
    Target {
        id: i + 1,
        appear_s: 0.5 * (i % 10) as f64,
        disappear_s: (i % 7 == 6).then_some(40.0 + i as f64 * 0.25),
        motion,
    }
}

/// Four cameras high above the corners, looking at the middle of the volume.
fn cameras() -> Vec<SensorSpec> {
    let corners = [
        ("cam1", [-5.0, -5.0]),
        ("cam2", [45.0, -5.0]),
        ("cam3", [45.0, 45.0]),
        ("cam4", [-5.0, 45.0]),
    ];
    corners
        .into_iter()
        .map(|(name, [x, y])| {
            let pose = LookAt {
                eye: [x, y, 15.0],
                target: [20.0, 20.0, 3.0],
                focal_px: 500.0,
                image_size: [640, 480],
            };
            SensorSpec {
                sensor: preset_sensor_id(name),
                detection_probability: 0.9,
                clutter_rate: CLUTTER_RATE,
                rate_hz: SENSOR_RATE_HZ,
                phase_s: 0.0,
                model: SensorModel::Camera(CameraModel {
                    projection: look_at_projection(&pose),
                    image_size: pose.image_size,
                    noise_std: [2.0, 2.0],
                }),
            }
        })
        .collect()
}

/// Two LIDARs at the middle of opposite sides, facing each other.
fn lidars() -> Vec<SensorSpec> {
    let mounts = [
        // Facing +x (identity), and facing −x (turned 180° about z).
        ("lidar1", [0.0, 20.0, 5.0], [1.0, 0.0, 0.0, 0.0]),
        ("lidar2", [40.0, 20.0, 5.0], [0.0, 0.0, 0.0, 1.0]),
    ];
    mounts
        .into_iter()
        .map(|(name, position, orientation)| SensorSpec {
            sensor: preset_sensor_id(name),
            detection_probability: 0.9,
            clutter_rate: CLUTTER_RATE,
            rate_hz: SENSOR_RATE_HZ,
            phase_s: 0.0,
            model: SensorModel::Lidar(LidarModel {
                position,
                orientation,
                noise_std: [0.05, 0.005, 0.005],
                max_range: 60.0,
                elevation_limits: [-0.6, 0.6],
            }),
        })
        .collect()
}

/// Two sensors reporting world positions over the whole volume (e.g. radio beacons).
fn position_sensors() -> Vec<SensorSpec> {
    let noises = [("pos1", [0.5, 0.5, 0.5]), ("pos2", [1.0, 1.0, 0.3])];
    noises
        .into_iter()
        .map(|(name, noise_std)| SensorSpec {
            sensor: preset_sensor_id(name),
            detection_probability: 0.85,
            clutter_rate: CLUTTER_RATE,
            rate_hz: SENSOR_RATE_HZ,
            phase_s: 0.0,
            model: SensorModel::Position(PositionModel {
                noise_std,
                region: Region {
                    min: VOLUME.min,
                    max: VOLUME.max,
                },
            }),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scaled_scenario_of_the_cost_table_is_valid() {
        for targets in [10, 50, 200, 500] {
            for sensors in [4, 8, 16, 32] {
                let scenario = dense_scaled(targets, sensors);
                assert_eq!(scenario.targets.len() as u64, targets);
                assert_eq!(scenario.sensors.len(), sensors);
                scenario
                    .validate()
                    .unwrap_or_else(|e| panic!("{targets} targets, {sensors} sensors: {e}"));
            }
        }
    }

    #[test]
    fn scaling_to_fifty_targets_and_eight_sensors_is_the_dense_scenario() {
        let (scaled, dense) = (dense_scaled(50, 8), dense());
        assert_eq!(
            format!("{:?}", scaled.targets),
            format!("{:?}", dense.targets)
        );
    }
}
