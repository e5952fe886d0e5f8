//! `fusion-router`: a Zenoh router for the deployment (docker/README.md).
//!
//! A Zenoh session opened in `router` mode routes between clients and peers exactly as `zenohd`
//! does, with the same JSON5 configuration: listen and connect endpoints, TLS with client
//! certificates, the user/password dictionary, access control. Built from the workspace's zenoh, it
//! needs no second, separately pinned zenoh build; `zenohd`'s plugins (REST, storages) are the only
//! thing it lacks, and the deployment uses none.

use std::path::PathBuf;

use clap::Parser;

/// A Zenoh router: routes the fusion service's keys between its agents, servers and clients.
#[derive(Parser)]
#[command(name = "fusion-router", version, about)]
struct Args {
    /// Zenoh JSON5 configuration file (listen endpoints, TLS, credentials, access control); its
    /// `mode` is always taken as `router`.
    #[arg(long, short)]
    config: Option<PathBuf>,
    /// Endpoints to listen on, instead of the file's (repeatable, or comma-separated).
    #[arg(long, value_delimiter = ',')]
    listen: Vec<String>,
    /// Routers to connect to, instead of the file's (repeatable, or comma-separated).
    #[arg(long, value_delimiter = ',')]
    connect: Vec<String>,
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
    let config = router_config(&args)?;
    let listen = config
        .get_json("listen/endpoints")
        .unwrap_or_else(|_| "Zenoh's default".into());
    let session = zenoh::open(config)
        .await
        .map_err(|e| anyhow::anyhow!("starting the router: {e}"))?;
    tracing::info!(zid = %session.zid(), %listen, "router up");
    // As PID 1 in a container a process gets no default signal handling: this is what stops it.
    transport::wait_for_signal().await;
    tracing::info!("router stopping");
    session
        .close()
        .await
        .map_err(|e| anyhow::anyhow!("closing the router: {e}"))?;
    Ok(())
}

/// The Zenoh configuration: the file's (or Zenoh's defaults), in router mode, with the flags' endpoints.
fn router_config(args: &Args) -> anyhow::Result<zenoh::Config> {
    let mut config = match &args.config {
        Some(path) => zenoh::Config::from_file(path)
            .map_err(|e| anyhow::anyhow!("zenoh configuration file {}: {e}", path.display()))?,
        None => zenoh::Config::default(),
    };
    let mut set = |key: &str, value: String| {
        config
            .insert_json5(key, &value)
            .map_err(|e| anyhow::anyhow!("zenoh configuration `{key}` = {value}: {e}"))
    };
    set("mode", r#""router""#.into())?;
    for (key, extra) in [
        ("listen/endpoints", &args.listen),
        ("connect/endpoints", &args.connect),
    ] {
        if !extra.is_empty() {
            let quoted: Vec<String> = extra.iter().map(|e| format!("{e:?}")).collect();
            set(key, format!("[{}]", quoted.join(",")))?;
        }
    }
    Ok(config)
}
