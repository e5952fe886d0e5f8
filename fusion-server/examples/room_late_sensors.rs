//! The default room with its two cameras late (cam1 by 0.4 s, cam2 by 1.0 s), through the engine
//! alone at the real rate: the engine's busy time and, from a one-server queue model (each set is
//! admitted when it arrives or when the engine is free, whichever is later), each set's latency
//! from arrival to the end of the step that processed it, for several `ingest.max_rollback_share`.
//!
//! `cargo run --release --example room_late_sensors`

use std::time::Instant;

use fusion_server::config::ServerConfig;
use fusion_server::engine::Engine;
use protocol::{MeasurementSet, SensorDescriptor};

const T0: f64 = 1_763_700_000.0;
const SECONDS: f64 = 30.0;

fn room() -> (Vec<SensorDescriptor>, Vec<MeasurementSet>) {
    let mut scenario = simulator::default_room();
    scenario.start = Some(T0);
    simulator::descriptors_and_sets(&scenario, 7, SECONDS).expect("the room scenario")
}

/// Arrival time of each set: cam1 0.4 s and cam2 1.0 s after its stamp when `late`.
fn arrivals(sets: &[MeasurementSet], late: bool) -> Vec<(f64, MeasurementSet)> {
    let mut out: Vec<(f64, MeasurementSet)> = sets
        .iter()
        .map(|s| {
            let delay = match (late, s.sensor.as_str()) {
                (true, "cam1") => 0.4,
                (true, "cam2") => 1.0,
                _ => 0.0,
            };
            (s.stamp + delay, s.clone())
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

fn run(descriptors: &[SensorDescriptor], arrivals: &[(f64, MeasurementSet)], share: f64) {
    let mut config = ServerConfig::default();
    config.ingest.max_rollback_share = share;
    let mut engine = Engine::new(config, T0, false).expect("the default configuration");
    for d in descriptors {
        engine
            .learn_descriptor(d.clone(), false)
            .expect("the room's descriptors");
    }
    let (mut free_at, mut busy, mut latency) = (f64::NEG_INFINITY, 0.0, Vec::new());
    for (arrived, set) in arrivals {
        let start = free_at.max(*arrived);
        let began = Instant::now();
        let _ = engine.admit_decoded(None, set.clone(), start);
        let out = engine.step(start);
        let took = began.elapsed().as_secs_f64();
        busy += took;
        free_at = start + took;
        latency.extend(out.arrivals.iter().map(|a| (free_at - a) * 1000.0));
    }
    latency.sort_by(f64::total_cmp);
    let status = engine.status(T0 + SECONDS + 10.0);
    let sum = |f: fn(&protocol::SensorStatus) -> u64| -> u64 { status.sensors.iter().map(f).sum() };
    println!(
        "max_rollback_share {share}: {} sets, engine busy {busy:.2} s of {SECONDS} s, latency p50 {:.3} ms, p99 {:.3} ms; {} rollbacks, {} late",
        arrivals.len(),
        latency[latency.len() / 2],
        latency[latency.len() * 99 / 100],
        sum(|s| s.rollbacks),
        sum(|s| s.late),
    );
}

fn main() {
    let (descriptors, sets) = room();
    println!("in order:");
    run(&descriptors, &arrivals(&sets, false), 0.25);
    println!("cam1 0.4 s and cam2 1.0 s late:");
    for share in [1.0, 0.25, 0.1, 0.02] {
        run(&descriptors, &arrivals(&sets, true), share);
    }
}
