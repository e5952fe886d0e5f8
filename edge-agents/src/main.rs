//! `edge-agent`: one sensor (or a simulation of several) on the fusion service's wire.
//!
//! Each subcommand turns its input into a source of frames ([`run::EventSource`]); [`launch::launch`] then
//! publishes them over Zenoh (descriptor, liveliness token, one `MeasurementSet` per frame) and/or writes them
//! as replay lines. See README.md for every subcommand with an example.

mod calibration;
mod camera;
mod camera_frontend;
mod camera_input;
mod camera_tracker;
mod capture_clock;
mod cli;
mod descriptor;
mod descriptor_calibration;
mod drop_report;
mod emit;
mod error;
mod ffmpeg;
mod front_end_report;
mod launch;
mod lidar;
mod lidar_live;
mod live_detections;
mod mic;
mod mic_stream;
mod output;
mod pacing;
mod publish;
mod run;
mod scan_follow;
mod settings;
mod sim;
#[cfg(feature = "sound-card")]
mod sound_card;
mod start_file;
mod tdoa_noise;
mod velodyne_input;
mod video_input;
mod video_reader;

use std::process::ExitCode;

use clap::Parser;
use tracing_subscriber::EnvFilter;

use crate::cli::{Cli, Command, CommonArgs, TimingArgs};
use crate::error::AgentError;
use crate::launch::{launch, Prepared};
use crate::settings::AgentSettings;

/// Runs one subcommand; exit code 0 on success (or a closed output pipe), 1 with a message on stderr otherwise.
fn main() -> ExitCode {
    let cli = Cli::parse();
    match run_command(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if error.is_broken_pipe() => ExitCode::SUCCESS,
        Err(error) => {
            // Logging may not be set up yet (a bad --config), so the final word goes straight to stderr.
            eprintln!("edge-agent: error: {error}");
            ExitCode::FAILURE
        }
    }
}

/// Resolves settings, prepares the subcommand's source (reading and checking every input before anything
/// goes on the wire) and runs it.
fn run_command(mut command: Command) -> Result<(), AgentError> {
    let settings = AgentSettings::resolve(shared_args(&command).0)?;
    init_logging(&settings.log.level);
    let timing = timing_mut(&mut command);
    if let Some(path) = &timing.start_file {
        // Before the input is read: the file is written once the input is complete.
        timing.start = Some(start_file::wait_for_start(path)?);
    }
    let (common, timing) = shared_args(&command);
    let prepared: Prepared = match &command {
        Command::Sim(c) => sim::prepare_sim(c)?,
        Command::Camera(c) => camera::prepare_camera(c)?,
        Command::MicPair(c) => mic::prepare_mic_pair(c)?,
        Command::Lidar(c) => lidar::prepare_lidar(c)?,
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(AgentError::Runtime)?;
    runtime.block_on(launch(prepared, common, &settings, timing.speed))
}

/// The flags every subcommand shares.
fn shared_args(command: &Command) -> (&CommonArgs, &TimingArgs) {
    match command {
        Command::Sim(c) => (&c.common, &c.timing),
        Command::Camera(c) => (&c.common, &c.timing),
        Command::MicPair(c) => (&c.common, &c.timing),
        Command::Lidar(c) => (&c.common, &c.timing),
    }
}

/// The stamping flags of any subcommand, to fill in `--start` from `--start-file`.
fn timing_mut(command: &mut Command) -> &mut TimingArgs {
    match command {
        Command::Sim(c) => &mut c.timing,
        Command::Camera(c) => &mut c.timing,
        Command::MicPair(c) => &mut c.timing,
        Command::Lidar(c) => &mut c.timing,
    }
}

/// Tracing to stderr (stdout may carry replay lines); `RUST_LOG` overrides the configured level.
fn init_logging(level: &str) {
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(level));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .init();
}
