//! `edge-agent lidar`: a directory of scans → ground removal and clustering → one set of cluster centroids
//! `[range, azimuth, elevation]` (sensor frame) per scan.
//!
//! Scans are `.pcd` or KITTI `.bin` files taken in file-name order, scan i stamped `start + i / rate`.
//! Centroids outside the descriptor's measurement region (beyond `max_range`, or outside `elevation_limits`)
//! are left out: the descriptor says the sensor does not see there, and the server's clutter density
//! assumes every measurement lies inside that region.

use std::path::{Path, PathBuf};

use frontends::lidar::{read_kitti_bin, read_pcd, LidarConfig, LidarPipeline};
use protocol::{LidarModel, SensorKind, SensorModel};

use crate::cli::LidarCommand;
use crate::descriptor::load_descriptor;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::launch::Prepared;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};
use crate::settings::read_frontend_config;
use crate::sim::prepare_simulated_sensor;

/// Prepares `edge-agent lidar`.
pub fn prepare_lidar(command: &LidarCommand) -> Result<Prepared, AgentError> {
    if command.simulate.simulate {
        if command.scans.is_some() || command.descriptor.is_some() {
            return Err(AgentError::Usage(
                "--simulate takes the LIDAR from --scenario: do not give --scans or --descriptor"
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
    let (Some(dir), Some(rate)) = (&command.scans, command.rate) else {
        return Err(AgentError::Usage(
            "lidar needs --scans DIR with --rate HZ (or --simulate)".into(),
        ));
    };
    if !(rate.is_finite() && rate > 0.0) {
        return Err(AgentError::invalid(
            "--rate",
            format!("{rate} is not a positive number of scans per second"),
        ));
    }
    let pipeline = LidarPipeline::new(frontend_config(command.frontend_config.as_deref())?)?;
    let scans = list_scans(dir)?;
    tracing::info!(scans = scans.len(), dir = %dir.display(), "LIDAR scans found");
    let start = command.timing.start.unwrap_or_else(wall_clock);
    let source = LidarSource {
        scans,
        next: 0,
        start,
        rate,
        pipeline,
        model: model.clone(),
    };
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        start,
        start,
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
enum ScanFormat {
    /// Point Cloud Library's format.
    Pcd,
    /// KITTI velodyne records.
    KittiBin,
}

/// The format of a scan file, by its extension; `None` for any other file.
fn scan_format(path: &Path) -> Option<ScanFormat> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "pcd" => Some(ScanFormat::Pcd),
        "bin" => Some(ScanFormat::KittiBin),
        _ => None,
    }
}

/// Scans read and segmented one at a time.
struct LidarSource {
    scans: Vec<PathBuf>,
    next: usize,
    start: f64,
    rate: f64,
    pipeline: LidarPipeline,
    model: LidarModel,
}

impl LidarSource {
    /// Whether a measurement lies in the region the descriptor says the sensor sees.
    fn in_region(&self, [range, _, elevation]: &[f64; 3]) -> bool {
        let [low, high] = self.model.elevation_limits;
        *range <= self.model.max_range && (low..=high).contains(elevation)
    }
}

impl EventSource for LidarSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        let Some(path) = self.scans.get(self.next) else {
            return Ok(None);
        };
        let cloud = match scan_format(path) {
            Some(ScanFormat::Pcd) => read_pcd(path)?,
            // `list_scans` only keeps the two formats.
            _ => read_kitti_bin(path)?,
        };
        let all = self.pipeline.measurements(&cloud);
        let measurements: Vec<Vec<f64>> = all
            .iter()
            .filter(|m| self.in_region(m))
            .map(|m| m.to_vec())
            .collect();
        if measurements.len() < all.len() {
            tracing::debug!(
                scan = %path.display(),
                outside = all.len() - measurements.len(),
                "clusters outside the descriptor's range or elevation limits left out"
            );
        }
        let stamp = self.start + self.next as f64 / self.rate;
        self.next += 1;
        Ok(Some(Event::Set {
            stream: 0,
            frame: Frame {
                stamp,
                measurements,
                covariances: None,
            },
        }))
    }
}
