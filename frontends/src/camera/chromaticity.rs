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
    let [red, green, blue] = rgb.map(u32::from);
    let sum = red + green + blue;
    if sum == 0 {
        return [85, 85, 0];
    }
    // Rounded integer division: round(255 x / sum) = (2 * 255 x + sum) / (2 sum).
    let scaled = |x: u32| ((510 * x + sum) / (2 * sum)) as u8;
    [scaled(red), scaled(green), ((sum + 1) / 3) as u8]
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
