//! Background models: learning, classification, selective update, and the configuration.

use frontends::camera::{
    new_background_model, rgb_to_rgi, BackgroundConfig, BackgroundModel, BackgroundModelKind,
    CameraConfig, KdeBackground, KdeConfig, RgiImage, FOREGROUND,
};
use image::{GrayImage, Rgb, RgbImage};

const SIZE: u32 = 8;

fn uniform(colour: [u8; 3]) -> RgiImage {
    RgiImage::from_rgb(&RgbImage::from_pixel(SIZE, SIZE, Rgb(colour)))
}

fn config(model: BackgroundModelKind) -> BackgroundConfig {
    BackgroundConfig {
        model,
        ..BackgroundConfig::default()
    }
}

fn foreground_count(mask: &GrayImage) -> usize {
    mask.iter().filter(|&&p| p == FOREGROUND).count()
}

/// Learns a grey background, then shows a slow brightness ramp (one grey level every second frame,
/// from 100 to 180) and holds the new level for 200 frames, with a red patch standing still in the
/// top-left quarter the whole time. The ramp must be absorbed by the selective update, the standing
/// patch must not, and the old level must have been forgotten outside the patch.
fn check_selective_update(model: BackgroundModelKind) {
    let config = config(model);
    let mut background = new_background_model(&config, SIZE, SIZE);
    let mut mask = GrayImage::new(SIZE, SIZE);
    let mut learned = 0;
    while background.is_learning() {
        background.update(&uniform([100, 100, 100]), &mask);
        learned += 1;
    }
    assert_eq!(learned, 16, "{model:?} learns from 16 frames by default");

    background.classify(&uniform([100, 100, 100]), &mut mask);
    assert_eq!(
        foreground_count(&mask),
        0,
        "{model:?}: the learned scene is background"
    );
    background.classify(&uniform([180, 60, 60]), &mut mask);
    assert_eq!(
        foreground_count(&mask),
        64,
        "{model:?}: a red scene is foreground"
    );

    for step in 1..=360u32 {
        let level = 100 + (step / 2).min(80) as u8;
        let mut frame = RgbImage::from_pixel(SIZE, SIZE, Rgb([level; 3]));
        for y in 0..SIZE / 2 {
            for x in 0..SIZE / 2 {
                frame.put_pixel(x, y, Rgb([180, 60, 60]));
            }
        }
        let frame = RgiImage::from_rgb(&frame);
        background.classify(&frame, &mut mask);
        for y in 0..SIZE {
            for x in 0..SIZE {
                let in_patch = x < SIZE / 2 && y < SIZE / 2;
                let expected = if in_patch { FOREGROUND } else { 0 };
                assert_eq!(
                    mask.get_pixel(x, y)[0],
                    expected,
                    "{model:?}: pixel ({x}, {y}) at level {level}, step {step}"
                );
            }
        }
        background.update(&frame, &mask);
    }
    background.classify(&uniform([100, 100, 100]), &mut mask);
    assert_eq!(
        foreground_count(&mask),
        48,
        "{model:?}: the old level is foreground now outside the never-updated patch"
    );
}

#[test]
fn kde_adapts_to_slow_change_but_not_to_a_standing_object() {
    check_selective_update(BackgroundModelKind::Kde);
}

#[test]
fn running_stats_adapts_to_slow_change_but_not_to_a_standing_object() {
    check_selective_update(BackgroundModelKind::RunningStats);
}

#[test]
fn kde_keeps_several_background_values() {
    // A pixel that flickers between two colours during learning: both are background afterwards,
    // which a single running Gaussian cannot represent.
    let mut background = new_background_model(&config(BackgroundModelKind::Kde), SIZE, SIZE);
    let mask = GrayImage::new(SIZE, SIZE);
    let (dark, light) = ([60, 60, 140], [200, 190, 60]);
    let mut k = 0;
    while background.is_learning() {
        background.update(&uniform(if k % 2 == 0 { dark } else { light }), &mask);
        k += 1;
    }
    let mut out = GrayImage::new(SIZE, SIZE);
    for colour in [dark, light] {
        background.classify(&uniform(colour), &mut out);
        assert_eq!(foreground_count(&out), 0, "{colour:?} is background");
    }
    background.classify(&uniform([130, 125, 100]), &mut out);
    assert_eq!(foreground_count(&out), 64, "the colour between them is not");
}

#[test]
fn configuration_reads_partial_toml_with_defaults() {
    let text = r#"
        [background]
        model = "running_stats"
        kde = { samples = 20 }
        [blobs]
        anchor = "bottom_centre"
        min_area = 50
        [mot_det]
        min_score = -1.5
    "#;
    let config: CameraConfig = toml::from_str(text).expect("parsed");
    assert_eq!(config.background.model, BackgroundModelKind::RunningStats);
    assert_eq!(config.background.kde.samples, 20);
    assert_eq!(config.background.kde.update_interval, 5, "default kept");
    assert_eq!(config.blobs.min_area, 50);
    assert_eq!(config.blobs.cleanup_radius, 1, "default kept");
    assert_eq!(config.mot_det.min_score, -1.5);
    config.validate().expect("valid");

    let empty: CameraConfig = toml::from_str("").expect("parsed");
    assert_eq!(empty, CameraConfig::default());
    assert_eq!(empty.background.model, BackgroundModelKind::Kde);

    let unknown = toml::from_str::<CameraConfig>("[blobs]\nmin_aera = 5\n");
    assert!(unknown.expect_err("typo").to_string().contains("min_aera"));
}

#[test]
fn out_of_range_values_are_refused() {
    let mut config = CameraConfig::default();
    config.background.kde.samples = 0;
    let message = config.validate().expect_err("invalid").to_string();
    assert!(
        message.contains("background.kde.samples must be in 1..=255, got 0"),
        "{message}"
    );

    let mut config = CameraConfig::default();
    config.background.kde.bandwidth_i = -1.0;
    let message = config.validate().expect_err("invalid").to_string();
    assert!(message.contains("background.kde.bandwidth_i"), "{message}");

    let mut config = CameraConfig::default();
    config.background.running_stats.learning_rate = 1.5;
    assert!(frontends::camera::CameraPipeline::new(config).is_err());
}

#[test]
fn kde_likelihood_is_the_normalised_density_of_eq_10() {
    let mut model = KdeBackground::new(&KdeConfig::default(), 4);
    let grey = rgb_to_rgi([100, 100, 100]);
    assert_eq!(model.likelihood(0, grey), None, "nothing learned yet");
    let frame = RgiImage::from_rgb(&RgbImage::from_pixel(2, 2, Rgb([100, 100, 100])));
    model.update(&frame, &GrayImage::new(2, 2));
    assert_eq!(model.likelihood(3, grey), Some(1.0));
    // 8 grey levels brighter is one intensity bandwidth away: exp(-1/2).
    let brighter = rgb_to_rgi([108, 108, 108]);
    let y = model.likelihood(3, brighter).expect("pixel 3 exists");
    assert!((y - (-0.5f32).exp()).abs() < 1e-6, "y = {y}");
    let red = rgb_to_rgi([200, 40, 40]);
    assert!(model.likelihood(0, red).expect("pixel 0 exists") < 1e-6);
    assert_eq!(model.likelihood(4, grey), None, "only 4 pixels");
}
