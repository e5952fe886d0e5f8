//! `fusion-checker`: a client of a running deployment, for people and for the compose tests.
//! It queries `tracks` and `status`, scores the published tracks against the simulators' truth,
//! follows which track ids the true objects get, can play a rogue publisher or an impostor, and
//! asks one server instance or every site (`probe`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use checker::probe;
use checker::raw_profile::{render_and_play, render_for_agents, RenderRun, RunStart};
use checker::rogue::run_rogue;
use checker::{query_status, query_tracks, Observer};
use clap::{Parser, Subcommand};
use evaluation::mean_ospa;
use protocol::{SensorId, Site, WireFormat};
use transport::ZenohConfig;

/// Watch and probe a running fusion deployment.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    /// Zenoh mode of this client.
    #[arg(long, default_value = "client", global = true)]
    mode: String,
    /// Router or peer endpoint to connect to (repeatable).
    #[arg(long, global = true, env = "CHECKER_CONNECT", value_delimiter = ',')]
    connect: Vec<String>,
    /// Zenoh JSON5 configuration file (TLS, credentials).
    #[arg(long, global = true)]
    zenoh_config: Option<PathBuf>,
    /// The deployment's site.
    #[arg(long, default_value = "default", global = true)]
    site: String,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print the server's status (JSON): the site's active server, or one instance's own.
    Status {
        /// Ask this server instance (`fusion/<site>/server/<instance>/status`, with its role).
        #[arg(long)]
        instance: Option<String>,
    },
    /// Print the server's current tracks (JSON).
    Tracks,
    /// Score published tracks against the truth for a while; fail when OSPA is too high.
    Watch {
        /// Seconds to watch.
        #[arg(long, default_value_t = 30.0)]
        duration: f64,
        /// Seconds at the start not scored (people entering, tracks confirming).
        #[arg(long, default_value_t = 0.0)]
        skip: f64,
        /// Fail (exit 1) when the mean OSPA exceeds this many metres.
        #[arg(long)]
        max_ospa: Option<f64>,
    },
    /// Wait until track sets flow; print how long it took; fail after the timeout.
    WaitTracks {
        /// Seconds to wait at most.
        #[arg(long, default_value_t = 30.0)]
        timeout: f64,
    },
    /// Watch for a while and print, as JSON, which track ids each true object got.
    Ids {
        /// Seconds to watch.
        #[arg(long, default_value_t = 5.0)]
        duration: f64,
    },
    /// Publish garbage, invalid and unknown-sensor sets, impersonating a sensor.
    Rogue {
        /// The sensor whose key is abused.
        #[arg(long, default_value = "cam1")]
        victim: String,
        /// Seconds to misbehave.
        #[arg(long, default_value_t = 10.0)]
        duration: f64,
        /// Messages per second.
        #[arg(long, default_value_t = 200.0)]
        rate: f64,
    },
    /// Write where this identity may not: forged sets on `victim`'s key, forged track sets,
    /// a fake status queryable; prints what was tried (JSON).
    Impersonate {
        /// The sensor whose measurement key is abused.
        #[arg(long, default_value = "lidar")]
        victim: String,
        /// Seconds to misbehave.
        #[arg(long, default_value_t = 5.0)]
        duration: f64,
        /// Rounds of puts per second.
        #[arg(long, default_value_t = 20.0)]
        rate: f64,
    },
    /// Subscribe to everything of the site and query its status for a while; print what was
    /// genuine and what was forged (JSON).
    Sniff {
        /// Seconds to listen.
        #[arg(long, default_value_t = 5.0)]
        duration: f64,
    },
    /// Query `fusion/*/tracks` and `fusion/*/status`: every site's track count and live sensors (JSON).
    Sites {
        /// Ask again until each of these sites answers with tracks and a status (comma-separated).
        #[arg(long, value_delimiter = ',')]
        expect: Vec<String>,
        /// Seconds to keep asking with `--expect`; exit 1 when a site is still missing.
        #[arg(long, default_value_t = 10.0)]
        timeout: f64,
    },
    /// Render every sensor's raw signal of the default room (camera frames, microphone-pair audio,
    /// LIDAR scans) into a directory, write each sensor's `<sensor>.start` once all are complete
    /// (`edge-agent … --start-file`), then publish the truth in real time: the raw profile's simulator.
    Render {
        /// Directory to render into (emptied first).
        #[arg(long)]
        out: PathBuf,
        /// Seed of the scenario's random streams.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Seconds of scenario to render and play.
        #[arg(long, default_value_t = 30.0)]
        duration: f64,
        /// Seconds from the end of rendering to scenario time 0 (the agents read their inputs).
        #[arg(long, default_value_t = 3.0)]
        lead: f64,
        /// Scenario time 0 at this Unix time instead (e.g. for replay files made from the signals).
        #[arg(long, conflicts_with = "lead")]
        start: Option<f64>,
        /// End once the signals and start files are written: publish no truth.
        #[arg(long)]
        render_only: bool,
    },
    /// Follow the tracks for a while: how many sets arrived and the longest silence (JSON).
    Gaps {
        /// Seconds to listen.
        #[arg(long, default_value_t = 10.0)]
        duration: f64,
    },
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() -> anyhow::Result<()> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env().unwrap_or_else(|_| "warn".into()),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    let site = Site::new(&cli.site)?;
    if let Some(run) = render_run(&cli.command, &site).filter(|run| !run.publish_truth) {
        // Rendering alone needs no router.
        render_for_agents(&run).await?;
        return Ok(());
    }
    let session = zenoh_config(&cli)?.open().await?;
    let code = execute(&session, &site, cli.command).await?;
    let _ = session.close().await;
    std::process::exit(code);
}

/// Runs one command; its exit code.
async fn execute(session: &zenoh::Session, site: &Site, command: Command) -> anyhow::Result<i32> {
    Ok(match command {
        Command::Status { instance: None } => {
            let status = query_status(session, site, WireFormat::Json).await?;
            println!("{}", serde_json::to_string_pretty(&status)?);
            0
        }
        Command::Status {
            instance: Some(instance),
        } => {
            let status = probe::instance_status(session, site, &instance).await?;
            println!("{}", serde_json::to_string_pretty(&status)?);
            0
        }
        Command::Tracks => {
            let tracks = query_tracks(session, site, WireFormat::Json).await?;
            println!("{}", serde_json::to_string_pretty(&tracks)?);
            0
        }
        Command::Watch {
            duration,
            skip,
            max_ospa,
        } => watch(session, site, duration, skip, max_ospa).await?,
        Command::WaitTracks { timeout } => wait_tracks(session, site, timeout).await?,
        Command::Ids { duration } => print_identities(session, site, duration).await?,
        Command::Rogue {
            victim,
            duration,
            rate,
        } => rogue(session, site, victim, duration, rate).await?,
        Command::Impersonate {
            victim,
            duration,
            rate,
        } => {
            let victim = SensorId::new(victim)?;
            let duration = Duration::from_secs_f64(duration);
            let report = probe::impersonate(session, site, &victim, duration, rate).await?;
            println!("{}", serde_json::to_string(&report)?);
            0
        }
        Command::Sniff { duration } => {
            let duration = Duration::from_secs_f64(duration);
            let report = probe::sniff(session, site, duration).await?;
            println!("{}", serde_json::to_string(&report)?);
            0
        }
        Command::Sites { expect, timeout } => {
            let timeout = Duration::from_secs_f64(timeout);
            let answer = probe::wait_sites(session, &expect, timeout).await?;
            println!("{answer}");
            i32::from(answer["complete"] != serde_json::json!(true))
        }
        Command::Gaps { duration } => {
            let duration = Duration::from_secs_f64(duration);
            println!("{}", probe::track_gaps(session, site, duration).await?);
            0
        }
        command @ Command::Render { .. } => {
            let run = render_run(&command, site).expect("a render command");
            render_and_play(session, run).await?;
            0
        }
    })
}

/// What `render` is to do, or `None` for another command.
fn render_run(command: &Command, site: &Site) -> Option<RenderRun> {
    let Command::Render {
        out,
        seed,
        duration,
        lead,
        start,
        render_only,
    } = command
    else {
        return None;
    };
    Some(RenderRun {
        out: out.clone(),
        site: site.clone(),
        seed: *seed,
        duration_s: *duration,
        start: start.map_or(RunStart::AfterRendering { lead_s: *lead }, RunStart::At),
        publish_truth: !render_only,
    })
}

/// The client's Zenoh configuration from the command line, checked before it is used.
fn zenoh_config(cli: &Cli) -> anyhow::Result<ZenohConfig> {
    let config = ZenohConfig {
        mode: cli.mode.clone(),
        connect: cli.connect.clone(),
        listen: Vec::new(),
        scouting: false,
        config_file: cli.zenoh_config.clone(),
    };
    config
        .validate()
        .map_err(|(key, reason)| anyhow::anyhow!("zenoh {key}: {reason}"))?;
    Ok(config)
}

/// `wait-tracks`: 0 once a track set arrives, 1 when none does within `timeout` seconds.
async fn wait_tracks(session: &zenoh::Session, site: &Site, timeout: f64) -> anyhow::Result<i32> {
    let observer = Observer::start(session, site).await?;
    let began = Instant::now();
    loop {
        if observer.latest_tracks().is_some() {
            println!(
                "tracks flowing after {:.2} s",
                began.elapsed().as_secs_f64()
            );
            return Ok(0);
        }
        if began.elapsed().as_secs_f64() > timeout {
            println!("no track set within {timeout} s");
            return Ok(1);
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// `ids`: prints which track ids each true object got over `duration` seconds; 1 when none.
async fn print_identities(
    session: &zenoh::Session,
    site: &Site,
    duration: f64,
) -> anyhow::Result<i32> {
    let observer = Observer::start(session, site).await?;
    tokio::time::sleep(Duration::from_secs_f64(duration)).await;
    let ids = identities(&observer.snapshot());
    println!("{}", serde_json::to_string(&ids)?);
    Ok(i32::from(ids.is_empty()))
}

/// `rogue`: misbehaves as `victim` for `duration` seconds at `rate` messages per second and
/// prints what it sent.
async fn rogue(
    session: &zenoh::Session,
    site: &Site,
    victim: String,
    duration: f64,
    rate: f64,
) -> anyhow::Result<i32> {
    let victim = SensorId::new(victim)?;
    let report = run_rogue(
        session,
        site,
        &victim,
        Duration::from_secs_f64(duration),
        rate,
    )
    .await?;
    println!(
        "rogue sent {} garbage, {} invalid, {} unknown-sensor messages",
        report.garbage, report.invalid, report.unknown
    );
    Ok(0)
}

/// `watch`: scores the tracks against the truth for `duration` seconds, leaving out the first
/// `skip`; 1 when nothing could be scored or the mean OSPA exceeds `max_ospa`.
async fn watch(
    session: &zenoh::Session,
    site: &Site,
    duration: f64,
    skip: f64,
    max_ospa: Option<f64>,
) -> anyhow::Result<i32> {
    let observer = Observer::start(session, site).await?;
    let began = fusion_server::clock::now();
    tokio::time::sleep(Duration::from_secs_f64(duration)).await;
    let observed = observer.snapshot();
    let scores = observed.scores();
    let status = query_status(session, site, WireFormat::Postcard).await;
    println!(
        "watched {duration} s: {} track sets, {} truth sets",
        observed.tracks.len(),
        observed.truth.len()
    );
    if let Ok(status) = &status {
        for s in &status.sensors {
            println!(
                "sensor {} ({}): alive {} received {} processed {} late {} invalid {} lost {}",
                s.sensor,
                s.kind.name(),
                s.alive,
                s.received,
                s.processed,
                s.late,
                s.invalid,
                s.lost
            );
        }
    }
    match mean_ospa(&scores, began + skip) {
        Some((ospa, n)) => {
            println!("mean OSPA {ospa:.3} m over {n} track sets (c = 1 m, p = 1)");
            Ok(match max_ospa {
                Some(max) if ospa > max => {
                    println!("FAIL: mean OSPA {ospa:.3} m exceeds {max} m");
                    1
                }
                _ => 0,
            })
        }
        None => {
            println!("FAIL: no track set could be scored (no tracks or no truth)");
            Ok(1)
        }
    }
}

/// For each true object, the track ids seen within 0.5 m of it, with how often.
fn identities(observed: &checker::Observed) -> BTreeMap<u64, BTreeMap<u64, usize>> {
    let mut ids: BTreeMap<u64, BTreeMap<u64, usize>> = BTreeMap::new();
    for set in &observed.tracks {
        let Some((_, truth)) = observed.truth.iter().min_by(|a, b| {
            (a.1.stamp - set.stamp)
                .abs()
                .total_cmp(&(b.1.stamp - set.stamp).abs())
        }) else {
            continue;
        };
        if (truth.stamp - set.stamp).abs() > 0.05 {
            continue;
        }
        let mut used = BTreeSet::new();
        for object in &truth.objects {
            let nearest = set
                .tracks
                .iter()
                .filter(|t| !used.contains(&t.id))
                .map(|t| {
                    let d: f64 = (0..3)
                        .map(|i| (t.position[i] - object.position[i]).powi(2))
                        .sum();
                    (d.sqrt(), t.id)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((_, id)) = nearest.filter(|(d, _)| *d < 0.5) {
                used.insert(id);
                *ids.entry(object.id).or_default().entry(id).or_default() += 1;
            }
        }
    }
    ids
}
