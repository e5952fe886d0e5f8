//! `fusion-loadbench`: the end-to-end load benchmark of the service over Zenoh on loopback.
//!
//! Starts the real `fusion-server` (reorder window 0, publication unthrottled, so that each
//! processed set yields a `TrackSet` stamped with it) and feeds it the dense scenario
//! (simulator::dense: 50 targets, 8 sensors at 30 Hz, 20 clutter per set) from this process:
//! 1. throughput: sets published as fast as the server keeps up (at most `--window` sets in
//!    flight); reports sets processed per second and the multiple of real time;
//! 2. latency at the real-time rate: publish → receipt of the TrackSet that includes the set,
//!    p50/p99, measured in the same run as a bare Zenoh round trip of the same payloads at the
//!    same rate (an echo session), so the figures are comparable;
//! 3. the server's peak resident memory (VmHWM).

use std::collections::{BTreeMap, HashMap};
use std::process::Command;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use checker::processes::{binary, free_port, Managed};
use clap::Parser;
use protocol::{keys, MeasurementSet, TrackSet, WireFormat};
use transport::ZenohConfig;
use zenoh::bytes::Encoding;
use zenoh::qos::CongestionControl;
use zenoh::sample::Sample;

/// End-to-end load benchmark of fusion-server on the dense scenario.
#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// Scenario seconds fed in the throughput phase.
    #[arg(long, default_value_t = 20.0)]
    throughput_seconds: f64,
    /// Scenario seconds fed in the latency phase (at real-time rate).
    #[arg(long, default_value_t = 10.0)]
    latency_seconds: f64,
    /// Sets in flight at most in the throughput phase.
    #[arg(long, default_value_t = 8)]
    window: usize,
    /// Maximum number of Gaussian components (J_max).
    #[arg(long, default_value_t = 1000)]
    max_components: usize,
    /// Server log file.
    #[arg(long, default_value = "loadbench-server.log")]
    log: std::path::PathBuf,
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted[rank.saturating_sub(1).min(sorted.len() - 1)]
}

/// When the first TrackSet that includes the set stamped `stamp_bits` arrived: the first one
/// stamped at or after it (sets are processed in stamp order).
fn covering(received: &BTreeMap<u64, Instant>, stamp_bits: u64) -> Option<Instant> {
    received.range(stamp_bits..).next().map(|(_, at)| *at)
}

fn peak_memory_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
}

/// Sets of the dense scenario in stamp order, starting at `start`.
fn dense_sets(
    start: f64,
    seconds: f64,
    seed: u64,
) -> anyhow::Result<(Vec<protocol::SensorDescriptor>, Vec<MeasurementSet>)> {
    let mut scenario = simulator::dense();
    scenario.start = Some(start);
    let mut descriptors = Vec::new();
    let mut sets = Vec::new();
    for line in simulator::replay_lines(&scenario, seed, seconds)? {
        match line {
            protocol::ReplayLine::Descriptor(d) => descriptors.push(d),
            protocol::ReplayLine::Measurements(s) => sets.push(s),
            protocol::ReplayLine::Truth(_) => {}
        }
    }
    Ok((descriptors, sets))
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let site = simulator::dense().site;
    let port = free_port()?;
    let endpoint = format!("tcp/127.0.0.1:{port}");
    let mut cmd = Command::new(binary("fusion-server")?);
    cmd.arg("run")
        .env("FUSION__ZENOH__LISTEN", &endpoint)
        .env("FUSION__SITE__NAME", site.as_str())
        .env("FUSION__SITE__VOLUME_MIN", "0,0,0")
        .env("FUSION__SITE__VOLUME_MAX", "40,40,10")
        .env("FUSION__FILTER__BIRTH_GRID", "8,8,2")
        .env(
            "FUSION__FILTER__MAX_COMPONENTS",
            args.max_components.to_string(),
        )
        .env("FUSION__INGEST__REORDER_WINDOW_MS", "0")
        .env("FUSION__INGEST__MAX_FUTURE_S", "1000000")
        .env("FUSION__INGEST__MAX_RATE_HZ", "100000")
        .env("FUSION__OUTPUT__MAX_PUBLISH_HZ", "1000000")
        .env("FUSION__LOG__LEVEL", "warn");
    let mut server = Managed::spawn("fusion-server", cmd, Some(&args.log))?;
    let pid = server.id().unwrap_or(0);

    let session = ZenohConfig {
        connect: vec![endpoint.clone()],
        ..ZenohConfig::default()
    }
    .open()
    .await?;
    // Receipt time of each TrackSet, by the bits of its stamp (positive stamps order like
    // their bits). The server publishes only the latest TrackSet of a batch of sets, so a
    // set's tracks are in the first TrackSet stamped at or after it (`covering`).
    let received: Arc<Mutex<BTreeMap<u64, Instant>>> = Arc::default();
    let sink = received.clone();
    let _tracks = session
        .declare_subscriber(keys::tracks_key(&site))
        .callback(move |sample: Sample| {
            let at = Instant::now();
            if let Ok(set) =
                protocol::decode::<TrackSet>(&sample.payload().to_bytes(), WireFormat::Postcard)
            {
                sink.lock().unwrap().insert(set.stamp.to_bits(), at);
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    tokio::time::sleep(Duration::from_millis(800)).await;

    let start = fusion_server::clock::now();
    let (descriptors, sets) = dense_sets(start, args.throughput_seconds + args.latency_seconds, 1)?;
    let postcard = Encoding::from(WireFormat::Postcard.encoding_str());
    for d in &descriptors {
        session
            .put(
                keys::descriptor_key(&site, &d.sensor),
                protocol::encode(d, WireFormat::Postcard)?,
            )
            .encoding(postcard.clone())
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    tokio::time::sleep(Duration::from_millis(500)).await;
    let publishers: HashMap<_, _> = {
        let mut map = HashMap::new();
        for d in &descriptors {
            let publisher = session
                .declare_publisher(keys::measurements_key(&site, &d.sensor))
                .encoding(postcard.clone())
                .congestion_control(CongestionControl::Block)
                .await
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            map.insert(d.sensor.clone(), publisher);
        }
        map
    };
    let split = sets.partition_point(|s| s.stamp < start + args.throughput_seconds);
    let (throughput_sets, latency_sets) = sets.split_at(split);

    // Phase 1: as fast as the server keeps up, with a bounded number in flight.
    println!(
        "dense scenario: {} sensors, {} sets in the throughput phase",
        descriptors.len(),
        throughput_sets.len()
    );
    let began = Instant::now();
    for (i, set) in throughput_sets.iter().enumerate() {
        if i >= args.window {
            let waited_for = throughput_sets[i - args.window].stamp.to_bits();
            let deadline = Instant::now() + Duration::from_secs(10);
            while covering(&received.lock().unwrap(), waited_for).is_none()
                && Instant::now() < deadline
            {
                tokio::time::sleep(Duration::from_micros(200)).await;
            }
        }
        publishers[&set.sensor]
            .put(protocol::encode(set, WireFormat::Postcard)?)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    let last = throughput_sets.last().map(|s| s.stamp.to_bits());
    while let Some(last) = last {
        if covering(&received.lock().unwrap(), last).is_some()
            || began.elapsed() > Duration::from_secs(120)
        {
            break;
        }
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
    let elapsed = began.elapsed().as_secs_f64();
    let rate = throughput_sets.len() as f64 / elapsed;
    let real_time = throughput_sets.len() as f64 / args.throughput_seconds;
    println!(
        "throughput: {} sets in {elapsed:.2} s = {rate:.0} sets/s = {:.1} × real time ({real_time:.0} sets/s)",
        throughput_sets.len(),
        rate / real_time
    );
    // With at most `window` sets in flight the server's queue cannot grow: this is the rate
    // it keeps up with.
    println!(
        "sensor rate sustained without the queue growing: {:.0} Hz per sensor ({} sensors)",
        rate / descriptors.len() as f64,
        descriptors.len()
    );

    // Phase 2: latency at the real-time rate, beside a bare Zenoh echo of the same payloads.
    let echo_key = "fusion-loadbench/echo";
    let back_key = "fusion-loadbench/back";
    let echo_session = ZenohConfig {
        connect: vec![endpoint.clone()],
        ..ZenohConfig::default()
    }
    .open()
    .await?;
    let back = echo_session
        .declare_publisher(back_key)
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let _echo = echo_session
        .declare_subscriber(echo_key)
        .callback(move |sample: Sample| {
            use zenoh::Wait;
            let _ = back.put(sample.payload().clone()).wait();
        })
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let echoed: Arc<Mutex<HashMap<u64, Instant>>> = Arc::default();
    let sink = echoed.clone();
    let _back_sub = session
        .declare_subscriber(back_key)
        .callback(move |sample: Sample| {
            let at = Instant::now();
            let bytes = sample.payload().to_bytes();
            if bytes.len() >= 8 {
                let id = u64::from_le_bytes(bytes[..8].try_into().unwrap());
                sink.lock().unwrap().insert(id, at);
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let echo_pub = session
        .declare_publisher(echo_key)
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    tokio::time::sleep(Duration::from_millis(300)).await;

    let t0 = Instant::now();
    let s0 = latency_sets.first().map_or(0.0, |s| s.stamp);
    let mut sent: Vec<(u64, Instant, u64, Instant)> = Vec::new();
    for (i, set) in latency_sets.iter().enumerate() {
        let due = t0 + Duration::from_secs_f64((set.stamp - s0).max(0.0));
        tokio::time::sleep_until(due.into()).await;
        let payload = protocol::encode(set, WireFormat::Postcard)?;
        let at = Instant::now();
        publishers[&set.sensor]
            .put(payload.clone())
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let mut echo_payload = (i as u64).to_le_bytes().to_vec();
        echo_payload.extend_from_slice(&payload);
        let echo_at = Instant::now();
        echo_pub
            .put(echo_payload)
            .await
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        sent.push((set.stamp.to_bits(), at, i as u64, echo_at));
    }
    tokio::time::sleep(Duration::from_millis(500)).await;
    let received = received.lock().unwrap();
    let echoed = echoed.lock().unwrap();
    let mut service: Vec<f64> = Vec::new();
    let mut bare: Vec<f64> = Vec::new();
    for (stamp, at, id, echo_at) in &sent {
        if let Some(done) = covering(&received, *stamp) {
            service.push(done.duration_since(*at).as_secs_f64() * 1000.0);
        }
        if let Some(done) = echoed.get(id) {
            bare.push(done.duration_since(*echo_at).as_secs_f64() * 1000.0);
        }
    }
    service.sort_by(f64::total_cmp);
    bare.sort_by(f64::total_cmp);
    let rate = latency_sets.len() as f64 / args.latency_seconds;
    println!(
        "latency at {rate:.0} sets/s, publish → tracks including the set ({} of {}): p50 {:.3} ms, p99 {:.3} ms",
        service.len(),
        sent.len(),
        percentile(&service, 0.5),
        percentile(&service, 0.99)
    );
    println!(
        "bare zenoh round trip of the same payloads at the same rate ({} of {}): p50 {:.3} ms, p99 {:.3} ms",
        bare.len(),
        sent.len(),
        percentile(&bare, 0.5),
        percentile(&bare, 0.99)
    );
    match peak_memory_kib(pid) {
        Some(kib) => println!(
            "server peak resident memory: {:.1} MiB",
            kib as f64 / 1024.0
        ),
        None => println!("server peak resident memory: unavailable"),
    }
    drop(received);
    drop(echoed);
    server.stop(Duration::from_secs(5));
    Ok(())
}
