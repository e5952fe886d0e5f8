//! Reading microphone-pair audio from WAV files with hound.
//!
//! Accepted encodings: 8/16/24/32-bit signed integer PCM and 32-bit IEEE float. Integer samples are scaled by
//! 2^(bits-1) so that full scale maps to about [-1, 1]; float samples are taken as they are. Nothing in here
//! panics on a malformed file: every failure becomes a [`MicError`] naming the file.

use std::io::Read;
use std::path::{Path, PathBuf};

use hound::{SampleFormat, WavReader, WavSpec};

use super::audio::StereoAudio;
use super::error::MicError;

/// Upper bound on how many samples are reserved up front: the header's length field is not trusted with the
/// allocation, a corrupt header must not make us reserve gigabytes.
const MAX_PREALLOCATED_SAMPLES: usize = 1 << 22;

/// Reads a two-channel WAV file; channel 1 is microphone 1, channel 2 microphone 2.
pub fn read_stereo_wav(path: impl AsRef<Path>) -> Result<StereoAudio, MicError> {
    let path = path.as_ref();
    let (spec, interleaved) = read_wav_file(path, 2)?;
    let (mic1, mic2) = interleaved
        .chunks_exact(2)
        .map(|pair| (pair[0], pair[1]))
        .unzip();
    StereoAudio::new(spec.sample_rate, mic1, mic2)
}

/// Reads two mono WAV files, one per microphone; they must share sample rate and length.
pub fn read_mono_pair(
    mic1_path: impl AsRef<Path>,
    mic2_path: impl AsRef<Path>,
) -> Result<StereoAudio, MicError> {
    let (first, second) = (mic1_path.as_ref(), mic2_path.as_ref());
    let (first_spec, mic1) = read_wav_file(first, 1)?;
    let (second_spec, mic2) = read_wav_file(second, 1)?;
    if first_spec.sample_rate != second_spec.sample_rate {
        return Err(MicError::SampleRateMismatch {
            first: first.to_path_buf(),
            first_rate: first_spec.sample_rate,
            second: second.to_path_buf(),
            second_rate: second_spec.sample_rate,
        });
    }
    if mic1.len() != mic2.len() {
        return Err(MicError::LengthMismatch {
            first: first.to_path_buf(),
            first_len: mic1.len(),
            second: second.to_path_buf(),
            second_len: mic2.len(),
        });
    }
    StereoAudio::new(first_spec.sample_rate, mic1, mic2)
}

/// Opens `path`, checks it has `channels` channels and returns its spec and interleaved, scaled samples.
fn read_wav_file(path: &Path, channels: u16) -> Result<(WavSpec, Vec<f64>), MicError> {
    let reader = WavReader::open(path).map_err(|source| MicError::WavOpen {
        path: path.to_path_buf(),
        source,
    })?;
    let spec = reader.spec();
    if spec.channels != channels {
        return Err(MicError::ChannelCount {
            path: path.to_path_buf(),
            expected: channels,
            found: spec.channels,
        });
    }
    if spec.sample_rate == 0 {
        return Err(MicError::InvalidSampleRate(0));
    }
    let samples = decode_samples(reader, path.to_path_buf(), spec)?;
    Ok((spec, samples))
}

/// Decodes all samples of an opened reader to f64 in about [-1, 1].
fn decode_samples<R: Read>(
    mut reader: WavReader<R>,
    path: PathBuf,
    spec: WavSpec,
) -> Result<Vec<f64>, MicError> {
    let capacity = (reader.len() as usize).min(MAX_PREALLOCATED_SAMPLES);
    let mut samples = Vec::with_capacity(capacity);
    let read_error = |source| MicError::WavSamples {
        path: path.clone(),
        source,
    };
    match (spec.sample_format, spec.bits_per_sample) {
        (SampleFormat::Int, bits @ 8..=32) => {
            let full_scale = f64::from(1u32 << (bits - 1));
            for sample in reader.samples::<i32>() {
                samples.push(f64::from(sample.map_err(read_error)?) / full_scale);
            }
        }
        (SampleFormat::Float, 32) => {
            for (index, sample) in reader.samples::<f32>().enumerate() {
                let value = f64::from(sample.map_err(read_error)?);
                if !value.is_finite() {
                    return Err(MicError::NonFiniteSample { path, index });
                }
                samples.push(value);
            }
        }
        (format, bits_per_sample) => {
            return Err(MicError::UnsupportedFormat {
                path,
                bits_per_sample,
                format: match format {
                    SampleFormat::Int => "integer",
                    SampleFormat::Float => "float",
                },
            })
        }
    }
    Ok(samples)
}
