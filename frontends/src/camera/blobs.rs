//! Blobs: connected components of a cleaned foreground mask, each reduced to one point measurement
//! (its head point by default, as in Pham's single-view stage, ch. 7).

use image::GrayImage;
use image::Luma;
use imageproc::region_labelling::{connected_components, Connectivity};

use super::config::BlobConfig;
use super::detections::PointAnchor;
use super::morphology::clean_mask;

/// One connected foreground region.
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
    /// The point measurement chosen by the configured anchor.
    pub point: [f64; 2],
}

/// Per-label sums gathered in one scan of the label image.
#[derive(Debug, Clone, Copy, Default)]
struct LabelStats {
    area: u32,
    left: u32,
    top: u32,
    right: u32,
    bottom: u32,
    sum_x: u64,
    sum_y: u64,
    band_sum_x: u64,
    band_count: u32,
}

/// Turns foreground masks into blobs and point measurements. Keeps its scratch buffer between frames.
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

    /// Cleans `mask` in place (opening then closing) and returns the blobs of at least `min_area`
    /// pixels, in order of their topmost pixel (row-major).
    pub fn detect(&mut self, mask: &mut GrayImage) -> Vec<Blob> {
        clean_mask(mask, self.config.cleanup_radius);
        self.find_blobs(mask)
    }

    /// The blobs (8-connected regions of non-zero pixels) of an already cleaned mask with at least
    /// `min_area` pixels, in order of their topmost pixel (row-major).
    pub fn find_blobs(&mut self, mask: &GrayImage) -> Vec<Blob> {
        let labels = connected_components(mask, Connectivity::Eight, Luma([0u8]));
        self.stats.clear();
        let width = mask.width() as usize;
        // Pass 1: area, bounding box and centroid sums. Labels appear in row-major order of their
        // first pixel, so `top` is known when a label is first met.
        for (index, &label) in labels.iter().enumerate() {
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
        // Pass 2: the band of rows at the top or bottom edge that fixes the anchor's x.
        let band = self.config.anchor_band_rows;
        if self.config.anchor != PointAnchor::Centroid {
            for (index, &label) in labels.iter().enumerate() {
                if label == 0 {
                    continue;
                }
                let s = &mut self.stats[label as usize - 1];
                if s.area < self.config.min_area {
                    continue;
                }
                let y = (index / width) as u32;
                let in_band = match self.config.anchor {
                    PointAnchor::TopCentre => y < s.top + band,
                    _ => y + band >= s.bottom,
                };
                if in_band {
                    s.band_sum_x += (index % width) as u64;
                    s.band_count += 1;
                }
            }
        }
        self.stats
            .iter()
            .filter(|s| s.area >= self.config.min_area)
            .map(|s| self.blob_from(s))
            .collect()
    }

    fn blob_from(&self, s: &LabelStats) -> Blob {
        // +0.5: pixel centres are at half-integer coordinates.
        let centroid = [
            s.sum_x as f64 / s.area as f64 + 0.5,
            s.sum_y as f64 / s.area as f64 + 0.5,
        ];
        let band_x = || s.band_sum_x as f64 / s.band_count.max(1) as f64 + 0.5;
        let point = match self.config.anchor {
            PointAnchor::TopCentre => [band_x(), s.top as f64],
            PointAnchor::Centroid => centroid,
            PointAnchor::BottomCentre => [band_x(), s.bottom as f64],
        };
        Blob {
            area: s.area,
            left: s.left,
            top: s.top,
            right: s.right,
            bottom: s.bottom,
            centroid,
            point,
        }
    }
}
