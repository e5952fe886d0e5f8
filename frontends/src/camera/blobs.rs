//! Blobs: the connected components of a cleaned foreground mask, the pieces of one body joined
//! (`bodies.rs`), each body reduced to point measurements: its heads (the peaks of its top
//! outline, `top_profile.rs`, as in Pham's single-view stage, ch. 7), its centroid or its feet.

use image::GrayImage;
use image::Luma;
use imageproc::region_labelling::{connected_components, Connectivity};

use super::bodies::{group_pieces, JoinRule, PieceBox};
use super::config::BlobConfig;
use super::detections::PointAnchor;
use super::morphology::clean_mask;
use super::top_profile::{head_points, NO_PIXEL};

/// One body: a connected foreground region, or several joined as pieces of one body.
///
/// Coordinates follow `PointAnchor`: pixel `(col, row)` covers `[col, col+1) x [row, row+1)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Blob {
    /// Number of pixels.
    pub area: u32,
    /// Leftmost column.
    pub left: u32,
    /// Topmost row.
    pub top: u32,
    /// One past the rightmost column.
    pub right: u32,
    /// One past the bottom row.
    pub bottom: u32,
    /// Centre of mass `[x, y]`.
    pub centroid: [f64; 2],
    /// The point measurement chosen by the configured anchor (with the top-centre anchor, the
    /// highest head).
    pub point: [f64; 2],
    /// With the top-centre anchor, every head of the body, highest first (one per person it
    /// holds); otherwise just `point`.
    pub points: Vec<[f64; 2]>,
}

/// Per-component sums gathered in one scan of the label image.
#[derive(Debug, Clone, Copy, Default)]
struct LabelStats {
    area: u32,
    left: u32,
    top: u32,
    right: u32,
    bottom: u32,
    sum_x: u64,
    sum_y: u64,
}

/// Per-body sums: the union of its pieces, then its outline and bottom band.
#[derive(Debug, Clone, Default)]
struct BodyStats {
    piece: LabelStats,
    /// Top row of each column from `left`, `NO_PIXEL` where the body has none.
    tops: Vec<u32>,
    band_sum_x: u64,
    band_count: u32,
}

/// Turns foreground masks into blobs and point measurements. Keeps its scratch buffers between
/// frames.
#[derive(Debug, Clone)]
pub struct BlobDetector {
    config: BlobConfig,
    stats: Vec<LabelStats>,
}

impl BlobDetector {
    /// A detector with the given settings (which must have passed `CameraConfig::validate`).
    pub fn new(config: BlobConfig) -> Self {
        Self {
            config,
            stats: Vec::new(),
        }
    }

    /// Its settings.
    pub fn config(&self) -> &BlobConfig {
        &self.config
    }

    /// Cleans `mask` in place (opening then closing) and returns the bodies of at least
    /// `min_area` pixels, in order of their topmost pixel (row-major).
    pub fn detect(&mut self, mask: &mut GrayImage) -> Vec<Blob> {
        clean_mask(mask, self.config.cleanup_radius);
        self.find_blobs(mask)
    }

    /// The bodies of an already cleaned mask: its 8-connected regions of at least
    /// `min_piece_area` pixels, joined by the configured rule, kept when they have `min_area`
    /// pixels in all; in order of their topmost pixel (row-major).
    pub fn find_blobs(&mut self, mask: &GrayImage) -> Vec<Blob> {
        let labels = connected_components(mask, Connectivity::Eight, Luma([0u8]));
        let width = mask.width() as usize;
        self.gather_label_stats(labels.iter().copied(), width);
        let pieces: Vec<usize> = (0..self.stats.len())
            .filter(|&i| self.stats[i].area >= self.config.min_piece_area)
            .collect();
        let boxes: Vec<PieceBox> = pieces.iter().map(|&i| piece_box(&self.stats[i])).collect();
        let rule = JoinRule {
            stacked_gap_rows: self.config.join_gap_rows,
            beside_gap_cols: self.config.join_gap_cols,
        };
        let groups = group_pieces(&boxes, rule);
        let mut bodies = vec![BodyStats::default(); groups.iter().max().map_or(0, |g| g + 1)];
        let mut body_of_label = vec![usize::MAX; self.stats.len()];
        for (&label, &group) in pieces.iter().zip(&groups) {
            body_of_label[label] = group;
            merge(&mut bodies[group].piece, &self.stats[label]);
        }
        // Bodies too small in all are noise: area 0 marks them dropped (indices stay).
        for body in bodies
            .iter_mut()
            .filter(|b| b.piece.area < self.config.min_area)
        {
            body.piece.area = 0;
        }
        self.outline_bodies(&labels, width, &body_of_label, &mut bodies);
        let mut blobs: Vec<Blob> = bodies
            .iter()
            .filter(|b| b.piece.area > 0)
            .map(|b| self.blob_from(b))
            .collect();
        blobs.sort_by_key(|b| (b.top, b.left));
        blobs
    }

    /// Pass 1: area, bounding box and centroid sums of every component. Labels appear in
    /// row-major order of their first pixel, so `top` is known when a label is first met.
    fn gather_label_stats(&mut self, labels: impl Iterator<Item = u32>, width: usize) {
        self.stats.clear();
        for (index, label) in labels.enumerate() {
            if label == 0 {
                continue;
            }
            let slot = label as usize - 1;
            if slot >= self.stats.len() {
                self.stats.resize(slot + 1, LabelStats::default());
            }
            let (x, y) = ((index % width) as u32, (index / width) as u32);
            let s = &mut self.stats[slot];
            if s.area == 0 {
                (s.left, s.top, s.right, s.bottom) = (x, y, x + 1, y + 1);
            }
            s.area += 1;
            s.left = s.left.min(x);
            s.right = s.right.max(x + 1);
            s.bottom = y + 1;
            s.sum_x += x as u64;
            s.sum_y += y as u64;
        }
    }

    /// Pass 2: each kept body's top row per column, and the pixels of its bottom band.
    fn outline_bodies(
        &self,
        labels: &image::ImageBuffer<Luma<u32>, Vec<u32>>,
        width: usize,
        body_of_label: &[usize],
        bodies: &mut [BodyStats],
    ) {
        for body in bodies.iter_mut().filter(|b| b.piece.area > 0) {
            body.tops = vec![NO_PIXEL; (body.piece.right - body.piece.left) as usize];
        }
        let band = self.config.anchor_band_rows;
        for (index, &label) in labels.iter().enumerate() {
            let Some(&group) = (label as usize)
                .checked_sub(1)
                .and_then(|l| body_of_label.get(l))
            else {
                continue;
            };
            let Some(body) = bodies.get_mut(group).filter(|b| b.piece.area > 0) else {
                continue;
            };
            let (x, y) = ((index % width) as u32, (index / width) as u32);
            let column = &mut body.tops[(x - body.piece.left) as usize];
            *column = (*column).min(y);
            if y + band >= body.piece.bottom {
                body.band_sum_x += u64::from(x);
                body.band_count += 1;
            }
        }
    }

    fn blob_from(&self, body: &BodyStats) -> Blob {
        let s = &body.piece;
        // +0.5: pixel centres are at half-integer coordinates.
        let centroid = [
            s.sum_x as f64 / s.area as f64 + 0.5,
            s.sum_y as f64 / s.area as f64 + 0.5,
        ];
        let points = match self.config.anchor {
            PointAnchor::TopCentre => head_points(
                &body.tops,
                s.left,
                s.bottom,
                self.config.head_prominence_rows,
                self.config.anchor_band_rows,
            ),
            PointAnchor::Centroid => vec![centroid],
            PointAnchor::BottomCentre => vec![[
                body.band_sum_x as f64 / body.band_count.max(1) as f64 + 0.5,
                s.bottom as f64,
            ]],
        };
        Blob {
            area: s.area,
            left: s.left,
            top: s.top,
            right: s.right,
            bottom: s.bottom,
            centroid,
            point: points.first().copied().unwrap_or(centroid),
            points,
        }
    }
}

fn piece_box(s: &LabelStats) -> PieceBox {
    PieceBox {
        left: s.left,
        top: s.top,
        right: s.right,
        bottom: s.bottom,
    }
}

/// Adds a component's sums to its body's.
fn merge(body: &mut LabelStats, piece: &LabelStats) {
    if body.area == 0 {
        *body = *piece;
        return;
    }
    body.area += piece.area;
    body.left = body.left.min(piece.left);
    body.top = body.top.min(piece.top);
    body.right = body.right.max(piece.right);
    body.bottom = body.bottom.max(piece.bottom);
    body.sum_x += piece.sum_x;
    body.sum_y += piece.sum_y;
}
