//! Replay lines: descriptors first, then every set of the run in stamp order, all valid.

use std::collections::HashMap;

use protocol::{ReplayLine, SensorDescriptor};
use simulator::{default_room, replay_lines, Simulation};

const SEED: u64 = 99;
const START: f64 = 1_763_700_000.0;
const DURATION_S: f64 = 3.0;

fn room_lines() -> Vec<ReplayLine> {
    let mut scenario = default_room();
    scenario.start = Some(START);
    replay_lines(&scenario, SEED, DURATION_S).unwrap().collect()
}

#[test]
fn descriptors_come_first_then_everything_in_stamp_order() {
    let scenario = default_room();
    let lines = room_lines();
    let sensors = scenario.sensors.len();
    let descriptors: Vec<&SensorDescriptor> = lines[..sensors]
        .iter()
        .map(|line| match line {
            ReplayLine::Descriptor(d) => d,
            other => panic!("expected a descriptor, got {other:?}"),
        })
        .collect();
    let names: Vec<&str> = descriptors.iter().map(|d| d.sensor.as_str()).collect();
    let expected: Vec<&str> = scenario.sensors.iter().map(|s| s.sensor.as_str()).collect();
    assert_eq!(names, expected);

    let stamps: Vec<f64> = lines[sensors..]
        .iter()
        .map(|l| l.stamp().unwrap())
        .collect();
    assert!(
        stamps.windows(2).all(|w| w[0] <= w[1]),
        "stamps out of order"
    );
    assert!(stamps
        .iter()
        .all(|&s| (START..START + DURATION_S).contains(&s)));
}

#[test]
fn every_instant_appears_once_and_every_line_is_valid() {
    let scenario = default_room();
    let lines = room_lines();
    let by_name: HashMap<String, SensorDescriptor> = lines
        .iter()
        .filter_map(|line| match line {
            ReplayLine::Descriptor(d) => Some((d.sensor.to_string(), d.clone())),
            _ => None,
        })
        .collect();
    let mut seqs: HashMap<String, Vec<u64>> = HashMap::new();
    let mut truth = 0;
    for line in &lines {
        line.validate().unwrap();
        match line {
            ReplayLine::Measurements(set) => {
                set.validate_against(&by_name[set.sensor.as_str()]).unwrap();
                seqs.entry(set.sensor.to_string())
                    .or_default()
                    .push(set.seq);
            }
            ReplayLine::Truth(_) => truth += 1,
            ReplayLine::Descriptor(_) => {}
        }
    }
    assert_eq!(truth, 75, "3 s of truth at 25 Hz");
    for spec in &scenario.sensors {
        let expected: Vec<u64> = (0..spec.frame_count(DURATION_S)).collect();
        assert_eq!(seqs[spec.sensor.as_str()], expected, "{}", spec.sensor);
    }
    // 3 s: 75 frames per camera, 30 LIDAR scans; 256 ms audio frames starting at 5 ms
    // give 12 sets, starting at 197 ms only 11.
    assert_eq!(seqs["cam1"].len(), 75);
    assert_eq!(seqs["lidar"].len(), 30);
    assert_eq!(seqs["mics_s"].len(), 12);
    assert_eq!(seqs["mics_w"].len(), 11);
}

#[test]
fn lines_are_the_simulations_sets_and_survive_json() {
    let lines = room_lines();
    let simulation = Simulation::with_start(default_room(), SEED, START).unwrap();
    for line in &lines {
        match line {
            ReplayLine::Measurements(set) => {
                let index = simulation.sensor_index(set.sensor.as_str()).unwrap();
                assert_eq!(&simulation.measurement_set(index, set.seq).unwrap(), set);
            }
            ReplayLine::Truth(set) => {
                let k = ((set.stamp - START) * 25.0).round() as u64;
                assert_eq!(&simulation.truth_set(k), set);
            }
            ReplayLine::Descriptor(_) => {}
        }
        let json = serde_json::to_string(line).unwrap();
        let back: ReplayLine = serde_json::from_str(&json).unwrap();
        assert_eq!(&back, line);
    }
}
