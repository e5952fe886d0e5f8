//! Late sensors, live: an outside client publishes the default room as JSON over Zenoh at the
//! real rate, cam1's sets 0.4 s late and cam2's 1.0 s late, to the real server in its default
//! configuration. No set is refused, every set is processed, the late cameras cause rollbacks,
//! and the final tracks are bit for bit those of processing the same sets in stamp order.

mod support;

use checker::{query_status, query_tracks};
use fusion_server::config::ServerConfig;
use fusion_server::engine::Engine;
use protocol::{keys, MeasurementSet, SensorDescriptor, Site, TrackSet, WireFormat};
use support::{now, scratch, sleep, start_server, Hub};
use zenoh::bytes::Encoding;

/// Scenario seconds published: the room's three people are all in from 4.5 s.
const SECONDS: f64 = 8.0;

/// The room's descriptors and sets, stamped from `start`.
fn room(start: f64) -> anyhow::Result<(Vec<SensorDescriptor>, Vec<MeasurementSet>)> {
    let mut scenario = simulator::default_room();
    scenario.start = Some(start);
    Ok(simulator::descriptors_and_sets(&scenario, 5, SECONDS)?)
}

/// How late each sensor's sets arrive.
fn delay_s(set: &MeasurementSet) -> f64 {
    match set.sensor.as_str() {
        "cam1" => 0.4,
        "cam2" => 1.0,
        _ => 0.0,
    }
}

/// The tracks after the last set, processing every set in stamp order.
fn in_stamp_order(descriptors: &[SensorDescriptor], sets: &[MeasurementSet]) -> TrackSet {
    let start = sets.first().map_or(0.0, |s| s.stamp);
    let mut engine = Engine::new(ServerConfig::default(), start, false).expect("default config");
    for d in descriptors {
        engine
            .learn_descriptor(d.clone(), false)
            .expect("room descriptor");
    }
    for set in sets {
        engine
            .admit_decoded(None, set.clone(), set.stamp)
            .expect("an in-order set is admitted");
        engine.step(set.stamp);
    }
    engine.tracks().clone()
}

/// Puts `value` as JSON on `key`.
async fn put_json<T: serde::Serialize>(
    session: &zenoh::Session,
    key: String,
    value: &T,
) -> anyhow::Result<()> {
    session
        .put(key, protocol::encode(value, WireFormat::Json)?)
        .encoding(Encoding::APPLICATION_JSON)
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn late_cameras_lose_nothing_and_change_nothing() -> anyhow::Result<()> {
    let dir = scratch("late-sensors");
    let hub = Hub::start().await?;
    let site = Site::default();
    let _server = start_server(&hub.endpoint, &dir.join("server.log"), &[])?;
    sleep(1.0).await;
    let start = now() + 0.5;
    let (descriptors, mut sets) = room(start)?;
    for d in &descriptors {
        put_json(&hub.session, keys::descriptor_key(&site, &d.sensor), d).await?;
    }
    sleep(0.3).await;

    sets.sort_by(|a, b| (a.stamp + delay_s(a)).total_cmp(&(b.stamp + delay_s(b))));
    for set in &sets {
        let wait = set.stamp + delay_s(set) - now();
        if wait > 0.0 {
            sleep(wait).await;
        }
        put_json(
            &hub.session,
            keys::measurements_key(&site, &set.sensor),
            set,
        )
        .await?;
    }
    sleep(1.5).await;

    let status = query_status(&hub.session, &site, WireFormat::Json).await?;
    println!(
        "room, cam1 0.4 s and cam2 1.0 s late: server arrival → put p50 {:?} ms, p99 {:?} ms",
        status.latency_ms.p50, status.latency_ms.p99
    );
    for sensor in &status.sensors {
        let sent = sets.iter().filter(|s| s.sensor == sensor.sensor).count() as u64;
        println!(
            "  {}: sent {sent}, received {}, processed {}, late {}, rollbacks {}, re-processed {}",
            sensor.sensor,
            sensor.received,
            sensor.processed,
            sensor.late,
            sensor.rollbacks,
            sensor.reprocessed
        );
        assert_eq!(sensor.received, sent, "{sensor:?}");
        assert_eq!(sensor.processed, sent, "{sensor:?}");
        assert_eq!(sensor.late + sensor.invalid + sensor.lost, 0, "{sensor:?}");
    }
    let rollbacks: u64 = status.sensors.iter().map(|s| s.rollbacks).sum();
    assert!(rollbacks > 0, "the late cameras caused no rollback");

    sets.sort_by(|a, b| a.stamp.total_cmp(&b.stamp));
    let expected = in_stamp_order(&descriptors, &sets);
    let live = query_tracks(&hub.session, &site, WireFormat::Json).await?;
    assert_eq!(live.stamp.to_bits(), expected.stamp.to_bits());
    assert_eq!(
        expected.tracks.len(),
        3,
        "three people tracked: {expected:?}"
    );
    assert_eq!(
        serde_json::to_string(&live.tracks)?,
        serde_json::to_string(&expected.tracks)?,
        "live tracks differ from stamp-order processing"
    );
    Ok(())
}
