//! `fusion-server`: the fusion service (`run`) and its offline twin (`replay`).

use std::fs::File;
use std::io::{BufReader, BufWriter};
use std::path::PathBuf;

use anyhow::Context;
use clap::{Parser, Subcommand};
use fusion_server::config::ServerConfig;
use fusion_server::{replay, service};
use tracing_subscriber::EnvFilter;

/// The filter allocates a mean and a covariance per updated component; mimalloc (through
/// `small-alloc`'s plain entry points) serves those small blocks much faster than glibc's
/// malloc (BENCHMARKS.md).
#[global_allocator]
static ALLOCATOR: small_alloc::SmallAlloc = small_alloc::SmallAlloc;

/// Multi-sensor multi-object tracking: asynchronous sequential GM-PHD fusion over Zenoh.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the service: subscribe to the site's sensors, publish and serve tracks.
    Run {
        /// TOML configuration (see fusion-server/fusion.example.toml); FUSION__SECTION__KEY
        /// environment variables override it.
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Run the same pipeline offline over a replay file; prints OSPA/GOSPA when the file has truth.
    Replay {
        /// TOML configuration.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Replay file (JSON Lines of descriptors, measurement sets and truth).
        #[arg(long)]
        input: PathBuf,
        /// Output file: one TrackSet JSON line per processed set.
        #[arg(long)]
        output: PathBuf,
        /// Draw tracks over truth and the OSPA curve into this SVG file.
        #[arg(long)]
        plot: Option<PathBuf>,
    },
}

fn init_logging(level: &str) {
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(level));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .init();
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Run { config } => {
            let config = ServerConfig::load(config.as_deref())?;
            init_logging(&config.log.level);
            let runtime = tokio::runtime::Builder::new_multi_thread()
                .enable_all()
                .build()?;
            runtime.block_on(service::run(config))
        }
        Command::Replay {
            config,
            input,
            output,
            plot: plot_path,
        } => {
            let config = ServerConfig::load(config.as_deref())?;
            init_logging(&config.log.level);
            let reader = BufReader::new(
                File::open(&input).with_context(|| format!("opening {}", input.display()))?,
            );
            let writer = BufWriter::new(
                File::create(&output).with_context(|| format!("creating {}", output.display()))?,
            );
            let report = replay::replay(config, reader, writer)?;
            println!(
                "replay: {} input lines ({} skipped), {} track sets written to {}",
                report.lines,
                report.bad_lines,
                report.outputs,
                output.display()
            );
            match (report.mean_ospa(), report.mean_gospa()) {
                (Some(ospa), Some(gospa)) => println!(
                    "accuracy over {} scored track sets: mean OSPA {ospa:.4} m, mean GOSPA {gospa:.4} m (c = 1 m, p = 1)",
                    report.scores.len()
                ),
                _ => println!("no truth in the input: accuracy not computed"),
            }
            if let Some(path) = plot_path {
                evaluation::plot(
                    evaluation::PlotData {
                        tracks: &report.tracks,
                        truth: &report.truth,
                        scores: &report.scores,
                    },
                    &path,
                )?;
                println!("plot written to {}", path.display());
            }
            Ok(())
        }
    }
}
