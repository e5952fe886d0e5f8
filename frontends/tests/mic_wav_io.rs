//! Reading microphone-pair audio from WAV files: round trips through hound for every supported encoding, and
//! clear errors (naming the file) for malformed or mismatched input.

use std::path::{Path, PathBuf};

use frontends::mic::{read_mono_pair, read_stereo_wav, MicError, MicPairConfig, MicPairPipeline};
use hound::{SampleFormat, WavSpec, WavWriter};
use tempfile::TempDir;

const RATE: u32 = 16_000;

fn spec(
    channels: u16,
    bits_per_sample: u16,
    sample_format: SampleFormat,
    sample_rate: u32,
) -> WavSpec {
    WavSpec {
        channels,
        sample_rate,
        bits_per_sample,
        sample_format,
    }
}

/// A deterministic test tone in [-0.9, 0.9], different on the two channels.
fn tone(len: usize, channel: usize) -> Vec<f64> {
    (0..len)
        .map(|i| 0.9 * (i as f64 * 0.05 * (channel + 1) as f64).sin())
        .collect()
}

/// Writes interleaved channels with the given encoding; integer samples are full-scale quantised.
fn write_wav(path: &Path, spec: WavSpec, channels: &[Vec<f64>]) {
    let mut writer = WavWriter::create(path, spec).unwrap();
    let full_scale = f64::from(1u32 << (spec.bits_per_sample - 1));
    for i in 0..channels[0].len() {
        for channel in channels {
            match spec.sample_format {
                SampleFormat::Int => writer
                    .write_sample((channel[i] * full_scale).round() as i32)
                    .unwrap(),
                SampleFormat::Float => writer.write_sample(channel[i] as f32).unwrap(),
            }
        }
    }
    writer.finalize().unwrap();
}

fn temp_path(dir: &TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

#[test]
fn stereo_round_trip_in_every_supported_encoding() {
    let dir = TempDir::new().unwrap();
    let channels = [tone(1000, 0), tone(1000, 1)];
    let encodings = [
        (8, SampleFormat::Int),
        (16, SampleFormat::Int),
        (24, SampleFormat::Int),
        (32, SampleFormat::Int),
        (32, SampleFormat::Float),
    ];
    for (bits, format) in encodings {
        let path = temp_path(&dir, &format!("stereo_{bits}_{format:?}.wav"));
        write_wav(&path, spec(2, bits, format, RATE), &channels);
        let audio = read_stereo_wav(&path).unwrap();
        assert_eq!(audio.sample_rate(), RATE);
        assert_eq!(audio.len(), 1000);
        // Half a quantisation step, or float rounding.
        let tolerance = match format {
            SampleFormat::Int => 0.5 / f64::from(1u32 << (bits - 1)) + 1e-12,
            SampleFormat::Float => 1e-7,
        };
        for (read, written) in [(audio.mic1(), &channels[0]), (audio.mic2(), &channels[1])] {
            let worst = read
                .iter()
                .zip(written)
                .map(|(r, w)| (r - w).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= tolerance,
                "{bits}-bit {format:?}: error {worst} > {tolerance}"
            );
        }
        println!("{bits}-bit {format:?}: round trip within {tolerance:.2e}");
    }
}

#[test]
fn two_mono_files_make_one_pair() {
    let dir = TempDir::new().unwrap();
    let (first, second) = (temp_path(&dir, "mic1.wav"), temp_path(&dir, "mic2.wav"));
    write_wav(
        &first,
        spec(1, 16, SampleFormat::Int, RATE),
        &[tone(500, 0)],
    );
    write_wav(
        &second,
        spec(1, 32, SampleFormat::Float, RATE),
        &[tone(500, 1)],
    );
    let audio = read_mono_pair(&first, &second).unwrap();
    assert_eq!(audio.len(), 500);
    assert!((audio.mic1()[10] - tone(500, 0)[10]).abs() < 1e-4);
    assert!((audio.mic2()[10] - tone(500, 1)[10]).abs() < 1e-7);
}

#[test]
fn a_delay_written_to_a_wav_file_comes_back_as_a_positive_tdoa() {
    // Channel 2 is channel 1 delayed by 4 samples: the sound reaches mic 2 later, tau = +4 samples.
    let dir = TempDir::new().unwrap();
    let path = temp_path(&dir, "delayed.wav");
    let mut state = 12345u64;
    let noise: Vec<f64> = (0..8200)
        .map(|_| {
            // A small LCG keeps this test free of RNG crates; its low-order patterns do not matter here.
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.5
        })
        .collect();
    let delayed: Vec<f64> = (0..8200)
        .map(|i| if i >= 4 { noise[i - 4] } else { 0.0 })
        .collect();
    write_wav(
        &path,
        spec(2, 16, SampleFormat::Int, RATE),
        &[noise, delayed],
    );
    let audio = read_stereo_wav(&path).unwrap();
    let mut config = MicPairConfig::new(0.5);
    config.min_spectral_contrast = 0.0; // the test signal is white noise
    let mut pipeline = MicPairPipeline::new(config, RATE).unwrap();
    let frames = pipeline.process(&audio, 100.0).unwrap();
    assert_eq!(frames.len(), 2);
    assert!((frames[0].stamp - 100.128).abs() < 1e-9);
    assert!(
        (frames[0].tdoas[0] * f64::from(RATE) - 4.0).abs() < 0.05,
        "{:?}",
        frames[0].tdoas
    );
}

/// The message of `error` names `path`.
fn assert_names(error: &MicError, path: &Path) {
    let message = error.to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(
        message.contains(name.as_ref()),
        "message {message:?} does not name {name}"
    );
    println!("{message}");
}

#[test]
fn truncated_files_are_errors_naming_the_file() {
    let dir = TempDir::new().unwrap();
    let path = temp_path(&dir, "truncated.wav");
    write_wav(
        &path,
        spec(2, 16, SampleFormat::Int, RATE),
        &[tone(1000, 0), tone(1000, 1)],
    );
    let bytes = std::fs::read(&path).unwrap();

    // Cut inside the sample data: the header promises more samples than there are.
    std::fs::write(&path, &bytes[..bytes.len() / 2 + 1]).unwrap();
    let error = read_stereo_wav(&path).unwrap_err();
    assert!(matches!(error, MicError::WavSamples { .. }), "{error:?}");
    assert_names(&error, &path);

    // Cut inside the header.
    std::fs::write(&path, &bytes[..30]).unwrap();
    let error = read_stereo_wav(&path).unwrap_err();
    assert!(matches!(error, MicError::WavOpen { .. }), "{error:?}");
    assert_names(&error, &path);
}

#[test]
fn garbage_and_missing_files_are_errors_naming_the_file() {
    let dir = TempDir::new().unwrap();
    let garbage = temp_path(&dir, "garbage.wav");
    std::fs::write(&garbage, b"this is not a RIFF file at all, just text").unwrap();
    let error = read_stereo_wav(&garbage).unwrap_err();
    assert!(matches!(error, MicError::WavOpen { .. }), "{error:?}");
    assert_names(&error, &garbage);

    let missing = temp_path(&dir, "missing.wav");
    let error = read_stereo_wav(&missing).unwrap_err();
    assert_names(&error, &missing);
}

#[test]
fn wrong_channel_counts_are_errors() {
    let dir = TempDir::new().unwrap();
    let mono = temp_path(&dir, "mono.wav");
    write_wav(&mono, spec(1, 16, SampleFormat::Int, RATE), &[tone(100, 0)]);
    let error = read_stereo_wav(&mono).unwrap_err();
    assert!(
        matches!(
            error,
            MicError::ChannelCount {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, &mono);

    let stereo = temp_path(&dir, "stereo.wav");
    write_wav(
        &stereo,
        spec(2, 16, SampleFormat::Int, RATE),
        &[tone(100, 0), tone(100, 1)],
    );
    let error = read_mono_pair(&mono, &stereo).unwrap_err();
    assert!(
        matches!(
            error,
            MicError::ChannelCount {
                expected: 1,
                found: 2,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, &stereo);
}

#[test]
fn mono_pairs_with_different_rates_or_lengths_are_errors() {
    let dir = TempDir::new().unwrap();
    let (at_16k, at_48k, short) = (
        temp_path(&dir, "rate16k.wav"),
        temp_path(&dir, "rate48k.wav"),
        temp_path(&dir, "short.wav"),
    );
    write_wav(
        &at_16k,
        spec(1, 16, SampleFormat::Int, 16_000),
        &[tone(400, 0)],
    );
    write_wav(
        &at_48k,
        spec(1, 16, SampleFormat::Int, 48_000),
        &[tone(400, 1)],
    );
    write_wav(
        &short,
        spec(1, 16, SampleFormat::Int, 16_000),
        &[tone(300, 1)],
    );

    let error = read_mono_pair(&at_16k, &at_48k).unwrap_err();
    assert!(
        matches!(
            error,
            MicError::SampleRateMismatch {
                first_rate: 16_000,
                second_rate: 48_000,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, &at_16k);
    assert_names(&error, &at_48k);

    let error = read_mono_pair(&at_16k, &short).unwrap_err();
    assert!(
        matches!(
            error,
            MicError::LengthMismatch {
                first_len: 400,
                second_len: 300,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, &short);
}

#[test]
fn non_finite_float_samples_are_errors() {
    let dir = TempDir::new().unwrap();
    let path = temp_path(&dir, "nan.wav");
    let mut channel = tone(100, 0);
    channel[7] = f64::NAN;
    write_wav(
        &path,
        spec(2, 32, SampleFormat::Float, RATE),
        &[tone(100, 1), channel],
    );
    let error = read_stereo_wav(&path).unwrap_err();
    assert!(
        matches!(error, MicError::NonFiniteSample { index: 15, .. }),
        "{error:?}"
    );
    assert_names(&error, &path);
}
