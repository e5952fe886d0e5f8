//! Shadow suppression (after Cucchiara et al.'s chromaticity test, in the rgI space of
//! `chromaticity.rs`): a shadow darkens a surface without changing its colour, so a foreground
//! pixel whose chromaticity is the background's and whose brightness is a fixed share of it is
//! shadow, not object. People's soft shadows at their feet would otherwise join two people into one
//! blob and push each blob's bottom onto the floor around it.

use image::GrayImage;

use super::background::{BackgroundModel, FOREGROUND};
use super::chromaticity::{RgiImage, RGI_SCALE};
use super::config::ShadowConfig;

/// Moves the shadow pixels of `objects` (foreground as classified) into `shadows` (255 there, 0
/// elsewhere) and clears them in `objects`; returns how many there were.
pub fn suppress_shadows(
    config: &ShadowConfig,
    background: &dyn BackgroundModel,
    frame: &RgiImage,
    objects: &mut GrayImage,
    shadows: &mut GrayImage,
) -> usize {
    shadows.fill(0);
    if !config.enabled {
        return 0;
    }
    let chroma = config.max_chromaticity_difference * RGI_SCALE[0];
    let mut count = 0;
    let pixels = objects
        .iter_mut()
        .zip(shadows.iter_mut())
        .zip(frame.pixels());
    for (index, ((object, shadow), x)) in pixels.enumerate() {
        if *object != FOREGROUND {
            continue;
        }
        let reference = background.reference(index);
        let same_colour =
            (0..2).all(|d| (f32::from(x[d]) - f32::from(reference[d])).abs() <= chroma);
        let ratio = f32::from(x[2]) / f32::from(reference[2]).max(1.0);
        if same_colour
            && (config.min_brightness_ratio..=config.max_brightness_ratio).contains(&ratio)
        {
            *object = 0;
            *shadow = FOREGROUND;
            count += 1;
        }
    }
    count
}
