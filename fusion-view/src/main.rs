//! `fusion-view`: serves a live page of the tracks and sensors of every site it can reach.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use clap::Parser;
use fusion_view::{http, inputs, state::Sites};
use transport::ZenohConfig;

/// A browser view of the fusion service's tracks and sensors, live.
#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// Address of the HTTP server (the page is at http://ADDR:PORT/).
    #[arg(long, default_value = "127.0.0.1:8080")]
    http: SocketAddr,
    /// Zenoh mode of this client: `peer` or `client` (a client needs a router in `--connect`).
    #[arg(long, default_value = "peer")]
    mode: String,
    /// Router or peer endpoint to connect to (repeatable, or comma-separated).
    #[arg(long, env = "VIEW_CONNECT", value_delimiter = ',')]
    connect: Vec<String>,
    /// Zenoh JSON5 configuration file (TLS, credentials); the flags above apply on top of it.
    #[arg(long)]
    zenoh_config: Option<PathBuf>,
    /// Seconds of trail drawn behind each track.
    #[arg(long, default_value_t = 10.0)]
    trail_s: f64,
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() -> anyhow::Result<()> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| "info,zenoh=warn".into()),
        )
        .init();
    let args = Args::parse();
    anyhow::ensure!(
        args.trail_s.is_finite() && args.trail_s > 0.0,
        "--trail-s {}: must be a positive number of seconds",
        args.trail_s
    );
    let zenoh = ZenohConfig {
        mode: args.mode,
        connect: args.connect,
        config_file: args.zenoh_config,
        ..ZenohConfig::default()
    };
    if let Err((key, reason)) = zenoh.validate() {
        anyhow::bail!("zenoh {key}: {reason}");
    }
    let session = zenoh.open().await?;
    let sites = Arc::new(Mutex::new(Sites::new(args.trail_s)));
    let _inputs = inputs::start(&session, sites.clone()).await?;

    let listener = tokio::net::TcpListener::bind(args.http)
        .await
        .map_err(|e| anyhow::anyhow!("listening on {}: {e}", args.http))?;
    let address = listener.local_addr()?;
    tracing::info!(zid = %session.zid(), "fusion-view on http://{address}/");
    println!("fusion-view: http://{address}/");
    axum::serve(listener, http::router(sites))
        .with_graceful_shutdown(async {
            let _ = tokio::signal::ctrl_c().await;
        })
        .await?;
    Ok(())
}
