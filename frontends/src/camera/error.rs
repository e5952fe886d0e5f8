//! The camera front end's error type.

use std::path::PathBuf;

/// Everything that can go wrong in the camera front end. Messages name the file (and line) at fault.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// A directory or file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A frame directory holds no PNG or JPEG file.
    #[error("frame directory {dir} holds no .png, .jpg or .jpeg file")]
    NoFrames {
        /// The directory.
        dir: PathBuf,
    },
    /// A frame file could not be decoded as an image.
    #[error("cannot decode frame {path}: {source}")]
    FrameDecode {
        /// The frame file.
        path: PathBuf,
        /// The decoder's error.
        source: image::ImageError,
    },
    /// A frame index past the end of a frame directory was asked for.
    #[error("frame index {index} is out of range: the directory holds {frames} frames")]
    FrameIndex {
        /// The index asked for.
        index: usize,
        /// Number of frames.
        frames: usize,
    },
    /// A frame's size differs from the first frame's.
    #[error("frame {frame} is {found_width}x{found_height} px but the sequence started with {expected_width}x{expected_height} px")]
    FrameSizeMismatch {
        /// The frame's file name, or its index when it did not come from a file.
        frame: String,
        /// Width of the first frame.
        expected_width: u32,
        /// Height of the first frame.
        expected_height: u32,
        /// Width of this frame.
        found_width: u32,
        /// Height of this frame.
        found_height: u32,
    },
    /// A frame is empty (zero width or height).
    #[error("frame {frame} has no pixels ({width}x{height})")]
    EmptyFrame {
        /// The frame's file name or index.
        frame: String,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
    },
    /// A line of a stamps file is not a usable stamp.
    #[error("{path}, line {line}: {problem}")]
    Stamp {
        /// The stamps file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        problem: String,
    },
    /// A stamps file lists a different number of stamps than there are frames.
    #[error("{path} lists {stamps} stamps but the frame directory holds {frames} frames")]
    StampCount {
        /// The stamps file.
        path: PathBuf,
        /// Stamps found.
        stamps: usize,
        /// Frames found.
        frames: usize,
    },
    /// A line of a MOT Challenge `det.txt` file is malformed.
    #[error("{path}, line {line}: {problem}")]
    Detection {
        /// The detections file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        problem: String,
    },
    /// A configuration value is out of its range.
    #[error("invalid camera configuration: {field} {problem}")]
    InvalidConfig {
        /// The offending field, as spelled in the configuration file.
        field: &'static str,
        /// What is wrong with its value.
        problem: String,
    },
}

/// Shorthand for results of the camera front end.
pub type CameraResult<T> = Result<T, CameraError>;
