//! `fusion-demo`: the whole pipeline on one machine. Starts the fusion server and one simulated
//! edge agent per sensor of the default room (or `--scenario`), in Zenoh peer mode on loopback,
//! prints live tracks, and at the end OSPA against the truth and an SVG plot. `fusion-view` runs
//! beside them: the demo prints its URL, where the run can be watched in a browser.
//!
//! With `--raw` the agents run their real front ends instead (`edge-agent camera --frames`,
//! `mic-pair --wav`, `lidar --scans`) on raw signals rendered from the truth before the run
//! (`checker::raw_inputs`), and the demo publishes the truth itself.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use checker::processes::{binary, free_port, Managed};
use checker::raw_inputs::{agent_command, publish_truth, remove_rendered, render_sensors};
use checker::{query_status, Observed, Observer};
use clap::Parser;
use evaluation::{mean_ospa, plot, PlotData};
use protocol::WireFormat;
use transport::ZenohConfig;

/// Run the fusion server and simulated agents together and watch the tracks.
#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// Seconds of scenario to run.
    #[arg(long, default_value_t = 30.0)]
    duration: f64,
    /// Scenario file (simulator/SCENARIOS.md); the built-in room when absent.
    #[arg(long)]
    scenario: Option<PathBuf>,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where to write the plot of tracks over truth.
    #[arg(long, default_value = "fusion-demo.svg")]
    plot: PathBuf,
    /// Directory for the processes' logs.
    #[arg(long, default_value = "fusion-demo-logs")]
    logs: PathBuf,
    /// Where `fusion-view` serves its page (another free port on 127.0.0.1 when this one is taken).
    #[arg(long, default_value = "127.0.0.1:8080")]
    view: std::net::SocketAddr,
    /// Do not start `fusion-view`.
    #[arg(long)]
    no_view: bool,
    /// Run the real front ends on raw signals (camera frames, audio, LIDAR scans) rendered from
    /// the truth into the logs directory before the run, instead of simulated measurement sets. The
    /// cameras' room and the LIDAR's scene are the default room's, whatever the scenario.
    #[arg(long)]
    raw: bool,
    /// With `--raw`: keep the rendered signals in `<logs>/raw/` after the run (1.2 GB for 30 s).
    #[arg(long)]
    keep_raw: bool,
}

/// Starts `fusion-view` as a peer of `endpoint` on `address` (or on a free port when that one is
/// taken) and prints its URL; `None`, saying why, when it cannot run.
fn start_view(endpoint: &str, address: std::net::SocketAddr, logs: &Path) -> Option<Managed> {
    let address = match std::net::TcpListener::bind(address) {
        Ok(_) => address.to_string(),
        Err(_) => format!("127.0.0.1:{}", free_port().ok()?),
    };
    let started = binary("fusion-view").and_then(|bin| {
        let mut cmd = Command::new(bin);
        cmd.args(["--mode", "peer", "--connect", endpoint, "--http", &address]);
        Managed::spawn("fusion-view", cmd, Some(&logs.join("fusion-view.log")))
    });
    match started {
        Ok(view) => {
            println!("fusion-demo: watch it live at http://{address}/");
            Some(view)
        }
        Err(e) => {
            println!("fusion-demo: no live view ({e})");
            None
        }
    }
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() -> anyhow::Result<()> {
    // Zenoh's own warnings (a peer's link going as its agent exits) are noise on the printout.
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| "warn,zenoh=error".into()),
        )
        .init();
    let args = Args::parse();
    let scenario = match &args.scenario {
        Some(path) => simulator::Scenario::from_file(path)?,
        None => simulator::default_room(),
    };
    let site = scenario.site.clone();
    let server_bin = binary("fusion-server")?;
    let agent_bin = binary("edge-agent")?;
    std::fs::create_dir_all(&args.logs)?;
    // Rendering comes first: it takes a while, and nothing else has started to wait for it.
    let raw_dir = args.logs.join("raw");
    let raw = args
        .raw
        .then(|| render_sensors(&scenario, args.seed, args.duration, &raw_dir, "fusion-demo"))
        .transpose()?;
    let port = free_port()?;
    let endpoint = format!("tcp/127.0.0.1:{port}");

    println!(
        "fusion-demo: server on {endpoint}, site {site}, {} sensors, {} s",
        scenario.sensors.len(),
        args.duration
    );
    let mut server = start_server(&server_bin, &endpoint, &site, &args.logs)?;
    // Let the server listen before the agents connect; all agents share one start time so that
    // their stamps and truth agree.
    tokio::time::sleep(Duration::from_millis(500)).await;
    let start = fusion_server::clock::now() + 1.5;
    let mut agents = match &raw {
        Some(sensors) => start_raw_agents(&agent_bin, sensors, &scenario, &args, &endpoint, start)?,
        None => start_agents(&agent_bin, &scenario, &args, &endpoint, start)?,
    };

    let watcher = ZenohConfig {
        connect: vec![endpoint.clone()],
        ..ZenohConfig::default()
    };
    let session = watcher.open().await?;
    let observer = Observer::start(&session, &site).await?;
    let mut view = (!args.no_view)
        .then(|| start_view(&endpoint, args.view, &args.logs))
        .flatten();
    print_live_tracks(&observer, &mut server, &args, start).await?;

    let status = query_status(&session, &site, WireFormat::Json).await;
    let observed = observer.snapshot();
    for agent in agents.iter_mut().chain(view.as_mut()) {
        agent.stop(Duration::from_secs(3));
    }
    server.stop(Duration::from_secs(5));
    if args.raw && !args.keep_raw {
        remove_rendered(&raw_dir);
    }

    println!();
    print_status(status);
    report_accuracy(&observed, &args.plot)
}

/// Starts the fusion server as a peer listening on `endpoint`, logging into `logs`.
fn start_server(
    server_bin: &Path,
    endpoint: &str,
    site: &protocol::Site,
    logs: &Path,
) -> anyhow::Result<Managed> {
    let mut server_cmd = Command::new(server_bin);
    server_cmd
        .arg("run")
        .env("FUSION__ZENOH__MODE", "peer")
        .env("FUSION__ZENOH__LISTEN", endpoint)
        .env("FUSION__SITE__NAME", site.as_str())
        .env("FUSION__LOG__LEVEL", "info,zenoh=warn");
    Managed::spawn(
        "fusion-server",
        server_cmd,
        Some(&logs.join("fusion-server.log")),
    )
}

/// Starts one simulating edge agent per sensor of `scenario`, all with scenario time 0 at
/// `start`; the first also publishes the truth.
fn start_agents(
    agent_bin: &Path,
    scenario: &simulator::Scenario,
    args: &Args,
    endpoint: &str,
    start: f64,
) -> anyhow::Result<Vec<Managed>> {
    let mut agents = Vec::new();
    for (i, spec) in scenario.sensors.iter().enumerate() {
        let mut cmd = Command::new(agent_bin);
        cmd.args(["sim", "--mode", "peer", "--connect", endpoint])
            .args(["--sensor", spec.sensor.as_str()])
            .args(["--seed", &args.seed.to_string()])
            .args(["--start", &format!("{start:.6}")])
            .args(["--duration", &args.duration.to_string()]);
        if let Some(path) = &args.scenario {
            cmd.arg("--scenario").arg(path);
        }
        if i == 0 {
            cmd.arg("--truth");
        }
        let log = args.logs.join(format!("edge-agent-{}.log", spec.sensor));
        agents.push(Managed::spawn(
            &format!("edge-agent {}", spec.sensor),
            cmd,
            Some(&log),
        )?);
    }
    Ok(agents)
}

/// Starts one front-end agent per rendered sensor, all with scenario time 0 at `start`, and the
/// task that publishes the truth in their stead (no simulating agent runs to do it).
fn start_raw_agents(
    agent_bin: &Path,
    sensors: &[checker::raw_inputs::RawSensor],
    scenario: &simulator::Scenario,
    args: &Args,
    endpoint: &str,
    start: f64,
) -> anyhow::Result<Vec<Managed>> {
    let truth = publish_truth(
        scenario.clone(),
        args.seed,
        start,
        args.duration,
        endpoint.to_string(),
    );
    tokio::spawn(async move {
        // Without truth nothing is scored: say why rather than print empty figures at the end.
        if let Err(e) = truth.await {
            println!("fusion-demo: publishing the truth failed: {e}");
        }
    });
    sensors
        .iter()
        .map(|sensor| {
            let cmd = agent_command(agent_bin, sensor, endpoint, start);
            let log = args.logs.join(format!("edge-agent-{}.log", sensor.sensor));
            Managed::spawn(&format!("edge-agent {}", sensor.sensor), cmd, Some(&log))
        })
        .collect()
}

/// Prints the latest track set once a second until the run is over (its duration and 2.5 s for
/// the last sets to arrive); fails as soon as the server has exited.
async fn print_live_tracks(
    observer: &Observer,
    server: &mut Managed,
    args: &Args,
    start: f64,
) -> anyhow::Result<()> {
    let began = Instant::now();
    let total = Duration::from_secs_f64(args.duration + 2.5);
    while began.elapsed() < total {
        tokio::time::sleep(Duration::from_secs(1)).await;
        anyhow::ensure!(
            server.is_running(),
            "the fusion server exited; see {}",
            args.logs.display()
        );
        match observer.latest_tracks() {
            Some(tracks) => println!("{}", describe_tracks(&tracks, start)),
            None => println!(
                "t = {:5.1} s  waiting for tracks …",
                began.elapsed().as_secs_f64()
            ),
        }
    }
    Ok(())
}

/// One line for a track set: its time since `start`, its count and each track's position.
fn describe_tracks(tracks: &protocol::TrackSet, start: f64) -> String {
    let listed: Vec<String> = tracks
        .tracks
        .iter()
        .map(|t| {
            format!(
                "#{} ({:.2}, {:.2}, {:.2})",
                t.id, t.position[0], t.position[1], t.position[2]
            )
        })
        .collect();
    format!(
        "t = {:5.1} s  {} tracks (expected {:.2}): {}",
        (tracks.stamp - start).max(0.0),
        tracks.tracks.len(),
        tracks.expected_count,
        listed.join("  ")
    )
}

/// Prints the mean OSPA over the whole run and once everyone is in, and draws the plot at
/// `plot_path`.
fn report_accuracy(observed: &Observed, plot_path: &Path) -> anyhow::Result<()> {
    let scores = observed.scores();
    let truth = observed.truth_sets();
    let max_count = truth.iter().map(|t| t.objects.len()).max().unwrap_or(0);
    let all_in = truth
        .iter()
        .find(|t| t.objects.len() == max_count)
        .map(|t| t.stamp);
    println!(
        "{} track sets and {} truth sets received",
        observed.tracks.len(),
        truth.len()
    );
    match mean_ospa(&scores, f64::NEG_INFINITY) {
        Some((ospa, n)) => {
            println!("mean OSPA over the whole run: {ospa:.3} m ({n} track sets, c = 1 m, p = 1)")
        }
        None => println!("no track set could be scored against the truth"),
    }
    // Tracks need about 2 s to be confirmed after the last person enters.
    if let Some((ospa, n)) = all_in.and_then(|t| mean_ospa(&scores, t + 2.0)) {
        println!("mean OSPA once all {max_count} people are in view (+2 s): {ospa:.3} m ({n} track sets)");
    }
    plot(
        PlotData {
            tracks: &observed.tracks,
            truth: &truth,
            scores: &scores,
        },
        plot_path,
    )?;
    println!("plot: {}", plot_path.display());
    Ok(())
}

/// Says which sensors lost a tenth of their sets as too late: with `--raw` a front end slower than
/// real time on a busy host falls behind its stamps, and the OSPA is then that of the others.
fn warn_if_behind(sensors: &[protocol::SensorStatus]) {
    for s in sensors.iter().filter(|s| s.late * 10 > s.received) {
        println!(
            "sensor {}: {} of {} sets came more than the server's max lateness late (its agent fell behind real time; the host is too busy)",
            s.sensor.as_str(), s.late, s.received
        );
    }
}

/// Prints the server's per-sensor counters and latency at the end of the run.
fn print_status(status: anyhow::Result<protocol::Status>) {
    match status {
        Ok(status) => {
            for s in &status.sensors {
                println!(
                    "sensor {:8} {:14} received {:5} processed {:5} late {:3} invalid {:3} lost {:3} rollbacks {:3}",
                    s.sensor.as_str(), s.kind.name(), s.received, s.processed, s.late, s.invalid, s.lost, s.rollbacks
                );
            }
            warn_if_behind(&status.sensors);
            let ms = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2} ms"));
            println!(
                "latency from arrival to the put of the tracks: p50 {}, p99 {}; {} components",
                ms(status.latency_ms.p50),
                ms(status.latency_ms.p99),
                status.components
            );
        }
        Err(e) => println!("status query failed: {e}"),
    }
}
