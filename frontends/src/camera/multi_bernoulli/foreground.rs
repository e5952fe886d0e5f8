//! The background-subtracted grey image the filter works on, and fast sums over its rows.
//!
//! Each pixel holds a foreground value `f = 1 − min(1, y / saturation)` from its background likelihood
//! `y` (eq. 10 of Hoseinnezhad, Vo & Vu): 1 for a pixel unlike every background sample, 0 for one as
//! likely as the background's own spread. The likelihood scores a region by the sum of
//! `f − threshold` over its pixels, so the map keeps, per row, the running sum of that score; any span's
//! sum is then two look-ups, interpolated inside the pixels at its ends so that it varies smoothly with
//! fractional edges.

use image::GrayImage;

use super::region::RowSpan;

/// Per-pixel foreground values of one (shrunk) frame and their row-wise running sums.
#[derive(Debug, Clone, Default)]
pub struct ForegroundMap {
    width: usize,
    height: usize,
    threshold: f32,
    values: Vec<f32>,
    /// Row-major, `width + 1` entries per row: `cumulative[r][c]` is the sum of `f − threshold` over
    /// columns `0..c` of row `r`.
    cumulative: Vec<f32>,
}

impl ForegroundMap {
    /// Takes the foreground values of a `width` × `height` frame (row-major, in [0, 1]); a pixel
    /// counts for a region covering it when its value exceeds `threshold`.
    pub fn fill(&mut self, width: usize, height: usize, values: &[f32], threshold: f32) {
        debug_assert_eq!(values.len(), width * height);
        self.width = width;
        self.height = height;
        self.threshold = threshold;
        self.values.clear();
        self.values.extend_from_slice(values);
        self.cumulative.clear();
        self.cumulative.reserve(height * (width + 1));
        for row in values.chunks_exact(width.max(1)).take(height) {
            let mut sum = 0.0f32;
            self.cumulative.push(0.0);
            for &f in row {
                sum += f - threshold;
                self.cumulative.push(sum);
            }
        }
    }

    /// Width and height in (shrunk) pixels.
    pub fn size(&self) -> [usize; 2] {
        [self.width, self.height]
    }

    /// The foreground values, row-major.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The threshold a pixel's value is scored against.
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// The pixels whose value exceeds the threshold, as a mask (255 = foreground).
    pub fn mask(&self) -> GrayImage {
        let mut mask = GrayImage::new(self.width as u32, self.height as u32);
        for (m, &f) in mask.iter_mut().zip(&self.values) {
            *m = if f > self.threshold { 255 } else { 0 };
        }
        mask
    }

    /// Sum of `f − threshold` over columns `[0, x)` of `row` (x fractional, clamped to the row).
    fn running(&self, row: &[f32], x: f32) -> f32 {
        let x = x.clamp(0.0, self.width as f32);
        let whole = x.floor();
        let c = whole as usize;
        if c >= self.width {
            return row[self.width];
        }
        row[c] + (x - whole) * (row[c + 1] - row[c])
    }

    /// Sum of `f − threshold` over columns `[left, right)` of `row`; 0 outside the image.
    pub fn row_sum(&self, row: i32, left: f32, right: f32) -> f32 {
        if row < 0 || row as usize >= self.height || right <= left {
            return 0.0;
        }
        let start = row as usize * (self.width + 1);
        let cumulative = &self.cumulative[start..start + self.width + 1];
        self.running(cumulative, right) - self.running(cumulative, left)
    }

    /// The weighted score of one span (see [`ForegroundMap::row_sum`]).
    pub fn span_sum(&self, span: &RowSpan) -> f32 {
        span.weight * self.row_sum(span.row, span.left, span.right)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_sums_interpolate_inside_the_end_pixels() {
        let mut map = ForegroundMap::default();
        // One row: 0, 1, 1, 0 with threshold 0.5: scores −0.5, 0.5, 0.5, −0.5.
        map.fill(4, 1, &[0.0, 1.0, 1.0, 0.0], 0.5);
        assert!((map.row_sum(0, 1.0, 3.0) - 1.0).abs() < 1e-6);
        assert!((map.row_sum(0, 0.0, 4.0)).abs() < 1e-6);
        assert!((map.row_sum(0, 0.5, 1.5) - 0.0).abs() < 1e-6);
        assert!((map.row_sum(0, -3.0, 2.0) - 0.0).abs() < 1e-6);
        assert_eq!(map.row_sum(1, 0.0, 4.0), 0.0);
        assert_eq!(map.row_sum(-1, 0.0, 4.0), 0.0);
        assert_eq!(map.mask().as_raw(), &vec![0, 255, 255, 0]);
    }
}
