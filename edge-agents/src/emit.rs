//! Where produced data goes: numbering each sensor's sets, checking them, and handing them to the replay
//! writer and/or the Zenoh publishers.

use std::time::Duration;

use protocol::{MeasurementSet, ReplayLine, SensorDescriptor, Site, TruthSet, WireFormat};
use transport::ZenohConfig;

use crate::descriptor::validate_descriptor;
use crate::descriptor_calibration::{CalibrationMode, DescriptorCalibration};
use crate::error::AgentError;
use crate::front_end_report::FrontEndReport;
use crate::output::ReplayWriter;
use crate::publish::{await_subscribers, Publishing, SensorPublisher, TruthPublisher};
use transport::LogLimiter;
use transport::Shutdown;

/// How long a publishing agent waits at start for subscribers to its sets (see `await_subscribers`).
const SUBSCRIBER_PATIENCE: Duration = Duration::from_secs(2);

/// One frame's measurements as a source produces them; the emitter adds sensor name, version and `seq`.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Capture time, seconds since the Unix epoch.
    pub stamp: f64,
    /// One vector per measurement, of the sensor kind's length.
    pub measurements: Vec<Vec<f64>>,
    /// `None`, or one covariance (rows) per measurement replacing the descriptor's noise.
    pub covariances: Option<Vec<Vec<Vec<f64>>>>,
}

/// Where a run's output goes: a replay file, Zenoh, or both.
pub struct OutputPlan {
    /// The replay writer of `--output`.
    pub replay: Option<ReplayWriter>,
    /// The Zenoh settings and payload form, when publishing.
    pub zenoh: Option<(ZenohConfig, WireFormat)>,
    /// Whether (and how) the descriptors are refined from the sets emitted: front ends, not simulations.
    pub calibration: Option<CalibrationMode>,
}

/// How many sets one sensor produced.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorCount {
    /// The sensor.
    pub sensor: String,
    /// Sets emitted (written and/or published).
    pub sets: u64,
    /// Sets that failed validation and were dropped (each leaves a `seq` gap).
    pub invalid: u64,
}

/// Numbers, checks and delivers the sets of one or more sensors (and truth sets).
pub struct Emitter {
    streams: Vec<Stream>,
    replay: Option<ReplayWriter>,
    publishing: Option<Publishing>,
    truth: Option<TruthPublisher>,
    truth_sets: u64,
    invalid_log: LogLimiter,
}

/// One sensor's numbering and publisher.
struct Stream {
    descriptor: SensorDescriptor,
    calibration: Option<DescriptorCalibration>,
    next_seq: u64,
    publisher: Option<SensorPublisher>,
    count: SensorCount,
}

impl Emitter {
    /// Validates every descriptor, opens Zenoh when publishing (declaring each sensor and, when `truth_site`
    /// is given, the truth publisher) and writes the descriptor lines to the replay output.
    /// A `live` source's sensors are declared with their first set instead, so that a liveliness token
    /// always means a sensor that produces (an agent waiting for its first packet is not yet alive).
    /// Returns `None` when shutdown was requested while waiting for the Zenoh router.
    pub async fn start(
        descriptors: Vec<SensorDescriptor>,
        truth_site: Option<&Site>,
        plan: OutputPlan,
        shutdown: &Shutdown,
        live: bool,
    ) -> Result<Option<Self>, AgentError> {
        for descriptor in &descriptors {
            validate_descriptor(descriptor)?;
        }
        let OutputPlan {
            mut replay,
            zenoh,
            calibration,
        } = plan;
        let publishing = match zenoh {
            Some((config, format)) => match Publishing::open(&config, format, shutdown).await? {
                Some(publishing) => Some(publishing),
                None => return Ok(None),
            },
            None => None,
        };
        let mut streams = Vec::with_capacity(descriptors.len());
        for descriptor in descriptors {
            let publisher = match &publishing {
                Some(publishing) if !live => Some(publishing.sensor(&descriptor).await?),
                _ => None,
            };
            if let Some(replay) = &mut replay {
                replay.write(&ReplayLine::Descriptor(descriptor.clone()))?;
            }
            streams.push(Stream {
                count: SensorCount {
                    sensor: descriptor.sensor.to_string(),
                    sets: 0,
                    invalid: 0,
                },
                calibration: calibration
                    .and_then(|mode| DescriptorCalibration::new(&descriptor, mode)),
                descriptor,
                next_seq: 0,
                publisher,
            });
        }
        let publishers: Vec<&SensorPublisher> = streams
            .iter()
            .filter_map(|s| s.publisher.as_ref())
            .collect();
        if !publishers.is_empty() && !await_subscribers(&publishers, SUBSCRIBER_PATIENCE).await {
            tracing::info!(
                "no subscriber yet for every sensor (is the fusion server up?); publishing anyway"
            );
        }
        let truth = match (&publishing, truth_site) {
            (Some(publishing), Some(site)) => Some(publishing.truth(site).await?),
            _ => None,
        };
        Ok(Some(Self {
            streams,
            replay,
            publishing,
            truth,
            truth_sets: 0,
            invalid_log: LogLimiter::new(Duration::from_secs(5)),
        }))
    }

    /// Emits the next set of sensor `stream` (its index in the descriptors given to [`Emitter::start`]).
    ///
    /// The set gets the sensor's next `seq`. A set that fails validation against the descriptor is logged and
    /// dropped, its `seq` consumed, so that the gap tells the server a set was lost. Only a failure to write
    /// the replay output is an error; publishing failures are logged inside the publisher.
    pub async fn emit_set(&mut self, stream: usize, frame: Frame) -> Result<(), AgentError> {
        let Some(entry) = self.streams.get_mut(stream) else {
            return Err(AgentError::Usage(format!("no sensor stream #{stream}")));
        };
        let set = MeasurementSet {
            version: protocol::PROTOCOL_VERSION,
            sensor: entry.descriptor.sensor.clone(),
            seq: entry.next_seq,
            stamp: frame.stamp,
            measurements: frame.measurements,
            covariances: frame.covariances,
        };
        entry.next_seq += 1;
        if let Err(error) = set.validate_against(&entry.descriptor) {
            entry.count.invalid += 1;
            if let Some(suppressed) = self.invalid_log.allow("invalid set") {
                tracing::error!(sensor = %set.sensor, seq = set.seq, %error, suppressed, "dropping an invalid set");
            }
            return Ok(());
        }
        if let (None, Some(publishing)) = (&entry.publisher, &self.publishing) {
            // Not declared yet (a live source) or withdrawn while its source was down: back with this set.
            entry.publisher = Some(publishing.sensor(&entry.descriptor).await?);
        }
        if let Some(publisher) = &mut entry.publisher {
            publisher.put_set(&set).await;
        }
        entry.count.sets += 1;
        let refined = entry
            .calibration
            .as_mut()
            .and_then(|c| c.observe(set.stamp, &set.measurements));
        if let Some(replay) = &mut self.replay {
            replay.write(&ReplayLine::Measurements(set))?;
        }
        if let Some(descriptor) = refined {
            self.announce(stream, descriptor)?;
        }
        Ok(())
    }

    /// Takes the front end's own report of sensor `stream`'s last set (`front_end_report.rs`): the
    /// descriptor is calibrated from these, and announced anew when it drifted.
    pub fn take_report(
        &mut self,
        stream: usize,
        stamp: f64,
        report: FrontEndReport,
    ) -> Result<(), AgentError> {
        let Some(entry) = self.streams.get_mut(stream) else {
            return Err(AgentError::Usage(format!("no sensor stream #{stream}")));
        };
        let refined = entry
            .calibration
            .as_mut()
            .and_then(|c| c.observe_report(stamp, report));
        if let Some(descriptor) = refined {
            self.announce(stream, descriptor)?;
        }
        Ok(())
    }

    /// Announces sensor `stream`'s refined descriptor: the next sets are validated against it, the replay
    /// output gets a descriptor line before them and the publisher puts it and answers queries with it.
    fn announce(&mut self, stream: usize, descriptor: SensorDescriptor) -> Result<(), AgentError> {
        validate_descriptor(&descriptor)?;
        let entry = &mut self.streams[stream];
        if let Some(publisher) = &mut entry.publisher {
            publisher.update_descriptor(&descriptor)?;
        }
        if let Some(replay) = &mut self.replay {
            replay.write(&ReplayLine::Descriptor(descriptor.clone()))?;
        }
        entry.descriptor = descriptor;
        Ok(())
    }

    /// Withdraws sensor `stream` from Zenoh while its source is down: its publisher, queryable and liveliness
    /// token are undeclared, so the server sees it leave; its next set declares them again.
    pub fn withdraw(&mut self, stream: usize) {
        let Some(entry) = self.streams.get_mut(stream) else {
            return;
        };
        if entry.publisher.take().is_some() {
            tracing::info!(sensor = %entry.descriptor.sensor, "source down: sensor withdrawn until it is back");
        }
    }

    /// Emits one truth set (published on `fusion/<site>/truth` and/or written as a `truth` line).
    pub async fn emit_truth(&mut self, truth: TruthSet) -> Result<(), AgentError> {
        if let Err(error) = truth.validate() {
            tracing::error!(stamp = truth.stamp, %error, "dropping an invalid truth set");
            return Ok(());
        }
        if let Some(publisher) = &mut self.truth {
            publisher.put_truth(&truth).await;
        }
        self.truth_sets += 1;
        if let Some(replay) = &mut self.replay {
            replay.write(&ReplayLine::Truth(truth))?;
        }
        Ok(())
    }

    /// Flushes the replay output, withdraws every sensor and closes the session; returns the counts.
    pub async fn finish(mut self) -> Result<(Vec<SensorCount>, u64), AgentError> {
        let counts = self.streams.iter().map(|s| s.count.clone()).collect();
        let replay_result = match &mut self.replay {
            Some(replay) => replay.finish().inspect(|()| {
                tracing::info!(
                    lines = replay.lines(),
                    target = replay.target(),
                    "replay output written"
                );
            }),
            None => Ok(()),
        };
        // Publishers and tokens go before the session closes, so they are undeclared cleanly.
        self.streams.clear();
        self.truth = None;
        if let Some(publishing) = self.publishing.take() {
            publishing.close().await;
        }
        replay_result?;
        Ok((counts, self.truth_sets))
    }
}
