//! The built-in scenarios: their files match them, and the room is what it claims.

use nalgebra::Vector3;
use protocol::SensorKind;
use simulator::{default_room, dense, Scenario, Simulation, ROOM_FLOOR};

const SCENARIO_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios");

#[test]
fn room_file_parses_to_the_default_room() {
    let from_file = Scenario::from_file(format!("{SCENARIO_DIR}/room.toml")).unwrap();
    assert_eq!(from_file, default_room());
}

#[test]
fn dense_file_parses_to_the_dense_preset() {
    let from_file = Scenario::from_file(format!("{SCENARIO_DIR}/dense.toml")).unwrap();
    assert_eq!(from_file, dense());
}

#[test]
fn presets_validate_and_round_trip_through_toml() {
    for preset in [default_room(), dense()] {
        preset.validate().unwrap();
        let text = preset.to_toml_string().unwrap();
        assert_eq!(Scenario::from_toml_str(&text).unwrap(), preset);
    }
}

#[test]
fn dense_has_fifty_targets_and_eight_fast_cluttered_sensors() {
    let scenario = dense();
    assert_eq!(scenario.targets.len(), 50);
    assert_eq!(scenario.sensors.len(), 8);
    let count = |kind| {
        scenario
            .sensors
            .iter()
            .filter(|s| s.model.kind() == kind)
            .count()
    };
    assert_eq!(count(SensorKind::Camera), 4);
    assert_eq!(count(SensorKind::Lidar), 2);
    assert_eq!(count(SensorKind::Position), 2);
    assert!(scenario
        .sensors
        .iter()
        .all(|s| s.rate_hz == 30.0 && s.clutter_rate == 20.0));
}

#[test]
fn room_people_enter_early_and_stay_in_the_room_and_in_view() {
    let scenario = default_room();
    let mut appear: Vec<f64> = scenario.targets.iter().map(|t| t.appear_s).collect();
    appear.sort_by(f64::total_cmp);
    appear.dedup();
    assert_eq!(appear.len(), 3, "people enter at different times");
    assert!(appear.iter().all(|&t| t <= 5.0), "{appear:?}");

    let mut present = 0usize;
    let mut seen_by_a_camera = 0usize;
    let mut seen_by_both = 0usize;
    for seed in [1, 2, 3] {
        let simulation = Simulation::with_start(scenario.clone(), seed, 0.0).unwrap();
        let cameras: Vec<_> = simulation
            .sensors()
            .iter()
            .filter(|s| s.spec().model.kind() == SensorKind::Camera)
            .collect();
        assert_eq!(cameras.len(), 2);
        for k in 0..scenario.truth_count(scenario.duration_s) {
            for object in simulation.truth_set(k).objects {
                let [x, y, z] = object.position;
                let [[x0, y0], [x1, y1]] = ROOM_FLOOR;
                assert!(
                    (x0..=x1).contains(&x) && (y0..=y1).contains(&y) && (1.6..=1.8).contains(&z),
                    "person {} left the room: {:?}",
                    object.id,
                    object.position
                );
                let p = Vector3::from(object.position);
                let seeing = cameras
                    .iter()
                    .filter(|c| c.model().detection_probability(&p) > 0.0)
                    .count();
                present += 1;
                seen_by_a_camera += usize::from(seeing > 0);
                seen_by_both += usize::from(seeing == 2);
            }
        }
    }
    let in_view = seen_by_a_camera as f64 / present as f64;
    let in_both = seen_by_both as f64 / present as f64;
    println!("room: people in at least one camera {in_view:.3}, in both {in_both:.3}");
    assert!(in_view >= 0.9, "in view only {in_view:.3} of the time");
}

#[test]
fn scenarios_md_example_parses() {
    let doc = include_str!("../SCENARIOS.md");
    let start = doc
        .find("```toml\n")
        .expect("SCENARIOS.md has a toml example")
        + 8;
    let end = start + doc[start..].find("```").expect("the example is closed");
    let scenario = Scenario::from_toml_str(&doc[start..end]).unwrap();
    assert_eq!(scenario.targets.len(), 3);
    let kinds: Vec<SensorKind> = scenario.sensors.iter().map(|s| s.model.kind()).collect();
    assert_eq!(kinds, SensorKind::ALL);
    Simulation::new(scenario, 1).unwrap();
}

#[test]
fn the_closest_pair_is_the_smallest_horizontal_distance_between_present_people() {
    let room = default_room();
    assert_eq!(room.closest_pair_m(1, -1.0), None, "nobody in the room yet");
    let t = 10.0;
    let heads: Vec<[f64; 3]> = room
        .present_at(1, t)
        .into_iter()
        .map(|(_, head)| head)
        .collect();
    assert!(heads.len() >= 2);
    let closest = room.closest_pair_m(1, t).unwrap();
    for (i, a) in heads.iter().enumerate() {
        for b in &heads[i + 1..] {
            assert!((a[0] - b[0]).hypot(a[1] - b[1]) >= closest);
        }
    }
    assert!(heads.iter().enumerate().any(|(i, a)| heads[i + 1..]
        .iter()
        .any(|b| (a[0] - b[0]).hypot(a[1] - b[1]) == closest)));
}
