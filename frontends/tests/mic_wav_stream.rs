//! The streaming WAV reader decodes exactly the samples hound decodes, accepts a stream writer's unknown
//! sizes, and refuses truncated headers and garbage without panicking.

use std::io::Cursor;

use frontends::mic::{read_stereo_wav, MicError, WavStream};

/// A stereo WAV of a ramp in `spec`'s format.
fn wav_bytes(spec: hound::WavSpec, pairs: usize) -> Vec<u8> {
    let mut bytes = Cursor::new(Vec::new());
    let mut writer = hound::WavWriter::new(&mut bytes, spec).unwrap();
    for n in 0..pairs {
        let x = ((n * 37) % 200) as f64 / 100.0 - 1.0;
        match (spec.sample_format, spec.bits_per_sample) {
            (hound::SampleFormat::Float, _) => {
                writer.write_sample(x as f32).unwrap();
                writer.write_sample(-x as f32).unwrap();
            }
            (_, bits) => {
                let scale = f64::from((1u32 << (bits - 1)) - 1);
                writer.write_sample((x * scale) as i32).unwrap();
                writer.write_sample((-x * scale) as i32).unwrap();
            }
        }
    }
    writer.finalize().unwrap();
    bytes.into_inner()
}

/// Every sample pair of a stream, read piece by piece.
fn stream_samples(bytes: &[u8]) -> Result<(Vec<f64>, Vec<f64>), MicError> {
    let mut stream = WavStream::open(bytes)?;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    while stream.read_pairs(&mut a, &mut b)? > 0 {}
    Ok((a, b))
}

#[test]
fn the_stream_reader_gives_hounds_samples_for_every_format() {
    let dir = tempfile::tempdir().unwrap();
    for (bits, format) in [
        (8, hound::SampleFormat::Int),
        (16, hound::SampleFormat::Int),
        (24, hound::SampleFormat::Int),
        (32, hound::SampleFormat::Int),
        (32, hound::SampleFormat::Float),
    ] {
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: 16_000,
            bits_per_sample: bits,
            sample_format: format,
        };
        let bytes = wav_bytes(spec, 3000);
        let path = dir.path().join(format!("{bits}.wav"));
        std::fs::write(&path, &bytes).unwrap();
        let file = read_stereo_wav(&path).unwrap();
        let (a, b) = stream_samples(&bytes).unwrap();
        assert_eq!(a, file.mic1(), "{bits} bits {format:?}");
        assert_eq!(b, file.mic2(), "{bits} bits {format:?}");
    }
}

#[test]
fn unknown_sizes_mean_until_the_end_of_the_stream() {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: 16_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let bytes = wav_bytes(spec, 1000);
    let data = bytes.windows(4).position(|w| w == b"data").unwrap();
    for size in [0u32, u32::MAX] {
        let mut stream = bytes.clone();
        stream[4..8].copy_from_slice(&size.to_le_bytes());
        stream[data + 4..data + 8].copy_from_slice(&size.to_le_bytes());
        let (a, _) = stream_samples(&stream).unwrap();
        assert_eq!(a.len(), 1000, "size field {size:#x}");
    }
}

#[test]
fn truncated_headers_and_garbage_are_errors() {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: 16_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let bytes = wav_bytes(spec, 10);
    for cut in 0..44 {
        assert!(
            matches!(
                WavStream::open(&bytes[..cut]),
                Err(MicError::WavStreamHeader(_))
            ),
            "cut at {cut}"
        );
    }
    let garbage: Vec<u8> = (0..4000u32).map(|i| (i * 7919 % 251) as u8).collect();
    assert!(WavStream::open(&garbage[..]).is_err());
    let mono = wav_bytes(
        hound::WavSpec {
            channels: 1,
            ..spec
        },
        10,
    );
    assert!(WavStream::open(&mono[..]).is_err());
}
