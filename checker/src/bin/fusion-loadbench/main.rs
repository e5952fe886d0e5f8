//! `fusion-loadbench`: the end-to-end benchmark of the service, as users see it.
//!
//! On the dense scenario (simulator::dense: 50 targets, 8 sensors at 30 Hz, 20 clutter per set):
//! 1. the engine alone on one core: CPU per set and the multiple of real time, in order and with
//!    two late sensors (one 0.4 s late, one late by a random 0–1 s), with rollbacks and memory;
//! 2. over Zenoh on loopback, the real `fusion-server` in its **default configuration**: latency
//!    from a set's put to the receipt of the first TrackSet that includes it, at the real-time
//!    rate, beside a bare Zenoh round trip of the same payloads measured in the same run; in
//!    order, then with the two late sensors (no set may be lost; the server's own arrival-to-put
//!    latency from its status); the server's peak memory;
//! 3. throughput over Zenoh: sets fed as fast as the server keeps up (at most `--window` in
//!    flight; the future-stamp and flood guards are relaxed for this phase only, since the feed
//!    is faster than real time by design);
//! 4. with `--scaling`, the cost and memory per set for 10–500 targets and 4–32 sensors.

mod echo;
mod heap;
mod offline;
mod rig;
mod zenoh_phases;

use clap::Parser;

use offline::{dense_config, engine_cost, Arrival};

#[global_allocator]
static ALLOCATOR: heap::Counting = heap::Counting;

/// End-to-end benchmark of fusion-server on the dense scenario.
#[derive(Parser)]
#[command(version, about)]
pub struct Args {
    /// Scenario seconds fed in the throughput phase.
    #[arg(long, default_value_t = 20.0)]
    pub throughput_seconds: f64,
    /// Scenario seconds fed in each latency phase (at real-time rate).
    #[arg(long, default_value_t = 10.0)]
    pub latency_seconds: f64,
    /// Scenario seconds of each offline run.
    #[arg(long, default_value_t = 20.0)]
    pub offline_seconds: f64,
    /// Sets in flight at most in the throughput phase.
    #[arg(long, default_value_t = 8)]
    pub window: usize,
    /// Maximum number of Gaussian components (J_max).
    #[arg(long, default_value_t = 1000)]
    pub max_components: usize,
    /// Also measure how the cost grows with targets and sensors.
    #[arg(long)]
    pub scaling: bool,
    /// Skip the Zenoh phases (offline figures only).
    #[arg(long)]
    pub offline_only: bool,
    /// Server log file.
    #[arg(long, default_value = "loadbench-server.log")]
    pub log: std::path::PathBuf,
}

fn offline_phase(args: &Args) -> anyhow::Result<()> {
    let config = dense_config(args.max_components);
    let scenario = simulator::dense();
    for arrival in [Arrival::InOrder, Arrival::Delayed] {
        let cost = engine_cost(&config, &scenario, args.offline_seconds, arrival)?;
        println!(
            "engine, one core, {arrival:?}: {} sets, {:.1} µs per set = {:.1} × real time; {} rollbacks ({:.2} per set), {} re-processed, {} late; peak heap {:.1} MiB; one snapshot {:.1} µs",
            cost.sets,
            cost.per_set_us(),
            cost.real_time_multiple(),
            cost.rollbacks,
            cost.rollbacks as f64 / cost.sets as f64,
            cost.reprocessed,
            cost.late,
            cost.peak_bytes as f64 / (1024.0 * 1024.0),
            cost.snapshot_us,
        );
    }
    Ok(())
}

fn scaling_phase(args: &Args) -> anyhow::Result<()> {
    println!("| targets | sensors | sets/s | µs per set (1 core) | × real time, 1 core | × real time, 2 threads | peak heap MiB |");
    println!("|---|---|---|---|---|---|---|");
    let seconds = 6.0;
    for targets in [10, 50, 200, 500] {
        for sensors in [4, 8, 16, 32] {
            let scenario = simulator::dense_scaled(targets, sensors);
            let config = dense_config(args.max_components.max(20 * targets as usize));
            let cost = engine_cost(&config, &scenario, seconds, Arrival::InOrder)?;
            let two = offline::engine_wall(&config, &scenario, seconds, 2)?;
            println!(
                "| {targets} | {sensors} | {:.0} | {:.1} | {:.1} | {:.1} | {:.1} |",
                cost.sets as f64 / seconds,
                cost.per_set_us(),
                cost.real_time_multiple(),
                seconds / two,
                cost.peak_bytes as f64 / (1024.0 * 1024.0),
            );
        }
    }
    Ok(())
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    offline_phase(&args)?;
    if args.scaling {
        scaling_phase(&args)?;
    }
    if !args.offline_only {
        zenoh_phases::latency(&args, Arrival::InOrder).await?;
        zenoh_phases::latency(&args, Arrival::Delayed).await?;
        zenoh_phases::throughput(&args).await?;
    }
    Ok(())
}
