//! Reader for MOT Challenge detection files (`det/det.txt`).
//!
//! Each non-blank line is one box: `frame, id, left, top, width, height, score, x, y, z`, comma
//! separated. The first six fields are required; `score` and the world coordinates `x, y, z` may be
//! missing or empty (trailing columns). Frames are numbered from 1; `id` is -1 in detection files and
//! is ignored, as are `x, y, z` (checked to be numbers when present). A box without a score is kept
//! whatever the threshold. Coordinates are taken as they are in the file (no 1-based shift), in
//! pixels with y down, so the top-centre of a box is `(left + width / 2, top)`. Frame numbers above
//! `MAX_FRAME` are refused.

use std::fs;
use std::path::Path;

use super::config::MotDetConfig;
use super::detections::{FrameDetections, PointAnchor};
use super::error::{CameraError, CameraResult};
use super::frames::FrameRate;

/// One line of a `det.txt` file.
#[derive(Debug, Clone, PartialEq)]
pub struct MotDetection {
    /// MOT frame number, from 1.
    pub frame: usize,
    /// Left edge of the box, in pixels.
    pub left: f64,
    /// Top edge of the box, in pixels.
    pub top: f64,
    /// Box width, in pixels (> 0).
    pub width: f64,
    /// Box height, in pixels (> 0).
    pub height: f64,
    /// Detector confidence, if the line has one.
    pub score: Option<f64>,
}

impl MotDetection {
    /// The point of the box that `anchor` names.
    pub fn point(&self, anchor: PointAnchor) -> [f64; 2] {
        let x = self.left + self.width / 2.0;
        match anchor {
            PointAnchor::TopCentre => [x, self.top],
            PointAnchor::Centroid => [x, self.top + self.height / 2.0],
            PointAnchor::BottomCentre => [x, self.top + self.height],
        }
    }
}

/// Largest frame number accepted (over 11 hours at 25 fps). Every frame up to the last one gets an
/// entry in the output, so a corrupt huge frame number must not allocate without bound.
pub const MAX_FRAME: usize = 1_000_000;
const REQUIRED_FIELDS: usize = 6;
const MAX_FIELDS: usize = 10;
const FIELD_NAMES: [&str; MAX_FIELDS] = [
    "frame", "id", "left", "top", "width", "height", "score", "x", "y", "z",
];

fn parse_number(fields: &[&str], index: usize) -> Result<f64, String> {
    let text = fields[index];
    let value: f64 = text
        .parse()
        .map_err(|_| format!("{} {text:?} is not a number", FIELD_NAMES[index]))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{} {text:?} is not finite", FIELD_NAMES[index]))
    }
}

/// Parses one non-blank line; the error says what is wrong with it.
pub fn parse_mot_line(line: &str) -> Result<MotDetection, String> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    if fields.len() < REQUIRED_FIELDS {
        return Err(format!(
            "expected at least {REQUIRED_FIELDS} comma-separated fields \
             (frame, id, left, top, width, height), found {}",
            fields.len()
        ));
    }
    if fields.len() > MAX_FIELDS {
        return Err(format!(
            "expected at most {MAX_FIELDS} fields \
             (frame, id, left, top, width, height, score, x, y, z), found {}",
            fields.len()
        ));
    }
    let frame = parse_number(&fields, 0)?;
    if frame < 1.0 || frame.fract() != 0.0 {
        return Err(format!("frame {:?} is not a whole number >= 1", fields[0]));
    }
    if frame > MAX_FRAME as f64 {
        return Err(format!(
            "frame {:?} is beyond the supported {MAX_FRAME} frames",
            fields[0]
        ));
    }
    parse_number(&fields, 1)?;
    let [left, top, width, height] = [2, 3, 4, 5].map(|i| parse_number(&fields, i));
    let (width, height) = (width?, height?);
    if width <= 0.0 || height <= 0.0 {
        return Err(format!("box size {width} x {height} is not positive"));
    }
    let mut score = None;
    for index in REQUIRED_FIELDS..fields.len() {
        if fields[index].is_empty() {
            continue;
        }
        let value = parse_number(&fields, index)?;
        if index == REQUIRED_FIELDS {
            score = Some(value);
        }
    }
    Ok(MotDetection {
        frame: frame as usize,
        left: left?,
        top: top?,
        width,
        height,
        score,
    })
}

/// Parses the text of a `det.txt` file; `path` only names the file in errors.
pub fn parse_mot_text(text: &str, path: &Path) -> CameraResult<Vec<MotDetection>> {
    let mut detections = Vec::new();
    for (i, line) in text.lines().enumerate() {
        // A byte-order mark may precede the first line of files written on Windows.
        let line = line.trim_start_matches('\u{feff}').trim();
        if line.is_empty() {
            continue;
        }
        let detection = parse_mot_line(line).map_err(|problem| CameraError::Detection {
            path: path.to_path_buf(),
            line: i + 1,
            problem,
        })?;
        detections.push(detection);
    }
    Ok(detections)
}

/// Groups boxes scoring at least `config.min_score` by frame, one point per box. The result has
/// one entry per frame from 1 to the highest frame number in `detections` (whatever its scores),
/// empty where no box passes, since an empty frame is information for a tracker too. Frame n gets
/// `frame_index` n - 1 and the stamp `rate.stamp(n - 1)`.
pub fn group_by_frame(
    detections: &[MotDetection],
    config: &MotDetConfig,
    rate: &FrameRate,
) -> Vec<FrameDetections> {
    let frames = detections.iter().map(|d| d.frame).max().unwrap_or(0);
    let mut out: Vec<FrameDetections> = (0..frames)
        .map(|index| FrameDetections {
            frame_index: index,
            stamp: rate.stamp(index),
            points: Vec::new(),
        })
        .collect();
    for detection in detections {
        if detection
            .score
            .is_none_or(|score| score >= config.min_score)
        {
            out[detection.frame - 1]
                .points
                .push(detection.point(config.anchor));
        }
    }
    out
}

/// Reads a `det.txt` file and groups its boxes by frame (see `group_by_frame`).
pub fn read_mot_detections(
    path: &Path,
    config: &MotDetConfig,
    rate: &FrameRate,
) -> CameraResult<Vec<FrameDetections>> {
    rate.validate()?;
    let text = fs::read_to_string(path).map_err(|source| CameraError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(group_by_frame(&parse_mot_text(&text, path)?, config, rate))
}
