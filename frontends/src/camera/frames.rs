//! Frame input: a directory of PNG/JPEG frames, ordered by file name, each with a time stamp.
//!
//! Stamps come either from a frame rate (`stamp = start + i / fps` for the i-th frame, 0-based) or from
//! a stamps file: a text file with one stamp in seconds per line, in the same order as the sorted frame
//! files. In a stamps file, blank lines and lines starting with `#` are skipped; every other line must
//! hold one finite decimal number, larger than the one before, and there must be exactly one per frame.

use std::fs;
use std::path::{Path, PathBuf};

use image::RgbImage;

use super::error::{CameraError, CameraResult};

/// A constant frame rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRate {
    /// Stamp of the first frame (index 0), in seconds.
    pub start: f64,
    /// Frames per second; must be finite and positive.
    pub fps: f64,
}

impl FrameRate {
    /// The stamp of the frame with 0-based index `index`.
    pub fn stamp(&self, index: usize) -> f64 {
        self.start + index as f64 / self.fps
    }

    /// Checks that `fps` is finite and positive and `start` is finite.
    pub fn validate(&self) -> CameraResult<()> {
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(CameraError::InvalidConfig {
                field: "fps",
                problem: format!("must be finite and > 0, got {}", self.fps),
            });
        }
        if !self.start.is_finite() {
            return Err(CameraError::InvalidConfig {
                field: "start",
                problem: format!("must be finite, got {}", self.start),
            });
        }
        Ok(())
    }
}

/// Where the stamps of a frame directory come from.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameTiming {
    /// Evenly spaced frames.
    Rate(FrameRate),
    /// A stamps file (format in the module documentation).
    StampsFile(PathBuf),
}

/// One decoded frame.
#[derive(Debug, Clone)]
pub struct Frame {
    /// 0-based position in the sorted directory listing.
    pub index: usize,
    /// Time of the frame, in seconds.
    pub stamp: f64,
    /// The file it was read from.
    pub path: PathBuf,
    /// Its pixels, converted to 8-bit RGB.
    pub image: RgbImage,
}

/// The frames of a directory, listed and stamped but decoded one at a time on demand.
#[derive(Debug, Clone)]
pub struct FrameDirectory {
    paths: Vec<PathBuf>,
    stamps: Vec<f64>,
}

impl FrameDirectory {
    /// Lists the `.png`, `.jpg` and `.jpeg` files (any letter case) of `dir`, sorted by file name, and
    /// stamps them. Other files (such as the stamps file itself) are ignored.
    pub fn open(dir: &Path, timing: &FrameTiming) -> CameraResult<Self> {
        let paths = list_frame_files(dir)?;
        let stamps = match timing {
            FrameTiming::Rate(rate) => {
                rate.validate()?;
                (0..paths.len()).map(|i| rate.stamp(i)).collect()
            }
            FrameTiming::StampsFile(path) => {
                let stamps = read_stamps_file(path)?;
                if stamps.len() != paths.len() {
                    return Err(CameraError::StampCount {
                        path: path.clone(),
                        stamps: stamps.len(),
                        frames: paths.len(),
                    });
                }
                stamps
            }
        };
        Ok(Self { paths, stamps })
    }

    /// Number of frames (never zero).
    pub fn len(&self) -> usize {
        self.paths.len()
    }

    /// Always false: opening a directory without frames fails. Present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }

    /// The frame files, in order.
    pub fn paths(&self) -> &[PathBuf] {
        &self.paths
    }

    /// The frame stamps, in order.
    pub fn stamps(&self) -> &[f64] {
        &self.stamps
    }

    /// Decodes the frame at `index`.
    pub fn load(&self, index: usize) -> CameraResult<Frame> {
        let path = self.paths.get(index).ok_or(CameraError::FrameIndex {
            index,
            frames: self.paths.len(),
        })?;
        let image = image::open(path)
            .map_err(|source| CameraError::FrameDecode {
                path: path.clone(),
                source,
            })?
            .to_rgb8();
        Ok(Frame {
            index,
            stamp: self.stamps[index],
            path: path.clone(),
            image,
        })
    }

    /// Decodes the frames one after the other.
    pub fn iter(&self) -> impl Iterator<Item = CameraResult<Frame>> + '_ {
        (0..self.len()).map(|i| self.load(i))
    }
}

fn is_frame_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| matches!(e.to_ascii_lowercase().as_str(), "png" | "jpg" | "jpeg"))
        .unwrap_or(false)
}

fn list_frame_files(dir: &Path) -> CameraResult<Vec<PathBuf>> {
    let io_err = |source| CameraError::Io {
        path: dir.to_path_buf(),
        source,
    };
    let mut paths = Vec::new();
    for entry in fs::read_dir(dir).map_err(io_err)? {
        let path = entry.map_err(io_err)?.path();
        if path.is_file() && is_frame_file(&path) {
            paths.push(path);
        }
    }
    if paths.is_empty() {
        return Err(CameraError::NoFrames {
            dir: dir.to_path_buf(),
        });
    }
    paths.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
    Ok(paths)
}

/// Reads a stamps file: one strictly increasing finite stamp (seconds) per non-blank, non-`#` line.
pub fn read_stamps_file(path: &Path) -> CameraResult<Vec<f64>> {
    let text = fs::read_to_string(path).map_err(|source| CameraError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut stamps: Vec<f64> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let problem = |problem: String| CameraError::Stamp {
            path: path.to_path_buf(),
            line: i + 1,
            problem,
        };
        let stamp: f64 = line
            .parse()
            .map_err(|_| problem(format!("{line:?} is not a number")))?;
        if !stamp.is_finite() {
            return Err(problem(format!("stamp {line:?} is not finite")));
        }
        if let Some(&previous) = stamps.last() {
            if stamp <= previous {
                return Err(problem(format!(
                    "stamp {stamp} is not after the previous stamp {previous}"
                )));
            }
        }
        stamps.push(stamp);
    }
    Ok(stamps)
}
