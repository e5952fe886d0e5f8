//! Asynchronous ingest: sets are processed in stamp order whatever their arrival order within
//! the reorder window; a set older than what was processed is late; `seq` gaps count as lost.

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
fn out_of_order_arrivals_are_processed_in_stamp_order() {
    let mut engine = Engine::new(ServerConfig::default(), T0, true).unwrap();
    engine
        .learn_descriptor(position_sensor("a"), false)
        .unwrap();
    engine
        .learn_descriptor(position_sensor("b"), false)
        .unwrap();
    // b's set is older but arrives later, within the 150 ms window.
    admit(&mut engine, "a", 0, T0 + 0.10, T0 + 0.11).unwrap();
    admit(&mut engine, "b", 0, T0 + 0.05, T0 + 0.15).unwrap();
    assert!(engine.step(T0 + 0.2).is_empty(), "b waits for its window");
    let out = engine.step(T0 + 0.31);
    let stamps: Vec<f64> = out.iter().map(|t| t.stamp).collect();
    assert_eq!(stamps, vec![T0 + 0.05, T0 + 0.10]);
}

#[test]
fn late_sets_are_dropped_and_gaps_are_lost() {
    let mut engine = Engine::new(ServerConfig::default(), T0, true).unwrap();
    engine
        .learn_descriptor(position_sensor("a"), false)
        .unwrap();
    admit(&mut engine, "a", 0, T0 + 1.0, T0 + 1.0).unwrap();
    assert_eq!(engine.step(T0 + 2.0).len(), 1);
    let late = admit(&mut engine, "a", 1, T0 + 0.5, T0 + 2.0);
    assert!(matches!(late, Err(Rejection::Late { .. })), "{late:?}");
    admit(&mut engine, "a", 5, T0 + 2.1, T0 + 2.1).unwrap();
    engine.drain(T0 + 3.0);
    let status = engine.status(T0 + 3.0);
    let a = &status.sensors[0];
    assert_eq!(
        (a.received, a.processed, a.late, a.lost),
        (3, 2, 1, 3),
        "{a:?}"
    );
    assert_eq!(status.rejected.late, 1);
}
