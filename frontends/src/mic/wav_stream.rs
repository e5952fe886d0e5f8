//! Reading two-channel WAV audio as it arrives: a pipe from `arecord -t wav` or `sox ... -t wav -`.
//!
//! hound reads files, where the header's sizes are true. A stream's writer cannot know them when it writes the
//! header, so it puts 0 or 0xFFFFFFFF there (or a size worth hours), which hound refuses or takes as "no
//! samples". This reader parses the RIFF header itself (`fmt ` before `data`, other chunks skipped, padded to
//! even sizes) and then decodes samples piece by piece: a data size of 0, or of 0x7FFF0000 and above, means
//! "until the end of the stream"; a smaller size is obeyed. Samples are scaled exactly as
//! [`super::read_stereo_wav`] scales them (integers by 2^(bits−1), 8-bit unsigned about 128, 32-bit float as
//! is), so a file read either way gives the same samples. Nothing here panics on bad input: a truncated header
//! or garbage is a [`MicError::WavStreamHeader`].

use std::io::{ErrorKind, Read};

use super::error::MicError;

/// Data sizes at or above this (and 0) are a stream writer's "unknown", not a length.
const UNKNOWN_SIZE_FROM: u32 = 0x7FFF_0000;
/// Chunks allowed before `data`: garbage that happens to start with `RIFF....WAVE` ends here.
const MAX_CHUNKS_BEFORE_DATA: usize = 64;
/// Bytes asked for per read: about 30 ms of 16 kHz stereo 16-bit audio, so frames are seen soon after their
/// last sample arrives.
const READ_SIZE: usize = 2048;

/// The sample format a stream's header declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WavStreamFormat {
    /// Samples per second per channel.
    pub sample_rate: u32,
    /// Bits per sample (of its container: 8, 16, 24 or 32).
    pub bits_per_sample: u16,
    /// IEEE float (32 bits) rather than integer PCM.
    pub float: bool,
}

/// A two-channel WAV stream, decoded as its bytes arrive.
pub struct WavStream<R> {
    reader: R,
    format: WavStreamFormat,
    /// Data bytes still to read, or `None` until the end of the stream.
    remaining: Option<u64>,
    /// Bytes read but not yet decoded (an incomplete sample pair).
    carry: Vec<u8>,
    ended: bool,
}

impl<R: Read> WavStream<R> {
    /// Reads the header up to the first sample; refuses anything but two channels of 8/16/24/32-bit integer
    /// or 32-bit float samples.
    pub fn open(mut reader: R) -> Result<Self, MicError> {
        let mut riff = [0u8; 12];
        read_header_bytes(&mut reader, &mut riff, "the RIFF header")?;
        if &riff[0..4] != b"RIFF" || &riff[8..12] != b"WAVE" {
            return Err(header_error("not a WAV stream (no RIFF/WAVE tag)"));
        }
        let mut format = None;
        for _ in 0..MAX_CHUNKS_BEFORE_DATA {
            let mut chunk = [0u8; 8];
            read_header_bytes(&mut reader, &mut chunk, "a chunk header")?;
            let size = u32::from_le_bytes([chunk[4], chunk[5], chunk[6], chunk[7]]);
            match &chunk[0..4] {
                b"fmt " => format = Some(read_fmt(&mut reader, size)?),
                b"data" => {
                    let format = format.ok_or_else(|| header_error("`data` before `fmt `"))?;
                    let remaining =
                        (size != 0 && size < UNKNOWN_SIZE_FROM).then_some(u64::from(size));
                    return Ok(Self {
                        reader,
                        format,
                        remaining,
                        carry: Vec::new(),
                        ended: false,
                    });
                }
                _ => skip(&mut reader, u64::from(size) + u64::from(size & 1))?,
            }
        }
        Err(header_error("no `data` chunk among the first chunks"))
    }

    /// The declared sample format.
    pub fn format(&self) -> WavStreamFormat {
        self.format
    }

    /// Bytes per sample pair (both channels).
    fn pair_bytes(&self) -> usize {
        2 * usize::from(self.format.bits_per_sample / 8)
    }

    /// Waits for the next bytes and appends the whole sample pairs among them to `mic1` and `mic2`; returns how
    /// many pairs were appended, 0 at the end of the stream (or of the declared data).
    pub fn read_pairs(
        &mut self,
        mic1: &mut Vec<f64>,
        mic2: &mut Vec<f64>,
    ) -> Result<usize, MicError> {
        let mut buffer = [0u8; READ_SIZE];
        while !self.ended {
            let want = self
                .remaining
                .map_or(READ_SIZE, |left| left.min(READ_SIZE as u64) as usize);
            if want == 0 {
                self.ended = true;
                break;
            }
            let read = match self.reader.read(&mut buffer[..want]) {
                Ok(0) => {
                    self.ended = true;
                    break;
                }
                Ok(read) => read,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => return Err(MicError::WavStreamRead(e)),
            };
            if let Some(left) = &mut self.remaining {
                *left -= read as u64;
            }
            self.carry.extend_from_slice(&buffer[..read]);
            let pairs = self.decode_carry(mic1, mic2);
            if pairs > 0 {
                return Ok(pairs);
            }
        }
        Ok(0)
    }

    /// Bytes of an incomplete sample pair left at the end of the stream (a writer cut off mid-sample).
    pub fn leftover_bytes(&self) -> usize {
        self.carry.len()
    }

    /// Decodes the whole pairs of `carry`, keeping the incomplete rest.
    fn decode_carry(&mut self, mic1: &mut Vec<f64>, mic2: &mut Vec<f64>) -> usize {
        let pair_bytes = self.pair_bytes();
        let half = pair_bytes / 2;
        let whole = self.carry.len() / pair_bytes * pair_bytes;
        for pair in self.carry[..whole].chunks_exact(pair_bytes) {
            mic1.push(decode_sample(&pair[..half], self.format));
            mic2.push(decode_sample(&pair[half..], self.format));
        }
        self.carry.drain(..whole);
        whole / pair_bytes
    }
}

/// Parses a `fmt ` chunk of `size` bytes (PCM, IEEE float or extensible), consuming it with its padding.
fn read_fmt(reader: &mut impl Read, size: u32) -> Result<WavStreamFormat, MicError> {
    if !(16..=1024).contains(&size) {
        return Err(header_error(&format!("`fmt ` chunk of {size} bytes")));
    }
    let mut fmt = vec![0u8; size as usize + (size & 1) as usize];
    read_header_bytes(reader, &mut fmt, "the `fmt ` chunk")?;
    let u16_at = |i: usize| u16::from_le_bytes([fmt[i], fmt[i + 1]]);
    let mut tag = u16_at(0);
    if tag == 0xFFFE {
        if size < 26 {
            return Err(header_error("extensible `fmt ` chunk too short"));
        }
        // The sub-format GUID starts with the plain format tag.
        tag = u16_at(24);
    }
    let channels = u16_at(2);
    let sample_rate = u32::from_le_bytes([fmt[4], fmt[5], fmt[6], fmt[7]]);
    let bits_per_sample = u16_at(14);
    if channels != 2 {
        return Err(header_error(&format!(
            "expected 2 channels, found {channels}"
        )));
    }
    if sample_rate == 0 {
        return Err(MicError::InvalidSampleRate(0));
    }
    let float = match (tag, bits_per_sample) {
        (1, 8 | 16 | 24 | 32) => false,
        (3, 32) => true,
        _ => {
            return Err(header_error(&format!(
                "format tag {tag} with {bits_per_sample} bits per sample is not supported (integer PCM of 8, 16, 24 or 32 bits, or 32-bit float)"
            )))
        }
    };
    Ok(WavStreamFormat {
        sample_rate,
        bits_per_sample,
        float,
    })
}

/// One little-endian sample of `format` scaled to about [−1, 1], as hound and `read_stereo_wav` scale it.
fn decode_sample(bytes: &[u8], format: WavStreamFormat) -> f64 {
    if format.float {
        let value = f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        // A non-finite sample would poison the FFT; silence is the least harmful stand-in.
        return if value.is_finite() {
            f64::from(value)
        } else {
            0.0
        };
    }
    let bits = u32::from(format.bits_per_sample);
    let value = match bits {
        // 8-bit WAV is unsigned, centred on 128.
        8 => i32::from(bytes[0]) - 128,
        _ => {
            let mut word = [0u8; 4];
            word[4 - bytes.len()..].copy_from_slice(bytes);
            // Shifting right from the top sign-extends the narrower sample.
            i32::from_le_bytes([word[0], word[1], word[2], word[3]]) >> (32 - bits)
        }
    };
    f64::from(value) / f64::from(1u32 << (bits - 1))
}

/// Reads exactly `buffer.len()` header bytes; an early end is a truncated header.
fn read_header_bytes(
    reader: &mut impl Read,
    buffer: &mut [u8],
    what: &str,
) -> Result<(), MicError> {
    reader.read_exact(buffer).map_err(|e| match e.kind() {
        ErrorKind::UnexpectedEof => {
            header_error(&format!("truncated header: the stream ended in {what}"))
        }
        _ => MicError::WavStreamRead(e),
    })
}

/// Discards `count` bytes of a chunk this reader does not use.
fn skip(reader: &mut impl Read, count: u64) -> Result<(), MicError> {
    let copied = std::io::copy(&mut reader.take(count), &mut std::io::sink())
        .map_err(MicError::WavStreamRead)?;
    if copied < count {
        return Err(header_error(
            "truncated header: the stream ended in a chunk before `data`",
        ));
    }
    Ok(())
}

/// A [`MicError::WavStreamHeader`] saying `what`.
fn header_error(what: &str) -> MicError {
    MicError::WavStreamHeader(what.to_owned())
}
