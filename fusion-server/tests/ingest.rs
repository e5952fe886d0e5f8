//! Asynchronous ingest: every set is processed at once; a set older than what was processed
//! rolls the filter back and the result is that of stamp order; a set older than
//! `ingest.max_lateness_s` is late; `seq` gaps count as lost.

use fusion_server::config::ServerConfig;
use fusion_server::engine::{Engine, Rejection};
use protocol::{MeasurementSet, SensorDescriptor, WireFormat};

const T0: f64 = 1_763_700_000.0;

fn position_sensor(name: &str) -> SensorDescriptor {
    serde_json::from_value(serde_json::json!({
        "version": 1, "site": "default", "sensor": name,
        "model": {"kind": "position", "noise_std": [0.1, 0.1, 0.1],
                  "region": {"min": [0, 0, 0], "max": [3, 2, 2.2]}},
        "detection_probability": 0.9, "clutter_rate": 0.5
    }))
    .unwrap()
}

fn admit(engine: &mut Engine, name: &str, seq: u64, stamp: f64, now: f64) -> Result<(), Rejection> {
    let set = MeasurementSet::new(
        protocol::SensorId::new(name).unwrap(),
        seq,
        stamp,
        vec![vec![1.0, 1.0, 1.7]],
    );
    let bytes = protocol::encode(&set, WireFormat::Postcard).unwrap();
    engine.admit_set(Some(&set.sensor), &bytes, WireFormat::Postcard, now)
}

#[test]
fn out_of_order_arrivals_are_processed_at_once_and_corrected() {
    let mut engine = Engine::new(ServerConfig::default(), T0, true).unwrap();
    engine
        .learn_descriptor(position_sensor("a"), false)
        .unwrap();
    engine
        .learn_descriptor(position_sensor("b"), false)
        .unwrap();
    admit(&mut engine, "a", 0, T0 + 0.10, T0 + 0.11).unwrap();
    let first = engine.step(T0 + 0.11);
    let stamps: Vec<f64> = first.tracks.iter().map(|t| t.stamp).collect();
    assert_eq!(
        stamps,
        vec![T0 + 0.10],
        "a is processed as soon as it arrives"
    );
    // b's set is older but arrives later: the filter goes back and processes both in order.
    admit(&mut engine, "b", 0, T0 + 0.05, T0 + 0.15).unwrap();
    let corrected = engine.step(T0 + 0.15);
    let stamps: Vec<f64> = corrected.tracks.iter().map(|t| t.stamp).collect();
    assert_eq!(stamps, vec![T0 + 0.05, T0 + 0.10]);
    let seqs: Vec<u64> = corrected.tracks.iter().map(|t| t.seq).collect();
    assert_eq!(seqs, vec![2, 3], "seq keeps increasing");
    let status = engine.status(T0 + 0.2);
    let b = status
        .sensors
        .iter()
        .find(|s| s.sensor.as_str() == "b")
        .unwrap();
    let a = status
        .sensors
        .iter()
        .find(|s| s.sensor.as_str() == "a")
        .unwrap();
    assert_eq!((b.processed, b.rollbacks, b.late), (1, 1, 0), "{b:?}");
    assert_eq!((a.processed, a.reprocessed), (1, 1), "{a:?}");
}

#[test]
fn late_sets_are_dropped_and_gaps_are_lost() {
    let mut engine = Engine::new(ServerConfig::default(), T0, true).unwrap();
    engine
        .learn_descriptor(position_sensor("a"), false)
        .unwrap();
    admit(&mut engine, "a", 0, T0 + 3.0, T0 + 3.0).unwrap();
    assert_eq!(engine.step(T0 + 3.0).tracks.len(), 1);
    // Older than the 2 s of history kept.
    let late = admit(&mut engine, "a", 1, T0 + 0.5, T0 + 3.0);
    assert!(matches!(late, Err(Rejection::Late { .. })), "{late:?}");
    admit(&mut engine, "a", 5, T0 + 3.1, T0 + 3.1).unwrap();
    engine.step(T0 + 3.1);
    let status = engine.status(T0 + 3.0);
    let a = &status.sensors[0];
    assert_eq!(
        (a.received, a.processed, a.late, a.lost),
        (3, 2, 1, 3),
        "{a:?}"
    );
    assert_eq!(status.rejected.late, 1);
}
