//! The per-pixel background model interface and its construction from the configuration.

use image::GrayImage;

use super::chromaticity::{Rgi, RgiImage};
use super::config::{BackgroundConfig, BackgroundModelKind};
use super::kde_background::KdeBackground;
use super::running_background::RunningStatsBackground;

/// Mask value of a foreground pixel; background pixels are 0.
pub const FOREGROUND: u8 = 255;

/// A per-pixel background model that learns from the first frames and then tells foreground from
/// background, updating itself only where it saw background (selective update), so that people
/// standing still are not absorbed into the background.
pub trait BackgroundModel: Send {
    /// True while the model is still learning its first frames; it classifies nothing then.
    fn is_learning(&self) -> bool;

    /// Writes `FOREGROUND` (255) into `foreground` where `frame` does not fit the background and 0
    /// elsewhere. `frame` and `foreground` have the size the model was built for.
    fn classify(&self, frame: &RgiImage, foreground: &mut GrayImage);

    /// Like [`BackgroundModel::classify`], and also writes each pixel's foreground value into `values`
    /// (resized to the frame): 1 for a pixel unlike the background, falling to 0 as its background
    /// likelihood rises to `saturation` (a model without a graded likelihood gives 0 or 1).
    fn foreground_values(
        &self,
        frame: &RgiImage,
        saturation: f32,
        values: &mut Vec<f32>,
        foreground: &mut GrayImage,
    ) {
        let _ = saturation;
        self.classify(frame, foreground);
        values.clear();
        values.extend(foreground.iter().map(|&m| if m == 0 { 0.0 } else { 1.0 }));
    }

    /// Feeds one frame to the model. While learning every pixel is learned; afterwards only the
    /// pixels that `foreground` marks 0 (background) are, so `foreground` should be the cleaned mask
    /// (its closing fills holes in people, which must not leak into the background).
    fn update(&mut self, frame: &RgiImage, foreground: &GrayImage);

    /// The background's value at pixel `index` (row-major): what the pixel shows when nothing is
    /// in front of it, the reference against which a shadow is recognised. Only meaningful once
    /// the model has learned.
    fn reference(&self, index: usize) -> Rgi;
}

/// Builds the configured model for frames of `width` x `height` pixels. The configuration must
/// have passed `CameraConfig::validate`.
pub fn new_background_model(
    config: &BackgroundConfig,
    width: u32,
    height: u32,
) -> Box<dyn BackgroundModel> {
    let pixels = width as usize * height as usize;
    match config.model {
        BackgroundModelKind::Kde => Box::new(KdeBackground::new(&config.kde, pixels)),
        BackgroundModelKind::RunningStats => {
            Box::new(RunningStatsBackground::new(&config.running_stats, pixels))
        }
    }
}
