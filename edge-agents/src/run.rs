//! The run loop shared by every subcommand: pull the next frame from a source, wait until it is due, emit it.

use protocol::{SensorDescriptor, Site, TruthSet};

use crate::emit::{Emitter, Frame, OutputPlan};
use crate::error::AgentError;
use crate::front_end_report::FrontEndReport;
use crate::pacing::Pacer;
use transport::Shutdown;

/// One thing a source produces, in stamp order.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A frame of the sensor with index `stream` in the run's descriptors.
    Set {
        /// Index of the sensor in [`RunPlan::descriptors`].
        stream: usize,
        /// Its measurements.
        frame: Frame,
    },
    /// A truth set (simulations only).
    Truth(TruthSet),
    /// The front end's own account of the set it just produced for sensor `stream`
    /// (`front_end_report.rs`), for the descriptor's calibration.
    Report {
        /// Index of the sensor in [`RunPlan::descriptors`].
        stream: usize,
        /// The stamp of the set it is about.
        stamp: f64,
        /// The account.
        report: FrontEndReport,
    },
    /// The live source of sensor `stream` is down (a network camera being re-opened): the sensor is
    /// withdrawn from Zenoh (its liveliness token undeclared) until its next set declares it again.
    SourceDown {
        /// Index of the sensor in [`RunPlan::descriptors`].
        stream: usize,
        /// When the source went down.
        stamp: f64,
    },
}

impl Event {
    /// The event's capture time.
    pub fn stamp(&self) -> f64 {
        match self {
            Event::Set { frame, .. } => frame.stamp,
            Event::Truth(truth) => truth.stamp,
            Event::SourceDown { stamp, .. } | Event::Report { stamp, .. } => *stamp,
        }
    }
}

/// Produces a run's events one at a time, in non-decreasing stamp order.
pub trait EventSource {
    /// The next event, `None` at the end of the data. May take a while (decoding a frame, a filter update):
    /// the run loop calls it outside the async executor's reach.
    fn next_event(&mut self) -> Result<Option<Event>, AgentError>;

    /// True when events come as the sensor captures them (stamped on arrival), not from recorded data:
    /// replay lines are then flushed one by one, as when publishing.
    fn is_live(&self) -> bool {
        false
    }

    /// Gives a live source the run's shutdown flag, so that a wait for data that may never come (a silent
    /// socket) can end on Ctrl-C.
    fn attach_shutdown(&mut self, _shutdown: &Shutdown) {}
}

/// Everything a run needs besides its source.
pub struct RunPlan {
    /// The sensors, in the order the source's `stream` indices refer to.
    pub descriptors: Vec<SensorDescriptor>,
    /// Publish truth on this site's truth key (simulations with `--truth`).
    pub truth_site: Option<Site>,
    /// Replay file and/or Zenoh.
    pub output: OutputPlan,
    /// `None`: as fast as possible (`--output` alone); otherwise frames wait until they are due.
    pub pacer: Option<Pacer>,
}

/// Runs `source` to its end (or until shutdown), emitting every event as `plan` says.
pub async fn run(
    source: &mut dyn EventSource,
    plan: RunPlan,
    shutdown: Shutdown,
) -> Result<(), AgentError> {
    let RunPlan {
        descriptors,
        truth_site,
        output,
        pacer,
    } = plan;
    let Some(mut emitter) = Emitter::start(
        descriptors,
        truth_site.as_ref(),
        output,
        &shutdown,
        source.is_live(),
    )
    .await?
    else {
        return Ok(());
    };
    source.attach_shutdown(&shutdown);
    let result = pump(source, &mut emitter, pacer, shutdown).await;
    let (counts, truth_sets) = emitter.finish().await?;
    for count in &counts {
        tracing::info!(sensor = %count.sensor, sets = count.sets, invalid = count.invalid, "sensor done");
    }
    if truth_sets > 0 {
        tracing::info!(truth_sets, "truth done");
    }
    result
}

/// The loop proper; returns at the end of the data, on shutdown, or on the first error.
async fn pump(
    source: &mut dyn EventSource,
    emitter: &mut Emitter,
    pacer: Option<Pacer>,
    mut shutdown: Shutdown,
) -> Result<(), AgentError> {
    loop {
        if shutdown.is_requested() {
            return Ok(());
        }
        // Computing a frame may be heavy (image decoding, a filter update): keep it off the executor's
        // worker so Zenoh's tasks and the descriptor refresh keep running meanwhile.
        let Some(event) = tokio::task::block_in_place(|| source.next_event())? else {
            return Ok(());
        };
        if let Some(pacer) = &pacer {
            tokio::select! {
                _ = pacer.wait_for(event.stamp()) => {}
                _ = shutdown.requested() => return Ok(()),
            }
        }
        match event {
            Event::Set { stream, frame } => emitter.emit_set(stream, frame).await?,
            Event::Truth(truth) => emitter.emit_truth(truth).await?,
            Event::SourceDown { stream, .. } => emitter.withdraw(stream),
            Event::Report {
                stream,
                stamp,
                report,
            } => emitter.take_report(stream, stamp, report)?,
        }
    }
}
