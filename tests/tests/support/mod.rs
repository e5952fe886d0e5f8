//! A deployment on loopback for integration tests: a Zenoh router inside the test process (so
//! that the server can restart while the agents stay connected), the real `fusion-server` and
//! `edge-agent` binaries as clients, and the test's own session to watch and query.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use checker::processes::{binary, free_port, Managed};

pub mod browser;

/// The router endpoint and the test's session on it.
pub struct Hub {
    /// `tcp/127.0.0.1:<port>`.
    pub endpoint: String,
    /// The router session (also used to watch and query).
    pub session: zenoh::Session,
}

impl Hub {
    /// Opens a router session listening on a free loopback port, scouting off.
    pub async fn start() -> anyhow::Result<Self> {
        Self::start_at(format!("tcp/127.0.0.1:{}", free_port()?)).await
    }

    /// Opens a router session listening on `endpoint`, scouting off.
    pub async fn start_at(endpoint: String) -> anyhow::Result<Self> {
        let mut config = zenoh::Config::default();
        let set = |config: &mut zenoh::Config, key: &str, value: &str| {
            config
                .insert_json5(key, value)
                .map_err(|e| anyhow::anyhow!("{key}: {e}"))
        };
        set(&mut config, "mode", r#""router""#)?;
        set(
            &mut config,
            "listen/endpoints",
            &format!(r#"["{endpoint}"]"#),
        )?;
        set(&mut config, "scouting/multicast/enabled", "false")?;
        let session = zenoh::open(config)
            .await
            .map_err(|e| anyhow::anyhow!("opening the router session: {e}"))?;
        Ok(Self { endpoint, session })
    }
}

/// Starts `fusion-server run` as a Zenoh client of `endpoint`, with extra `FUSION__…` variables.
pub fn start_server(endpoint: &str, log: &Path, env: &[(&str, String)]) -> anyhow::Result<Managed> {
    let mut cmd = Command::new(binary("fusion-server")?);
    cmd.arg("run")
        .env("FUSION__ZENOH__MODE", "client")
        .env("FUSION__ZENOH__CONNECT", endpoint)
        .env("FUSION__ZENOH__LISTEN", "")
        .env("FUSION__LOG__LEVEL", "info,zenoh=warn");
    for (key, value) in env {
        cmd.env(key, value);
    }
    Managed::spawn("fusion-server", cmd, Some(log))
}

/// Starts `edge-agent sim` for every sensor of the default room (with truth) as a client.
pub fn start_agents(
    endpoint: &str,
    log: &Path,
    start: f64,
    duration: f64,
    seed: u64,
) -> anyhow::Result<Managed> {
    let mut cmd = Command::new(binary("edge-agent")?);
    cmd.args(["sim", "--mode", "client", "--connect", endpoint, "--truth"])
        .args(["--start", &format!("{start:.6}")])
        .args(["--duration", &duration.to_string()])
        .args(["--seed", &seed.to_string()]);
    Managed::spawn("edge-agent sim", cmd, Some(log))
}

/// Wall clock, seconds since the epoch.
pub fn now() -> f64 {
    fusion_server::clock::now()
}

/// Sleeps without blocking the runtime.
pub async fn sleep(seconds: f64) {
    tokio::time::sleep(Duration::from_secs_f64(seconds)).await;
}

/// A scratch directory for logs and checkpoints, kept on failure for inspection.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fusion-it-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Starts `fusion-view` as a Zenoh client of `endpoint`, serving HTTP on `http` (`ADDR:PORT`).
pub fn start_view(endpoint: &str, http: &str, log: &Path) -> anyhow::Result<Managed> {
    let mut cmd = Command::new(binary("fusion-view")?);
    cmd.args(["--mode", "client", "--connect", endpoint, "--http", http])
        .env("RUST_LOG", "info,zenoh=warn");
    Managed::spawn("fusion-view", cmd, Some(log))
}

/// Starts `edge-agent sim` for the given sensors of the default room only.
pub fn start_sensors(
    endpoint: &str,
    log: &Path,
    sensors: &[&str],
    truth: bool,
    (start, duration, seed): (f64, f64, u64),
) -> anyhow::Result<Managed> {
    let mut cmd = Command::new(binary("edge-agent")?);
    cmd.args(["sim", "--mode", "client", "--connect", endpoint])
        .args(["--start", &format!("{start:.6}")])
        .args(["--duration", &duration.to_string()])
        .args(["--seed", &seed.to_string()]);
    for sensor in sensors {
        cmd.args(["--sensor", sensor]);
    }
    if truth {
        cmd.arg("--truth");
    }
    Managed::spawn(
        &format!("edge-agent sim {}", sensors.join(",")),
        cmd,
        Some(log),
    )
}
