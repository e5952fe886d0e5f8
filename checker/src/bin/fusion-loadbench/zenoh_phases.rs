//! The phases over Zenoh: latency at the real-time rate (default configuration, in order and
//! with late sensors) and throughput.

use std::time::{Duration, Instant};

use crate::echo::Echo;
use crate::offline::{arrivals, scenario_sets, Arrival};
use crate::rig::{Receipt, Rig};
use fusion_server::latency::LatencyHistogram;

use crate::Args;

/// One set as the client sent it.
struct Sent {
    stamp: f64,
    put_at: Instant,
    /// Whether its sensor was on time (the client can tell which TrackSet includes it).
    on_time: bool,
    echo_sent: Instant,
}

/// The first TrackSet received after `put_at` that is stamped at or after `stamp`: the server
/// publishes the newest state after each batch, so that is the first one that includes the set.
fn covering(receipts: &[Receipt], stamp: f64, put_at: Instant) -> Option<Instant> {
    let from = receipts.partition_point(|r| r.at < put_at);
    receipts[from..]
        .iter()
        .find(|r| r.stamp >= stamp)
        .map(|r| r.at)
}

fn histogram_ms(values: impl Iterator<Item = Duration>) -> LatencyHistogram {
    LatencyHistogram::of(values.map(|d| d.as_secs_f64() * 1000.0))
}

/// Latency at the real-time rate against the server's default configuration.
pub async fn latency(args: &Args, arrival: Arrival) -> anyhow::Result<()> {
    let site = simulator::dense().site;
    // Stamps on the wall clock from a moment after the setup.
    let start = fusion_server::clock::now() + 3.0;
    let (descriptors, sets) = scenario_sets(&simulator::dense(), args.latency_seconds, start)?;
    let rig = Rig::start(&site, &descriptors, args.max_components, &[], &args.log).await?;
    let echo = Echo::start(&rig.session, &rig.endpoint).await?;
    let schedule = arrivals(&descriptors, &sets, arrival);
    let late_sensors = [&descriptors[0].sensor, &descriptors[1].sensor];
    let until_start = (start - fusion_server::clock::now()).max(0.0);
    tokio::time::sleep(Duration::from_secs_f64(until_start)).await;
    let t0 = Instant::now();
    let mut sent = Vec::with_capacity(schedule.len());
    for (i, (due, set)) in schedule.iter().enumerate() {
        // Each set goes out when its (delayed) arrival is due.
        let due_at = t0 + Duration::from_secs_f64((due - start).max(0.0));
        tokio::time::sleep_until(due_at.into()).await;
        let put_at = rig.put(set).await?;
        let payload = protocol::encode(set, protocol::WireFormat::Postcard)?;
        let echo_sent = echo.send(i as u64, &payload).await?;
        let on_time = arrival == Arrival::InOrder || !late_sensors.contains(&&set.sensor);
        sent.push(Sent {
            stamp: set.stamp,
            put_at,
            on_time,
            echo_sent,
        });
    }
    let settled_after = settle(&rig, sent.len() as u64).await?;
    println!("  every set accounted for {settled_after:.2} s after the last put");
    report_latency(&rig, &echo, &sent, arrival, args.latency_seconds).await?;
    rig.stop();
    Ok(())
}

async fn report_latency(
    rig: &Rig,
    echo: &Echo,
    sent: &[Sent],
    arrival: Arrival,
    seconds: f64,
) -> anyhow::Result<()> {
    let receipts = rig.receipts.lock().unwrap().clone();
    let service = histogram_ms(sent.iter().filter(|s| s.on_time).filter_map(|s| {
        covering(&receipts, s.stamp, s.put_at).map(|at| at.duration_since(s.put_at))
    }));
    let bare = histogram_ms(sent.iter().enumerate().filter_map(|(i, s)| {
        echo.returned(i as u64)
            .map(|at| at.duration_since(s.echo_sent))
    }));
    let status = rig.status().await?;
    let sum = |f: fn(&protocol::SensorStatus) -> u64| -> u64 { status.sensors.iter().map(f).sum() };
    println!(
        "default configuration, {arrival:?}, {:.0} sets/s: put → first TrackSet including the set (on-time sensors, {} of {}): p50 {} ms, p99 {} ms; bare zenoh round trip: p50 {} ms, p99 {} ms",
        sent.len() as f64 / seconds,
        service.len(),
        sent.iter().filter(|s| s.on_time).count(),
        fmt_ms(service.quantile(0.5)),
        fmt_ms(service.quantile(0.99)),
        fmt_ms(bare.quantile(0.5)),
        fmt_ms(bare.quantile(0.99)),
    );
    println!(
        "  server: {} sets sent, {} processed, {} late, {} invalid; {} rollbacks ({:.2} per set), {} re-processed; arrival → put p50 {} ms, p99 {} ms; {} TrackSets received; peak memory {}",
        sent.len(),
        sum(|s| s.processed),
        sum(|s| s.late),
        sum(|s| s.invalid),
        sum(|s| s.rollbacks),
        sum(|s| s.rollbacks) as f64 / sent.len().max(1) as f64,
        sum(|s| s.reprocessed),
        fmt_ms(status.latency_ms.p50),
        fmt_ms(status.latency_ms.p99),
        receipts.len(),
        rig.peak_memory_kib()
            .map_or("unavailable".into(), |k| format!("{:.1} MiB", k as f64 / 1024.0)),
    );
    Ok(())
}

/// Waits (at most 10 s) until the server has processed, refused or counted as invalid every
/// one of `sent` sets, since late sets may still be held for the next rollback; returns how
/// long that took.
async fn settle(rig: &Rig, sent: u64) -> anyhow::Result<f64> {
    let began = std::time::Instant::now();
    loop {
        tokio::time::sleep(Duration::from_millis(100)).await;
        let status = rig.status().await?;
        let done: u64 = status
            .sensors
            .iter()
            .map(|s| s.processed + s.late + s.invalid)
            .sum();
        if done >= sent || began.elapsed() > Duration::from_secs(10) {
            return Ok(began.elapsed().as_secs_f64());
        }
    }
}

fn fmt_ms(value: Option<f64>) -> String {
    value.map_or("n/a".into(), |v| format!("{v:.3}"))
}

/// Throughput: as fast as the server keeps up, with at most `window` sets in flight.
pub async fn throughput(args: &Args) -> anyhow::Result<()> {
    let site = simulator::dense().site;
    let start = fusion_server::clock::now();
    let (descriptors, sets) = scenario_sets(&simulator::dense(), args.throughput_seconds, start)?;
    // The feed runs ahead of the wall clock by design: relax the guards against that.
    let relaxed = [
        ("FUSION__INGEST__MAX_FUTURE_S", "1000000".to_string()),
        ("FUSION__INGEST__MAX_RATE_HZ", "100000".to_string()),
    ];
    let rig = Rig::start(
        &site,
        &descriptors,
        args.max_components,
        &relaxed,
        &args.log,
    )
    .await?;
    let began = Instant::now();
    for (i, set) in sets.iter().enumerate() {
        if i >= args.window {
            let waited_for = sets[i - args.window].stamp;
            let deadline = Instant::now() + Duration::from_secs(10);
            while !rig.has_covered(waited_for) && Instant::now() < deadline {
                tokio::time::sleep(Duration::from_micros(200)).await;
            }
        }
        rig.put(set).await?;
    }
    if let Some(last) = sets.last() {
        while !rig.has_covered(last.stamp) && began.elapsed() < Duration::from_secs(120) {
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    }
    let elapsed = began.elapsed().as_secs_f64();
    let rate = sets.len() as f64 / elapsed;
    let real_time = sets.len() as f64 / args.throughput_seconds;
    println!(
        "throughput over zenoh: {} sets in {elapsed:.2} s = {rate:.0} sets/s = {:.1} × real time ({real_time:.0} sets/s), {:.0} Hz per sensor ({} sensors)",
        sets.len(),
        rate / real_time,
        rate / descriptors.len() as f64,
        descriptors.len()
    );
    rig.stop();
    Ok(())
}
