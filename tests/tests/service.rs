//! The real server and agents over Zenoh on loopback: tracks appear and are accurate, both
//! query encodings answer, a JSON set from an outside client is accepted, garbage is counted
//! and harmless, and a restart keeps the track ids.

mod support;

use checker::{query_status, query_tracks, Observer};
use evaluation::mean_ospa;
use protocol::{keys, MeasurementSet, SensorDescriptor, SensorId, Site, WireFormat};
use support::{now, scratch, sleep, start_agents, start_server, Hub};
use zenoh::bytes::Encoding;

/// The room's third person enters at 4.5 s; tracks are confirmed well within 2 s after.
const ALL_IN_S: f64 = 6.5;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn tracks_queries_json_clients_and_garbage() -> anyhow::Result<()> {
    let dir = scratch("service");
    let hub = Hub::start().await?;
    let site = Site::default();
    let observer = Observer::start(&hub.session, &site).await?;
    let _server = start_server(&hub.endpoint, &dir.join("server.log"), &[])?;
    sleep(1.0).await;
    let start = now() + 0.5;
    let _agents = start_agents(&hub.endpoint, &dir.join("agents.log"), start, 14.0, 11)?;
    sleep(ALL_IN_S + 3.0).await;

    // Tracks appear and are accurate once everyone is in.
    let scores = observer.snapshot().scores();
    let (ospa, n) = mean_ospa(&scores, start + ALL_IN_S).expect("scored track sets");
    println!("live room: mean OSPA {ospa:.3} m over {n} track sets once all are in");
    assert!(n > 20, "only {n} track sets scored");
    assert!(ospa < 0.2, "mean OSPA {ospa} m");

    // Both encodings answer, and say which they are.
    let json = query_tracks(&hub.session, &site, WireFormat::Json).await?;
    let postcard = query_tracks(&hub.session, &site, WireFormat::Postcard).await?;
    assert_eq!(json.tracks.len(), 3, "three people tracked: {json:?}");
    assert!(postcard.seq >= json.seq);
    let status = query_status(&hub.session, &site, WireFormat::Json).await?;
    let status_pc = query_status(&hub.session, &site, WireFormat::Postcard).await?;
    assert_eq!(status.sensors.len(), 7);
    assert_eq!(status_pc.sensors.len(), 7);
    for sensor in &status.sensors {
        assert!(sensor.alive, "{} not alive", sensor.sensor);
        assert!(sensor.received > 0 && sensor.processed > 0, "{sensor:?}");
        assert_eq!(sensor.invalid + sensor.late + sensor.lost, 0, "{sensor:?}");
    }

    // An outside client speaking JSON: a descriptor, then sets (empty ones: nothing seen in
    // its region, which is away from the people so that it does not disturb their tracks).
    let probe = SensorId::new("probe")?;
    let descriptor: SensorDescriptor = serde_json::from_str(
        r#"{"version": 1, "site": "default", "sensor": "probe",
            "model": {"kind": "position", "noise_std": [0.1, 0.1, 0.1],
                      "region": {"min": [10, 10, 0], "max": [11, 11, 2]}},
            "detection_probability": 0.9, "clutter_rate": 0.5}"#,
    )?;
    hub.session
        .put(
            keys::descriptor_key(&site, &probe),
            serde_json::to_vec(&descriptor)?,
        )
        .encoding(Encoding::APPLICATION_JSON)
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    sleep(0.3).await;
    for seq in 0..5 {
        let set = MeasurementSet::new(probe.clone(), seq, now(), vec![]);
        hub.session
            .put(
                keys::measurements_key(&site, &probe),
                protocol::encode(&set, WireFormat::Json)?,
            )
            .encoding(Encoding::APPLICATION_JSON)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        sleep(0.05).await;
    }

    // A rogue publisher: garbage, invalid sets on cam1's key, an unknown sensor.
    let rogue = checker::rogue::run_rogue(
        &hub.session,
        &site,
        &SensorId::new("cam1")?,
        std::time::Duration::from_secs(1),
        100.0,
    )
    .await?;
    sleep(1.0).await;

    let status = query_status(&hub.session, &site, WireFormat::Json).await?;
    let probe_status = status
        .sensors
        .iter()
        .find(|s| s.sensor == probe)
        .expect("probe learned");
    assert_eq!(
        (probe_status.received, probe_status.processed),
        (5, 5),
        "{probe_status:?}"
    );
    assert!(
        status.rejected.undecodable >= rogue.garbage,
        "{:?} vs {rogue:?}",
        status.rejected
    );
    assert!(
        status.rejected.invalid >= rogue.invalid,
        "{:?} vs {rogue:?}",
        status.rejected
    );
    assert!(
        status.rejected.unknown_sensor >= rogue.unknown,
        "{:?} vs {rogue:?}",
        status.rejected
    );
    let tracks = query_tracks(&hub.session, &site, WireFormat::Postcard).await?;
    assert_eq!(
        tracks.tracks.len(),
        3,
        "tracks survive the rogue: {tracks:?}"
    );
    let after = observer.snapshot().scores();
    let (ospa_after, _) = mean_ospa(&after, now() - 2.0).expect("tracks after the rogue");
    println!(
        "after the rogue: {rogue:?}, rejected {:?}, OSPA {ospa_after:.3} m",
        status.rejected
    );
    assert!(ospa_after < 0.2);
    Ok(())
}

/// The dominant track id of each true object while watching for `seconds`.
async fn identities(hub: &Hub, site: &Site, seconds: f64) -> anyhow::Result<Vec<(u64, u64)>> {
    let observer = Observer::start(&hub.session, site).await?;
    sleep(seconds).await;
    let observed = observer.snapshot();
    let mut counts: std::collections::BTreeMap<(u64, u64), usize> = Default::default();
    for set in &observed.tracks {
        let Some(truth) = observed.truth.values().min_by(|a, b| {
            (a.stamp - set.stamp)
                .abs()
                .total_cmp(&(b.stamp - set.stamp).abs())
        }) else {
            continue;
        };
        for object in &truth.objects {
            let nearest = set.tracks.iter().min_by(|a, b| {
                let d = |t: &protocol::Track| -> f64 {
                    (0..3)
                        .map(|i| (t.position[i] - object.position[i]).powi(2))
                        .sum()
                };
                d(a).total_cmp(&d(b))
            });
            if let Some(track) = nearest {
                *counts.entry((object.id, track.id)).or_default() += 1;
            }
        }
    }
    let mut best: std::collections::BTreeMap<u64, (usize, u64)> = Default::default();
    for ((object, track), n) in counts {
        let entry = best.entry(object).or_insert((0, track));
        if n > entry.0 {
            *entry = (n, track);
        }
    }
    Ok(best
        .into_iter()
        .map(|(object, (_, track))| (object, track))
        .collect())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_restart_keeps_the_track_ids() -> anyhow::Result<()> {
    let dir = scratch("restart");
    let hub = Hub::start().await?;
    let site = Site::default();
    let checkpoint = dir.join("checkpoint.json");
    let env = [
        ("FUSION__CHECKPOINT__PATH", checkpoint.display().to_string()),
        ("FUSION__CHECKPOINT__INTERVAL_S", "0.5".to_string()),
    ];
    let mut server = start_server(&hub.endpoint, &dir.join("server-1.log"), &env)?;
    sleep(1.0).await;
    let start = now() + 0.5;
    let _agents = start_agents(&hub.endpoint, &dir.join("agents.log"), start, 20.0, 5)?;
    sleep(ALL_IN_S + 1.0).await;
    let before = identities(&hub, &site, 2.0).await?;
    assert_eq!(before.len(), 3, "three people tracked before: {before:?}");

    let status = server.stop(std::time::Duration::from_secs(5));
    assert!(
        status.is_some_and(|s| s.success()),
        "graceful shutdown: {status:?}"
    );
    assert!(checkpoint.exists(), "checkpoint written at shutdown");
    let _server = start_server(&hub.endpoint, &dir.join("server-2.log"), &env)?;
    sleep(2.5).await;
    let after = identities(&hub, &site, 2.0).await?;
    println!("track ids before the restart {before:?}, after {after:?}");
    assert_eq!(before, after, "the same people keep the same ids");
    Ok(())
}
