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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{new_background_model, BackgroundConfig};
    use image::{Rgb, RgbImage};

    #[test]
    fn a_darkened_floor_is_shadow_and_a_coloured_object_is_not() {
        let floor = Rgb([150u8, 116, 82]);
        let empty = RgbImage::from_pixel(4, 1, floor);
        let mut model = new_background_model(&BackgroundConfig::default(), 4, 1);
        let mut mask = GrayImage::new(4, 1);
        while model.is_learning() {
            model.update(&RgiImage::from_rgb(&empty), &mask);
        }
        // Floor, floor at 60 % of its light, a red shirt, floor at 20 % (too dark for a shadow).
        let mut frame = empty.clone();
        frame.put_pixel(1, 0, Rgb([90, 70, 49]));
        frame.put_pixel(2, 0, Rgb([176, 44, 48]));
        frame.put_pixel(3, 0, Rgb([30, 23, 16]));
        let rgi = RgiImage::from_rgb(&frame);
        model.classify(&rgi, &mut mask);
        println!("classified foreground: {:?}", mask.as_raw());
        assert_eq!(mask.as_raw(), &[0, FOREGROUND, FOREGROUND, FOREGROUND]);
        let mut shadows = GrayImage::new(4, 1);
        let count = suppress_shadows(
            &ShadowConfig {
                enabled: true,
                ..ShadowConfig::default()
            },
            model.as_ref(),
            &rgi,
            &mut mask,
            &mut shadows,
        );
        println!(
            "objects {:?}, shadows {:?}",
            mask.as_raw(),
            shadows.as_raw()
        );
        assert_eq!(count, 1);
        assert_eq!(mask.as_raw(), &[0, 0, FOREGROUND, FOREGROUND]);
        assert_eq!(shadows.as_raw(), &[0, FOREGROUND, 0, 0]);
    }
}
