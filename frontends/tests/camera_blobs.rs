//! Mask clean-up and blob points on hand-drawn masks, and the rgI conversion.

use frontends::camera::{
    clean_mask, rgb_to_rgi, BlobConfig, BlobDetector, PointAnchor, FOREGROUND,
};
use image::{GrayImage, Luma};

fn fill(mask: &mut GrayImage, left: u32, top: u32, width: u32, height: u32) {
    for y in top..top + height {
        for x in left..left + width {
            mask.put_pixel(x, y, Luma([FOREGROUND]));
        }
    }
}

/// A 20 x 30 rectangle at (50, 40) with a pinhole, plus a 2 x 2 speck and a 12 x 12 square.
fn test_mask() -> GrayImage {
    let mut mask = GrayImage::new(160, 120);
    fill(&mut mask, 50, 40, 20, 30);
    mask.put_pixel(60, 55, Luma([0]));
    fill(&mut mask, 120, 10, 2, 2);
    fill(&mut mask, 100, 90, 12, 12);
    mask
}

fn detector(anchor: PointAnchor, min_area: u32) -> BlobDetector {
    BlobDetector::new(BlobConfig {
        anchor,
        min_area,
        ..BlobConfig::default()
    })
}

#[test]
fn opening_removes_specks_and_closing_fills_holes() {
    let mut mask = test_mask();
    clean_mask(&mut mask, 1);
    assert_eq!(mask.get_pixel(60, 55)[0], FOREGROUND, "pinhole filled");
    assert_eq!(mask.get_pixel(120, 10)[0], 0, "speck removed");
    let foreground = mask.iter().filter(|&&p| p == FOREGROUND).count();
    assert_eq!(foreground, 20 * 30 + 12 * 12, "rectangles kept exactly");

    let mut untouched = test_mask();
    clean_mask(&mut untouched, 0);
    assert!(untouched == test_mask(), "radius 0 leaves the mask alone");
}

#[test]
fn blobs_give_the_configured_anchor_point() {
    let mut top = detector(PointAnchor::TopCentre, 100);
    let blobs = top.detect(&mut test_mask());
    assert_eq!(blobs.len(), 2, "the speck is gone, both rectangles stay");
    let rectangle = &blobs[0];
    assert_eq!(rectangle.area, 600);
    assert_eq!(
        (
            rectangle.left,
            rectangle.top,
            rectangle.right,
            rectangle.bottom
        ),
        (50, 40, 70, 70)
    );
    assert_eq!(rectangle.point, [60.0, 40.0]);
    assert_eq!(rectangle.centroid, [60.0, 55.0]);
    assert_eq!(blobs[1].point, [106.0, 90.0]);

    let mut centroid = detector(PointAnchor::Centroid, 100);
    assert_eq!(centroid.detect(&mut test_mask())[0].point, [60.0, 55.0]);
    let mut bottom = detector(PointAnchor::BottomCentre, 100);
    assert_eq!(bottom.detect(&mut test_mask())[0].point, [60.0, 70.0]);
}

#[test]
fn small_blobs_are_dropped() {
    let mut large_only = detector(PointAnchor::TopCentre, 200);
    let blobs = large_only.detect(&mut test_mask());
    assert_eq!(blobs.len(), 1, "the 144-pixel square is below 200");
    assert_eq!(blobs[0].area, 600);
    let empty = large_only.find_blobs(&GrayImage::new(40, 30));
    assert!(empty.is_empty());
}

#[test]
fn head_band_follows_the_top_rows_not_the_whole_blob() {
    // An L: a narrow 6-px-wide "head" column on top of a wide body offset to the right.
    let mut mask = GrayImage::new(100, 100);
    fill(&mut mask, 20, 10, 6, 20);
    fill(&mut mask, 20, 30, 50, 40);
    let blobs = detector(PointAnchor::TopCentre, 100).find_blobs(&mask);
    assert_eq!(blobs.len(), 1);
    assert_eq!(
        blobs[0].point,
        [23.0, 10.0],
        "x of the top rows, not of the body"
    );
    assert!(blobs[0].centroid[0] > 35.0);
}

#[test]
fn rgb_to_rgi_matches_the_definition() {
    assert_eq!(rgb_to_rgi([255, 0, 0]), [255, 0, 85]);
    assert_eq!(
        rgb_to_rgi([0, 0, 0]),
        [85, 85, 0],
        "black gets neutral chromaticity"
    );
    assert_eq!(rgb_to_rgi([255, 255, 255]), [85, 85, 255]);
    // r = 30/180 = 0.1667 -> 42.5 -> 43; g = 60/180 -> 85; I = 60.
    assert_eq!(rgb_to_rgi([30, 60, 90]), [43, 85, 60]);
    // Scaling the brightness keeps the chromaticity.
    let dim = rgb_to_rgi([40, 80, 120]);
    let bright = rgb_to_rgi([80, 160, 240]);
    assert_eq!(dim[..2], bright[..2]);
    assert_eq!((dim[2], bright[2]), (80, 160));
}
