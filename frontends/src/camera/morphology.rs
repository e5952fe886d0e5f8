//! Clean-up of a binary foreground mask: an opening (erode, dilate) removes specks smaller than the
//! structuring element, then a closing (dilate, erode) fills holes and gaps inside objects, e.g. where
//! a person's clothing happens to match the background.

use image::GrayImage;
use imageproc::distance_transform::Norm;
use imageproc::morphology::{close_mut, open_mut};

/// Opens then closes `mask` in place with a (2 `radius` + 1)-pixel square structuring element
/// (the L-infinity ball of radius `radius`); radius 0 leaves the mask unchanged.
pub fn clean_mask(mask: &mut GrayImage, radius: u8) {
    if radius == 0 {
        return;
    }
    open_mut(mask, Norm::LInf, radius);
    close_mut(mask, Norm::LInf, radius);
}
