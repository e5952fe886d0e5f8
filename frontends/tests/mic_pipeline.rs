//! The mic-pair configuration (serde, defaults, validation) and the pipeline's framing, stamps and input checks.

use frontends::mic::{MicError, MicPairConfig, MicPairPipeline, StereoAudio};

const RATE: u32 = 16_000;

#[test]
fn a_config_with_only_the_mic_distance_takes_the_documented_defaults() {
    let config: MicPairConfig = toml::from_str("mic_distance = 0.5").unwrap();
    assert_eq!(config, MicPairConfig::new(0.5));
    assert_eq!(config.speed_of_sound, 343.0);
    assert_eq!(config.frame_duration, 0.256);
    assert_eq!(config.hop_duration, None);
    assert_eq!(config.interpolation, 8);
    assert_eq!(config.max_peaks, 3);
    assert_eq!(config.peak_threshold, 0.07);
    assert_eq!(config.relative_peak_threshold, 0.9);
    assert_eq!(config.pooling_time_constant, 0.0);
    assert!(config.noise_by_peak_height);
    assert_eq!(config.min_frequency, 100.0);
    assert_eq!(config.max_frequency, None);
    assert_eq!(config.median_gate, 2.0);
    assert_eq!(config.min_spectral_contrast, 1.25);
    assert!((config.max_tdoa() - 0.5 / 343.0).abs() < 1e-15);
}

#[test]
fn every_field_can_be_set_and_unknown_or_missing_fields_are_rejected() {
    let config: MicPairConfig = toml::from_str(
        "mic_distance = 0.3\nspeed_of_sound = 340.0\nframe_duration = 0.128\nhop_duration = 0.064\n\
         interpolation = 4\nmax_peaks = 2\npeak_threshold = 0.2\nmin_frequency = 300.0\n\
         max_frequency = 4000.0\nphat_floor = 1e-6\nmedian_gate = 0.0\nmin_spectral_contrast = 0.0\n\
         relative_peak_threshold = 0.5\nnoise_by_peak_height = false",
    )
    .unwrap();
    assert_eq!(config.hop_duration, Some(0.064));
    assert_eq!(config.max_frequency, Some(4000.0));
    assert_eq!(config.max_peaks, 2);
    assert_eq!(config.relative_peak_threshold, 0.5);
    assert!(!config.noise_by_peak_height);
    config.validate().unwrap();

    let misspelt = toml::from_str::<MicPairConfig>("mic_distance = 0.5\nmax_peak = 3").unwrap_err();
    assert!(misspelt.to_string().contains("max_peak"), "{misspelt}");
    let missing = toml::from_str::<MicPairConfig>("max_peaks = 3").unwrap_err();
    assert!(missing.to_string().contains("mic_distance"), "{missing}");
}

/// Turns a valid configuration into one invalid in a single field.
type Spoiler = fn(&mut MicPairConfig);

#[test]
fn out_of_range_values_are_rejected_with_the_field_named() {
    let cases: [(&str, Spoiler); 10] = [
        ("mic_distance", |c| c.mic_distance = 0.0),
        ("speed_of_sound", |c| c.speed_of_sound = f64::NAN),
        ("frame_duration", |c| c.frame_duration = -1.0),
        ("hop_duration", |c| c.hop_duration = Some(0.0)),
        ("interpolation", |c| c.interpolation = 0),
        ("max_peaks", |c| c.max_peaks = 0),
        ("peak_threshold", |c| c.peak_threshold = -0.1),
        ("phat_floor", |c| c.phat_floor = 1.0),
        ("relative_peak_threshold", |c| {
            c.relative_peak_threshold = f64::NAN
        }),
        ("relative_peak_threshold", |c| {
            c.relative_peak_threshold = 1.5
        }),
    ];
    for (field, spoil) in cases {
        let mut config = MicPairConfig::new(0.5);
        spoil(&mut config);
        let error = MicPairPipeline::new(config, RATE)
            .err()
            .expect("invalid config accepted");
        assert!(
            matches!(&error, MicError::InvalidConfig { field: f, .. } if *f == field),
            "{field}: {error:?}"
        );
        println!("{error}");
    }
}

#[test]
fn frames_too_short_for_the_lag_range_or_an_empty_band_are_rejected() {
    let mut short_frames = MicPairConfig::new(0.5);
    short_frames.frame_duration = 0.004; // 64 samples for lags up to 23
    short_frames.segment_duration = 0.0; // the whole frame at once
    assert!(matches!(
        MicPairPipeline::new(short_frames, RATE),
        Err(MicError::InvalidConfig {
            field: "frame_duration",
            ..
        })
    ));
    let mut short_segments = MicPairConfig::new(0.5);
    short_segments.segment_duration = 0.004;
    assert!(matches!(
        MicPairPipeline::new(short_segments, RATE),
        Err(MicError::InvalidConfig {
            field: "segment_duration",
            ..
        })
    ));
    let mut long_segments = MicPairConfig::new(0.5);
    long_segments.segment_duration = 0.5;
    assert!(matches!(
        MicPairPipeline::new(long_segments, RATE),
        Err(MicError::InvalidConfig {
            field: "segment_duration",
            ..
        })
    ));
    let mut empty_band = MicPairConfig::new(0.5);
    empty_band.min_frequency = 5000.0;
    empty_band.max_frequency = Some(4000.0);
    assert!(matches!(
        MicPairPipeline::new(empty_band, RATE),
        Err(MicError::InvalidConfig {
            field: "min_frequency",
            ..
        })
    ));
    assert!(matches!(
        MicPairPipeline::new(MicPairConfig::new(0.5), 0),
        Err(MicError::InvalidSampleRate(0))
    ));
    // A corrupt header's sample rate must not make the pipeline allocate gigabytes.
    assert!(matches!(
        MicPairPipeline::new(MicPairConfig::new(0.5), u32::MAX),
        Err(MicError::InvalidConfig {
            field: "frame_duration",
            ..
        })
    ));
}

#[test]
fn overlapping_frames_are_stamped_at_their_centres() {
    let mut config = MicPairConfig::new(0.5);
    config.hop_duration = Some(0.128);
    let mut pipeline = MicPairPipeline::new(config, RATE).unwrap();
    assert_eq!(pipeline.layout().frame_len(), 4096);
    assert_eq!(pipeline.layout().hop(), 2048);
    // One second: whole frames start at 0, 2048, …, 10240 (10240 + 4096 ≤ 16000 < 12288 + 4096).
    let audio = StereoAudio::new(RATE, vec![0.0; 16_000], vec![0.0; 16_000]).unwrap();
    let frames = pipeline.process(&audio, 1000.0).unwrap();
    let stamps: Vec<f64> = frames.iter().map(|f| f.stamp).collect();
    let expected: Vec<f64> = (0..6).map(|k| 1000.0 + 0.128 + 0.128 * k as f64).collect();
    assert_eq!(stamps.len(), expected.len());
    for (stamp, want) in stamps.iter().zip(&expected) {
        assert!((stamp - want).abs() < 1e-9, "{stamp} vs {want}");
    }
}

#[test]
fn mismatched_audio_is_an_error_not_a_panic() {
    let mut pipeline = MicPairPipeline::new(MicPairConfig::new(0.5), RATE).unwrap();
    let at_48k = StereoAudio::new(48_000, vec![0.0; 48_000], vec![0.0; 48_000]).unwrap();
    assert!(matches!(
        pipeline.process(&at_48k, 0.0),
        Err(MicError::PipelineRateMismatch {
            expected: 16_000,
            actual: 48_000
        })
    ));
    let audio = StereoAudio::new(RATE, vec![0.0; 5000], vec![0.0; 5000]).unwrap();
    assert!(matches!(
        pipeline.process(&audio, f64::INFINITY),
        Err(MicError::NonFiniteStartTime(_))
    ));
    assert!(matches!(
        pipeline.frame_peaks(&[0.0; 4096], &[0.0; 4000]),
        Err(MicError::FrameLength {
            expected: 4096,
            mic1: 4096,
            mic2: 4000
        })
    ));
    // Shorter than one frame: no frames, no error.
    let short = StereoAudio::new(RATE, vec![0.1; 100], vec![0.1; 100]).unwrap();
    assert!(pipeline.process(&short, 0.0).unwrap().is_empty());
}
