//! `edge-agent lidar`: a directory of scans → ground removal, range-image segmentation, person-sized objects →
//! one set of object centres `[range, azimuth, elevation]` (sensor frame) per scan.
//!
//! Scans are `.pcd` or KITTI `.bin` files taken in file-name order, scan i stamped `start + i / rate`; live
//! scans come from Velodyne packets over UDP (`velodyne_input.rs`) or from a followed directory
//! (`scan_follow.rs`), stamped on arrival (`lidar_live.rs`).
//! Centres outside the descriptor's measurement region (beyond `max_range`, or outside `elevation_limits`)
//! are left out: the descriptor says the sensor does not see there, and the server's clutter density
//! assumes every measurement lies inside that region.

use std::path::{Path, PathBuf};

use frontends::lidar::{read_kitti_bin, read_pcd, LidarConfig, LidarPipeline, PointCloud};
use protocol::{LidarModel, SensorKind, SensorModel};

use crate::capture_clock::CaptureClock;
use crate::cli::LidarCommand;
use crate::descriptor::load_descriptor;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::launch::Prepared;
use crate::lidar_live::LiveLidar;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};
use crate::settings::read_frontend_config;
use crate::sim::prepare_simulated_sensor;
use crate::{scan_follow, velodyne_input};

/// Prepares `edge-agent lidar`.
pub fn prepare_lidar(command: &LidarCommand) -> Result<Prepared, AgentError> {
    if command.simulate.simulate {
        if command.scans.is_some() || command.velodyne.is_some() || command.descriptor.is_some() {
            return Err(AgentError::Usage(
                "--simulate takes the LIDAR from --scenario: do not give --scans, --velodyne or --descriptor"
                    .into(),
            ));
        }
        return prepare_simulated_sensor(
            &command.simulate,
            command.common.site.as_ref(),
            &command.timing,
            SensorKind::Lidar,
        );
    }
    let descriptor_path = command
        .descriptor
        .as_deref()
        .ok_or_else(|| AgentError::Usage("lidar needs --descriptor FILE (or --simulate)".into()))?;
    let descriptor = load_descriptor(
        descriptor_path,
        command.common.site.as_ref(),
        SensorKind::Lidar,
    )?;
    let SensorModel::Lidar(model) = &descriptor.model else {
        return Err(AgentError::Usage("the descriptor is not a LIDAR".into()));
    };
    let segmenter = ScanSegmenter {
        pipeline: LidarPipeline::new(frontend_config(command.frontend_config.as_deref())?)?,
        model: model.clone(),
    };
    if command.velodyne.is_some() || command.follow {
        return prepare_live(command, segmenter, descriptor);
    }
    let (Some(dir), Some(rate)) = (&command.scans, command.rate) else {
        return Err(AgentError::Usage(
            "lidar needs --scans DIR with --rate HZ, --scans DIR --follow, --velodyne ADDR:PORT (or --simulate)"
                .into(),
        ));
    };
    if !(rate.is_finite() && rate > 0.0) {
        return Err(AgentError::invalid(
            "--rate",
            format!("{rate} is not a positive number of scans per second"),
        ));
    }
    let scans = list_scans(dir)?;
    tracing::info!(scans = scans.len(), dir = %dir.display(), "LIDAR scans found");
    let start = command.timing.start.unwrap_or_else(wall_clock);
    let source = LidarSource {
        scans,
        next: 0,
        start,
        rate,
        segmenter,
    };
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        start,
        start,
    ))
}

/// `--velodyne` or `--scans DIR --follow`: a reader thread and a bounded queue, scans stamped on arrival.
fn prepare_live(
    command: &LidarCommand,
    segmenter: ScanSegmenter,
    descriptor: protocol::SensorDescriptor,
) -> Result<Prepared, AgentError> {
    if command.timing.start.is_some() || command.rate.is_some() {
        return Err(AgentError::Usage(
            "live LIDAR input is stamped on arrival (host clock less --pipeline-delay-ms): do not give --start or --rate"
                .into(),
        ));
    }
    let clock = CaptureClock::new(command.pipeline_delay_ms)?;
    let what = if command.velodyne.is_some() {
        "velodyne"
    } else {
        "follow"
    };
    let (queue, source) = LiveLidar::new(segmenter, clock, what);
    match (&command.velodyne, &command.scans) {
        (Some(address), _) => {
            let address = velodyne_input::parse_address(address)?;
            velodyne_input::start(address, command.idle_timeout_s, clock, queue)?;
        }
        (None, Some(dir)) => scan_follow::start(dir.clone(), clock, queue)?,
        (None, None) => return Err(AgentError::Usage("--follow goes with --scans DIR".into())),
    }
    tracing::info!(
        input = what,
        pipeline_delay_ms = command.pipeline_delay_ms,
        "live LIDAR input: scans stamped on arrival on the host clock, less the pipeline delay"
    );
    let origin = clock.origin_wall();
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        origin,
        origin,
    ))
}

/// The front end's configuration: the TOML file, or its documented defaults.
fn frontend_config(path: Option<&Path>) -> Result<LidarConfig, AgentError> {
    match path {
        Some(path) => read_frontend_config(path),
        None => Ok(LidarConfig::default()),
    }
}

/// The `.pcd` and `.bin` files of `dir` (any letter case), sorted by file name; an error when there are none.
fn list_scans(dir: &Path) -> Result<Vec<PathBuf>, AgentError> {
    let io_error = |source| AgentError::Input {
        path: dir.to_path_buf(),
        source,
    };
    let mut scans = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io_error)? {
        let path = entry.map_err(io_error)?.path();
        if path.is_file() && scan_format(&path).is_some() {
            scans.push(path);
        }
    }
    if scans.is_empty() {
        return Err(AgentError::Usage(format!(
            "{} holds no .pcd or .bin scans",
            dir.display()
        )));
    }
    scans.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
    Ok(scans)
}

/// The two scan formats, told apart by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanFormat {
    /// Point Cloud Library's format.
    Pcd,
    /// KITTI velodyne records.
    KittiBin,
}

/// The format of a scan file, by its extension; `None` for any other file.
pub fn scan_format(path: &Path) -> Option<ScanFormat> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "pcd" => Some(ScanFormat::Pcd),
        "bin" => Some(ScanFormat::KittiBin),
        _ => None,
    }
}

/// Reads one scan file in the format its extension names.
pub fn read_scan(path: &Path) -> Result<PointCloud, AgentError> {
    Ok(match scan_format(path) {
        Some(ScanFormat::Pcd) => read_pcd(path)?,
        Some(ScanFormat::KittiBin) => read_kitti_bin(path)?,
        None => {
            return Err(AgentError::Usage(format!(
                "{} is neither .pcd nor .bin",
                path.display()
            )))
        }
    })
}

/// The front end and the descriptor's region: one scan in, one frame of in-region objects out, each with its
/// covariance (the sensor's noise and the front end's `objects.centre_std`).
pub struct ScanSegmenter {
    pipeline: LidarPipeline,
    model: LidarModel,
}

impl ScanSegmenter {
    /// Whether a measurement lies in the region the descriptor says the sensor sees.
    fn in_region(&self, [range, _, elevation]: &[f64; 3]) -> bool {
        let [low, high] = self.model.elevation_limits;
        *range <= self.model.max_range && (low..=high).contains(elevation)
    }

    /// The frame of `cloud`, stamped `stamp`.
    pub fn frame(&self, cloud: &PointCloud, stamp: f64) -> Frame {
        let all = self.pipeline.measurements(cloud);
        let kept: Vec<[f64; 3]> = all.iter().copied().filter(|m| self.in_region(m)).collect();
        if kept.len() < all.len() {
            tracing::debug!(
                stamp,
                outside = all.len() - kept.len(),
                "clusters outside the descriptor's range or elevation limits left out"
            );
        }
        let covariances = self
            .pipeline
            .covariances(&kept, self.model.noise_std)
            .map(|all| {
                all.iter()
                    .map(|c| c.iter().map(|row| row.to_vec()).collect())
                    .collect()
            });
        let measurements = kept.iter().map(|m| m.to_vec()).collect();
        Frame {
            stamp,
            measurements,
            covariances,
        }
    }
}

/// Scans read and segmented one at a time.
struct LidarSource {
    scans: Vec<PathBuf>,
    next: usize,
    start: f64,
    rate: f64,
    segmenter: ScanSegmenter,
}

impl EventSource for LidarSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        let Some(path) = self.scans.get(self.next) else {
            return Ok(None);
        };
        let cloud = read_scan(path)?;
        let stamp = self.start + self.next as f64 / self.rate;
        self.next += 1;
        Ok(Some(Event::Set {
            stream: 0,
            frame: self.segmenter.frame(&cloud, stamp),
        }))
    }
}
