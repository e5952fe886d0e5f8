//! The front end's output: one set of image-plane point measurements per frame.

use nalgebra::DVector;
use serde::Deserialize;

/// Which point of a blob or bounding box stands for the object.
///
/// Coordinates are in pixels, x to the right and y down, with pixel `(col, row)` covering the square
/// `[col, col+1) x [row, row+1)`; so the top edge of a box whose top row is 10 is at y = 10.0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PointAnchor {
    /// Centre of the top edge: the head of a standing person (Pham, ch. 7, tracks heads).
    #[default]
    TopCentre,
    /// Centre of mass of the blob, or centre of the box.
    Centroid,
    /// Centre of the bottom edge: the feet, i.e. the ground contact point.
    BottomCentre,
}

/// The point measurements one camera frame yields.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameDetections {
    /// 0-based index of the frame in its sequence (MOT frame number minus one).
    pub frame_index: usize,
    /// Time of the frame, in seconds.
    pub stamp: f64,
    /// One image point `[x, y]` in pixels per detected object.
    pub points: Vec<[f64; 2]>,
}

impl FrameDetections {
    /// The points as 2-vectors, the measurement type a GM-PHD update takes.
    pub fn measurement_vectors(&self) -> Vec<DVector<f64>> {
        self.points
            .iter()
            .map(|p| DVector::from_column_slice(p))
            .collect()
    }
}
