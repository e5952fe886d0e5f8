//! `fusion-checker render`: the simulator of the compose raw profile (`docker/docker-compose.raw.yml`).
//!
//! It renders every sensor's raw signal of the default room into a shared directory, then tells the
//! agents waiting beside it when scenario time 0 is (one `<sensor>.start` file each, written last, read
//! by `edge-agent … --start-file`), and publishes the truth in real time while they run their real front
//! ends on the files, so that the tracks can be scored.

use std::path::PathBuf;

use protocol::Site;

use crate::raw_inputs::{publish_truth_on, render_sensors};

/// What to render and when to start.
#[derive(Debug, Clone)]
pub struct RenderRun {
    /// The directory the agents read (emptied first).
    pub out: PathBuf,
    /// The deployment's site.
    pub site: Site,
    /// Seed of the scenario's random streams.
    pub seed: u64,
    /// Seconds of scenario rendered and played.
    pub duration_s: f64,
    /// When scenario time 0 is.
    pub start: RunStart,
    /// Whether to publish the truth once the signals are written (else the run ends there).
    pub publish_truth: bool,
}

/// When scenario time 0 of a rendered run is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunStart {
    /// This many seconds after the rendering ended: the agents' time to read their inputs.
    AfterRendering {
        /// The seconds.
        lead_s: f64,
    },
    /// At this Unix time (s).
    At(f64),
}

/// Renders, writes the start files, then (unless told not to) publishes the truth on `session`
/// until the run's end.
pub async fn render_and_play(session: &zenoh::Session, run: RenderRun) -> anyhow::Result<()> {
    let start = render_for_agents(&run).await?;
    if !run.publish_truth {
        return Ok(());
    }
    let mut scenario = simulator::default_room();
    scenario.site = run.site.clone();
    publish_truth_on(session, &scenario, run.seed, start, run.duration_s).await
}

/// Renders every sensor's signal and writes the start files (no network): scenario time 0 as a Unix
/// time.
pub async fn render_for_agents(run: &RenderRun) -> anyhow::Result<f64> {
    anyhow::ensure!(
        run.duration_s.is_finite() && run.duration_s > 0.0,
        "--duration {}: must be a positive number of seconds",
        run.duration_s
    );
    match run.start {
        RunStart::AfterRendering { lead_s } => anyhow::ensure!(
            lead_s.is_finite() && lead_s >= 0.0,
            "--lead {lead_s}: must be a number of seconds, 0 or more"
        ),
        RunStart::At(start) => anyhow::ensure!(
            start.is_finite(),
            "--start {start}: must be a Unix time in seconds"
        ),
    }
    let mut scenario = simulator::default_room();
    scenario.site = run.site.clone();
    let sensors = {
        let (out, seed, duration_s) = (run.out.clone(), run.seed, run.duration_s);
        tokio::task::spawn_blocking(move || {
            render_sensors(&scenario, seed, duration_s, &out, "fusion-checker")
        })
        .await??
    };
    let start = match run.start {
        RunStart::AfterRendering { lead_s } => fusion_server::clock::now() + lead_s,
        RunStart::At(start) => start,
    };
    for sensor in &sensors {
        sensor
            .write_start_file(start)
            .map_err(|e| anyhow::anyhow!("writing {}: {e}", sensor.start_file().display()))?;
    }
    println!(
        "fusion-checker: {} sensors rendered into {}; scenario time 0 is Unix time {start:.3}{}",
        sensors.len(),
        run.out.display(),
        if run.publish_truth {
            ", the truth follows"
        } else {
            ""
        }
    );
    Ok(start)
}
