//! The one error type of the microphone-pair front end.

use std::path::PathBuf;

/// Everything that can go wrong while reading audio or estimating TDOAs.
///
/// Every variant that concerns a file names it, so that a message alone tells an operator which file to fix.
#[derive(Debug, thiserror::Error)]
pub enum MicError {
    /// The file could not be opened or its WAV header could not be parsed.
    #[error("cannot open WAV file {}: {source}", path.display())]
    WavOpen {
        /// The offending file.
        path: PathBuf,
        /// What hound reported.
        #[source]
        source: hound::Error,
    },
    /// The header was fine but the sample data could not be read (typically a truncated file).
    #[error("cannot read the samples of WAV file {} (truncated or corrupt data?): {source}", path.display())]
    WavSamples {
        /// The offending file.
        path: PathBuf,
        /// What hound reported.
        #[source]
        source: hound::Error,
    },
    /// The file has a different number of channels than the caller asked for.
    #[error("WAV file {}: expected {expected} channel(s), found {found}", path.display())]
    ChannelCount {
        /// The offending file.
        path: PathBuf,
        /// The number of channels required.
        expected: u16,
        /// The number of channels in the file.
        found: u16,
    },
    /// The sample encoding is not one this front end reads.
    #[error(
        "WAV file {}: unsupported sample format ({bits_per_sample}-bit {format}); \
         supported are 8/16/24/32-bit integer and 32-bit float",
        path.display()
    )]
    UnsupportedFormat {
        /// The offending file.
        path: PathBuf,
        /// Bits per sample declared in the header.
        bits_per_sample: u16,
        /// "integer" or "float".
        format: &'static str,
    },
    /// A float sample is NaN or infinite.
    #[error("WAV file {}: sample {index} is not a finite number", path.display())]
    NonFiniteSample {
        /// The offending file.
        path: PathBuf,
        /// Index of the sample, counted over all channels (interleaved).
        index: usize,
    },
    /// Two mono files that should form a pair have different sample rates.
    #[error(
        "WAV files {} ({first_rate} Hz) and {} ({second_rate} Hz) have different sample rates",
        first.display(),
        second.display()
    )]
    SampleRateMismatch {
        /// The file for microphone 1.
        first: PathBuf,
        /// Its sample rate in Hz.
        first_rate: u32,
        /// The file for microphone 2.
        second: PathBuf,
        /// Its sample rate in Hz.
        second_rate: u32,
    },
    /// Two mono files that should form a pair have different lengths.
    #[error(
        "WAV files {} ({first_len} samples) and {} ({second_len} samples) have different lengths",
        first.display(),
        second.display()
    )]
    LengthMismatch {
        /// The file for microphone 1.
        first: PathBuf,
        /// Its number of samples.
        first_len: usize,
        /// The file for microphone 2.
        second: PathBuf,
        /// Its number of samples.
        second_len: usize,
    },
    /// In-memory audio whose two channels differ in length.
    #[error("audio channels differ in length: mic 1 has {mic1} samples, mic 2 has {mic2}")]
    ChannelLengthMismatch {
        /// Samples of microphone 1.
        mic1: usize,
        /// Samples of microphone 2.
        mic2: usize,
    },
    /// In-memory audio holds a NaN or infinite sample.
    #[error("audio sample {index} of mic {mic} is not a finite number")]
    NonFiniteAudio {
        /// 1 or 2.
        mic: u8,
        /// Index of the sample in that channel.
        index: usize,
    },
    /// A sample rate of zero.
    #[error("sample rate must be positive, got {0} Hz")]
    InvalidSampleRate(u32),
    /// Audio handed to a pipeline built for another sample rate.
    #[error("audio sampled at {actual} Hz given to a pipeline built for {expected} Hz")]
    PipelineRateMismatch {
        /// The pipeline's sample rate.
        expected: u32,
        /// The audio's sample rate.
        actual: u32,
    },
    /// A single frame of the wrong length handed to the pipeline.
    #[error(
        "frame of {mic1} / {mic2} samples (mic 1 / mic 2) given, the pipeline expects {expected}"
    )]
    FrameLength {
        /// The frame length the pipeline was built for.
        expected: usize,
        /// Samples given for microphone 1.
        mic1: usize,
        /// Samples given for microphone 2.
        mic2: usize,
    },
    /// A start time that is NaN or infinite.
    #[error("start time must be a finite number of seconds, got {0}")]
    NonFiniteStartTime(f64),
    /// A configuration value out of its valid range.
    #[error("invalid mic-pair configuration: `{field}` {reason}")]
    InvalidConfig {
        /// The configuration field at fault.
        field: &'static str,
        /// Why it was rejected.
        reason: String,
    },
    /// realfft refused a buffer; this indicates a bug in the buffer sizing, not bad input.
    #[error("internal FFT error: {0}")]
    Fft(String),
    /// A WAV stream whose header is truncated, is not RIFF/WAVE, or describes audio that cannot be analysed.
    #[error("WAV stream: {0}")]
    WavStreamHeader(String),
    /// Reading a WAV stream failed (not its end, which is a normal end of the stream).
    #[error("WAV stream: reading failed: {0}")]
    WavStreamRead(std::io::Error),
}
