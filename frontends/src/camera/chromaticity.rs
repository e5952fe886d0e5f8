//! rgI chromaticity (Hoseinnezhad, Vo, Vu, eqs. 6-8): `r = R/(R+G+B)`, `g = G/(R+G+B)`,
//! `I = (R+G+B)/3`.
//!
//! Chromaticity separates colour from brightness, so it is less sensitive to lighting changes and
//! shadows than raw RGB. Each component is stored as one byte: `r` and `g` scaled by 255, `I` in grey
//! levels (the paper's `I = (R+G+B)/256` differs only by a constant factor, which the bandwidth absorbs).
//! One byte per component keeps the background sample stack small and lets the kernel be a table
//! look-up; the rounding (at most 0.002 in r or g, 0.5 grey level in I) is far below any useful
//! kernel bandwidth.

use image::RgbImage;

/// One pixel's quantised rgI: `[round(255 r), round(255 g), round(I)]`.
pub type Rgi = [u8; 3];

/// Scale of each stored component relative to its natural unit (r and g in [0, 1], I in grey levels).
pub const RGI_SCALE: [f32; 3] = [255.0, 255.0, 1.0];

/// Converts one RGB pixel to quantised rgI. Black (R+G+B = 0) has no chromaticity; it is given the
/// neutral grey chromaticity r = g = 1/3.
pub fn rgb_to_rgi(rgb: [u8; 3]) -> Rgi {
    rgb_sums_to_rgi(rgb.map(u32::from), 1)
}

/// The quantised rgI of `count` pixels whose R, G and B add up to `sums`: the chromaticity of their
/// summed light and their mean intensity.
fn rgb_sums_to_rgi(sums: [u32; 3], count: u32) -> Rgi {
    let [red, green, blue] = sums;
    let sum = red + green + blue;
    if sum == 0 {
        return [85, 85, 0];
    }
    // Rounded integer division: round(255 x / sum) = (2 * 255 x + sum) / (2 sum).
    let scaled = |x: u32| ((510 * x + sum) / (2 * sum)) as u8;
    let divisor = 3 * count;
    [
        scaled(red),
        scaled(green),
        ((sum + divisor / 2) / divisor) as u8,
    ]
}

/// A frame in quantised rgI, row-major. Reused from frame to frame to avoid allocation.
#[derive(Debug, Clone, Default)]
pub struct RgiImage {
    width: u32,
    height: u32,
    pixels: Vec<Rgi>,
}

impl RgiImage {
    /// Converts an RGB frame.
    pub fn from_rgb(image: &RgbImage) -> Self {
        let mut out = Self::default();
        out.fill_from(image);
        out
    }

    /// Converts an RGB frame into this buffer, reusing its allocation.
    pub fn fill_from(&mut self, image: &RgbImage) {
        self.width = image.width();
        self.height = image.height();
        self.pixels.clear();
        self.pixels
            .extend(image.pixels().map(|pixel| rgb_to_rgi(pixel.0)));
    }

    /// Converts an RGB frame binned `factor` × `factor` (each output pixel the rgI of the summed light
    /// of a block, as a sensor's binning gives it: less noise, and `factor²` fewer pixels to model);
    /// the frame's last columns and rows that do not fill a block are left out. `factor` 1 is
    /// [`RgiImage::fill_from`].
    pub fn fill_binned(&mut self, image: &RgbImage, factor: u32) {
        let factor = factor.max(1);
        if factor == 1 {
            self.fill_from(image);
            return;
        }
        self.width = image.width() / factor;
        self.height = image.height() / factor;
        self.pixels.clear();
        let width = self.width as usize;
        let mut sums = vec![[0u32; 3]; width];
        let raw = image.as_raw();
        let stride = image.width() as usize * 3;
        let block = factor as usize;
        for out_row in 0..self.height as usize {
            sums.iter_mut().for_each(|s| *s = [0; 3]);
            for row in out_row * block..(out_row + 1) * block {
                let line = &raw[row * stride..][..width * block * 3];
                for (sum, pixels) in sums.iter_mut().zip(line.chunks_exact(block * 3)) {
                    for rgb in pixels.chunks_exact(3) {
                        sum[0] += u32::from(rgb[0]);
                        sum[1] += u32::from(rgb[1]);
                        sum[2] += u32::from(rgb[2]);
                    }
                }
            }
            let count = factor * factor;
            self.pixels
                .extend(sums.iter().map(|&s| rgb_sums_to_rgi(s, count)));
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, row-major.
    pub fn pixels(&self) -> &[Rgi] {
        &self.pixels
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_binned_pixel_is_the_chromaticity_of_its_blocks_light() {
        let mut image = RgbImage::new(5, 2);
        image.put_pixel(0, 0, image::Rgb([200, 0, 0]));
        image.put_pixel(1, 1, image::Rgb([0, 200, 0]));
        image.put_pixel(2, 0, image::Rgb([30, 60, 90]));
        let mut rgi = RgiImage::default();
        rgi.fill_binned(&image, 2);
        assert_eq!((rgi.width(), rgi.height()), (2, 1));
        // Block 1: R 200, G 200, B 0 over 4 pixels: r = g = 0.5, I = 400 / 12.
        assert_eq!(rgi.pixels()[0], [128, 128, 33]);
        assert_eq!(rgi.pixels()[1], rgb_sums_to_rgi([30, 60, 90], 4));
        let mut same = RgiImage::default();
        same.fill_binned(&image, 1);
        assert_eq!(same.pixels(), RgiImage::from_rgb(&image).pixels());
    }
}
