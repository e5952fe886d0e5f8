//! What the filter reports per person: the head top in the image with the covariance its particles
//! give, and how much of the head the camera actually sees.

use super::bernoulli::Bernoulli;
use super::cover::Cover;
use super::region::{inside, PersonProjector, RowSpan};

/// One estimated person.
#[derive(Debug, Clone, PartialEq)]
pub struct PersonEstimate {
    /// The component's id: the same person from frame to frame while the filter keeps it.
    pub id: u64,
    /// Probability that the person exists.
    pub existence: f64,
    /// Frames in a row the person has been an estimate.
    pub reported_frames: u32,
    /// The head top `[u, v]`, full-resolution pixels: the particles' mean.
    pub head: [f64; 2],
    /// Its 2 × 2 covariance (rows), px²: the particles' spread, the person model's own error, and the
    /// spread of a head whose outline lies on another person.
    pub covariance: [[f64; 2]; 2],
    /// Floor position `(x, y)`, metres (the particles' mean).
    pub floor: [f64; 2],
    /// Height of the head top above the floor, metres.
    pub height: f64,
    /// Share of the head inside the image and not behind a nearer person, in [0, 1].
    pub visible_head: f64,
    /// Share of the whole person inside the image and not behind a nearer person, in [0, 1].
    pub visible_body: f64,
    /// Horizontal distance from the camera, metres (who hides whom).
    pub distance: f64,
}

/// The head top's mean and covariance over the component's particles (full-resolution pixels), with
/// the variance of a head-top error of `model_error` metres (seen at the person's distance) added;
/// `None` when no particle projects into view.
pub fn head_statistics(
    component: &Bernoulli,
    projector: &PersonProjector,
    model_error: f64,
) -> Option<([f64; 2], [[f64; 2]; 2])> {
    let mut points = Vec::with_capacity(component.particles.len());
    for (p, &w) in component.particles.iter().zip(&component.weights) {
        if let Some(head) = projector.head_top(p[0], p[1], p[4]) {
            points.push((head, w));
        }
    }
    let total: f64 = points.iter().map(|(_, w)| w).sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let mut mean = [0.0; 2];
    for (h, w) in &points {
        mean[0] += w * h[0] / total;
        mean[1] += w * h[1] / total;
    }
    let mut c = [[0.0; 2]; 2];
    for (h, w) in &points {
        let d = [h[0] - mean[0], h[1] - mean[1]];
        for (i, row) in c.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v += w * d[i] * d[j] / total;
            }
        }
    }
    let floor = (model_error * pixels_per_metre(component, projector)?).powi(2);
    c[0][0] += floor;
    c[1][1] += floor;
    let off = 0.5 * (c[0][1] + c[1][0]);
    c[0][1] = off;
    c[1][0] = off;
    Some((mean, c))
}

/// Full-resolution pixels per metre across the line of sight at the mean head top of `component`.
fn pixels_per_metre(component: &Bernoulli, projector: &PersonProjector) -> Option<f64> {
    let m = component.mean();
    let [ax, ay] = projector.geometry().across_sight(m[0], m[1])?;
    let step = 0.1;
    let a = projector.head_top(m[0], m[1], m[4])?;
    let b = projector.head_top(m[0] + step * ax, m[1] + step * ay, m[4])?;
    Some((a[0] - b[0]).hypot(a[1] - b[1]) / step)
}

/// Share of `spans` (a region or its head) inside an image of `size` (shrunk pixels) and not covered
/// by `nearer`.
pub fn visible_share(spans: &[RowSpan], nearer: &Cover, size: [usize; 2]) -> f64 {
    let total: f32 = spans.iter().map(|s| s.area()).sum();
    if total.is_nan() || total <= 0.0 {
        return 0.0;
    }
    let seen = inside(spans, size)
        - spans
            .iter()
            .map(|s| s.weight * nearer.covered_length(&clipped(s, size)))
            .sum::<f32>();
    f64::from((seen / total).clamp(0.0, 1.0))
}

/// `span` cut to the image's columns (rows outside are left to `inside`).
fn clipped(span: &RowSpan, size: [usize; 2]) -> RowSpan {
    let mut s = *span;
    s.left = s.left.max(0.0);
    s.right = s.right.min(size[0] as f32).max(s.left);
    if s.row < 0 || s.row as usize >= size[1] {
        s.right = s.left;
    }
    s
}
