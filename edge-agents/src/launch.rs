//! From a subcommand's prepared source to a running agent: where output goes (`--output`, `--publish`,
//! `--json`), whether frames are paced, and the run itself.

use protocol::{SensorDescriptor, Site, WireFormat};

use crate::cli::CommonArgs;
use crate::descriptor_calibration::CalibrationMode;
use crate::emit::OutputPlan;
use crate::error::AgentError;
use crate::output::ReplayWriter;
use crate::pacing::{check_speed, wall_clock, Pacer};
use crate::run::{run, EventSource, RunPlan};
use crate::settings::AgentSettings;
use transport::Shutdown;

/// A subcommand's work, ready to run: its source of frames and the sensors they belong to.
pub struct Prepared {
    /// The frames (and truth sets), in stamp order.
    pub source: Box<dyn EventSource>,
    /// The sensors, indexed by the source's `stream`.
    pub descriptors: Vec<SensorDescriptor>,
    /// Publish truth on this site (`sim --truth`).
    pub truth_site: Option<Site>,
    /// The stamp of the run's time 0 (`--start`, the scenario's start, or the launch time).
    pub origin_stamp: f64,
    /// The wall time at which `origin_stamp` is due: the same value for simulations and sources stamped from
    /// `--start` (so processes agree), the launch time for recorded stamps replayed at their own pace.
    pub origin_wall: f64,
    /// Whether the sets come from a real front end, whose descriptor is refined from what it emits
    /// (`descriptor_calibration.rs`); simulated sensors match their descriptors by construction.
    pub calibrate: bool,
    /// Whether a refined descriptor is announced (`false`: the drift is only logged, as with
    /// `--keep-descriptor`).
    pub announce_calibration: bool,
}

impl Prepared {
    /// A run of one front end's sensor, without truth, its descriptor refined as it runs.
    pub fn single_sensor(
        source: Box<dyn EventSource>,
        descriptor: SensorDescriptor,
        origin_stamp: f64,
        origin_wall: f64,
    ) -> Self {
        Self {
            source,
            descriptors: vec![descriptor],
            truth_site: None,
            origin_stamp,
            origin_wall,
            calibrate: true,
            announce_calibration: true,
        }
    }
}

/// Runs `prepared` with the output flags of `common`, the Zenoh settings already resolved and `speed`.
pub async fn launch(
    prepared: Prepared,
    common: &CommonArgs,
    settings: &AgentSettings,
    speed: f64,
) -> Result<(), AgentError> {
    check_speed(speed)?;
    let publishing = common.output.is_none() || common.publish;
    let replay = match &common.output {
        // Live runs flush each line so a reader sees a set as soon as it is published (or captured).
        Some(path) => Some(ReplayWriter::create(
            path,
            publishing || prepared.source.is_live(),
        )?),
        None => None,
    };
    let format = if common.json {
        WireFormat::Json
    } else {
        WireFormat::Postcard
    };
    let pacer = if publishing {
        let pacer = Pacer::new(prepared.origin_stamp, prepared.origin_wall, speed)?;
        let late = wall_clock() - pacer.due(prepared.origin_stamp);
        if late > 1.0 {
            tracing::warn!(
                late_s = late,
                "the run started {late:.1} s ago (--start or the scenario's start): frames already due are published at once"
            );
        }
        Some(pacer)
    } else {
        None
    };
    let plan = RunPlan {
        descriptors: prepared.descriptors,
        truth_site: prepared.truth_site,
        output: OutputPlan {
            replay,
            zenoh: publishing.then(|| (settings.zenoh.clone(), format)),
            calibration: prepared.calibrate.then_some(
                if common.keep_descriptor || !prepared.announce_calibration {
                    CalibrationMode::LogOnly
                } else {
                    CalibrationMode::Update
                },
            ),
        },
        pacer,
    };
    let mut source = prepared.source;
    run(source.as_mut(), plan, Shutdown::listen()).await
}
