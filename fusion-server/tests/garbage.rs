//! Bad input never hurts: the same honest sets with and without an interleaved garbage
//! publisher give identical track sets, and every bad message is counted.

use fusion_server::config::ServerConfig;
use fusion_server::engine::Engine;
use protocol::{MeasurementSet, ReplayLine, SensorId, TrackSet, WireFormat};

fn room_lines() -> Vec<ReplayLine> {
    let mut scenario = simulator::default_room();
    scenario.start = Some(1_763_700_000.0);
    simulator::replay_lines(&scenario, 21, 10.0)
        .unwrap()
        .collect()
}

/// Runs the engine over the lines, the clock being each set's stamp; with `rogue`, bad
/// messages of every kind go in before each honest set.
fn run(lines: &[ReplayLine], rogue: bool) -> (Vec<TrackSet>, Engine) {
    let mut engine = Engine::new(ServerConfig::default(), 1_763_700_000.0, true).unwrap();
    let mut out = Vec::new();
    let stranger = SensorId::new("stranger").unwrap();
    for (i, line) in lines.iter().enumerate() {
        match line {
            ReplayLine::Descriptor(d) => {
                engine.learn_descriptor(d.clone(), false).unwrap();
            }
            ReplayLine::Measurements(set) => {
                let now = set.stamp;
                if rogue {
                    let key = Some(&set.sensor);
                    let garbage: Vec<u8> = (0..40).map(|b| (b * 31 + i) as u8).collect();
                    assert!(engine
                        .admit_set(key, &garbage, WireFormat::Postcard, now)
                        .is_err());
                    assert!(engine
                        .admit_set(key, b"{\"version\":1", WireFormat::Json, now)
                        .is_err());
                    let mut wrong_dim = set.clone();
                    wrong_dim.measurements = vec![vec![0.5; 7]];
                    let bytes = protocol::encode(&wrong_dim, WireFormat::Json).unwrap();
                    assert!(engine
                        .admit_set(key, &bytes, WireFormat::Json, now)
                        .is_err());
                    let mut future = set.clone();
                    future.stamp += 3600.0;
                    let bytes = protocol::encode(&future, WireFormat::Postcard).unwrap();
                    assert!(engine
                        .admit_set(key, &bytes, WireFormat::Postcard, now)
                        .is_err());
                    let unknown = MeasurementSet::new(
                        stranger.clone(),
                        i as u64,
                        now,
                        vec![vec![1.0, 2.0, 3.0]],
                    );
                    let bytes = protocol::encode(&unknown, WireFormat::Postcard).unwrap();
                    assert!(engine
                        .admit_set(Some(&stranger), &bytes, WireFormat::Postcard, now)
                        .is_err());
                }
                let bytes = protocol::encode(set, WireFormat::Postcard).unwrap();
                engine
                    .admit_set(Some(&set.sensor), &bytes, WireFormat::Postcard, now)
                    .unwrap();
                out.extend(engine.step(now).tracks);
            }
            ReplayLine::Truth(_) => {}
        }
    }
    let end = lines.iter().filter_map(|l| l.stamp()).fold(0.0, f64::max);
    out.extend(engine.step(end).tracks);
    (out, engine)
}

#[test]
fn garbage_leaves_the_tracks_of_honest_sensors_unchanged() {
    let lines = room_lines();
    let (clean, _) = run(&lines, false);
    let (dirty, engine) = run(&lines, true);
    assert!(
        clean.iter().any(|t| !t.tracks.is_empty()),
        "the room is tracked"
    );
    assert_eq!(
        clean, dirty,
        "identical track sets with and without the rogue"
    );

    let status = engine.status(1_763_700_010.0);
    let sets = lines
        .iter()
        .filter(|l| matches!(l, ReplayLine::Measurements(_)))
        .count() as u64;
    println!("{sets} honest sets; rejected {:?}", status.rejected);
    assert_eq!(status.rejected.undecodable, 2 * sets);
    assert_eq!(status.rejected.invalid, 2 * sets);
    assert_eq!(status.rejected.unknown_sensor, sets);
    let per_sensor_invalid: u64 = status.sensors.iter().map(|s| s.invalid).sum();
    let processed: u64 = status.sensors.iter().map(|s| s.processed).sum();
    assert_eq!(
        per_sensor_invalid,
        4 * sets,
        "each sensor counts what came on its key"
    );
    assert_eq!(processed, sets, "every honest set was processed");
}
