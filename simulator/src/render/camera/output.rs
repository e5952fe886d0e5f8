//! Rendered frames to where the camera agent and `ffmpeg` read them: a directory of PNG frames
//! (`edge-agent camera --frames DIR`, stamped by `--fps` and `--start`), a YUV4MPEG2 stream
//! (`ffmpeg -f yuv4mpegpipe -i -`, and `edge-agent camera --video -` through ffmpeg) and raw RGB
//! (`ffmpeg -f rawvideo -pix_fmt rgb24 -video_size WxH -framerate F -i -`, lossless).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use image::RgbImage;

use super::CameraRenderer;
use crate::sensor_spec::SensorSpec;

/// What [`write_frame_directory`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedFrames {
    /// The frame files, in order (`000000.png`, `000001.png`, …).
    pub paths: Vec<PathBuf>,
    /// The scenario time of each frame, s.
    pub times: Vec<f64>,
}

/// The scenario times of a camera's frames in `[from_s, to_s)`, on its own clock (`phase_s + k /
/// rate_hz`, with `k` negative before the scenario's start: a camera that runs before anybody is in).
pub fn frame_times(spec: &SensorSpec, from_s: f64, to_s: f64) -> Vec<f64> {
    let time = |k: i64| spec.phase_s + k as f64 / spec.rate_hz;
    let mut k = ((from_s - spec.phase_s) * spec.rate_hz).floor() as i64;
    while time(k) < from_s {
        k += 1;
    }
    let mut times = Vec::new();
    while time(k) < to_s {
        times.push(time(k));
        k += 1;
    }
    times
}

/// Renders the frames of `spec`'s camera taken in `[from_s, to_s)` into `dir` as PNG files named
/// by their index from 0, the form `edge-agent camera --frames` reads.
pub fn write_frame_directory(
    renderer: &mut CameraRenderer,
    spec: &SensorSpec,
    from_s: f64,
    to_s: f64,
    dir: &Path,
) -> Result<RenderedFrames, image::ImageError> {
    std::fs::create_dir_all(dir)?;
    let [width, height] = renderer.size();
    let mut image = RgbImage::new(width, height);
    let times = frame_times(spec, from_s, to_s);
    let mut paths = Vec::with_capacity(times.len());
    for (index, &t) in times.iter().enumerate() {
        renderer.render_into(t, &mut image);
        let path = dir.join(format!("{index:06}.png"));
        image.save(&path)?;
        paths.push(path);
    }
    Ok(RenderedFrames { paths, times })
}

/// Writes the frames of `spec`'s camera in `[from_s, to_s)` as a YUV4MPEG2 stream (4:4:4, BT.601,
/// full range) at the sensor's rate; returns how many.
pub fn write_y4m(
    renderer: &mut CameraRenderer,
    spec: &SensorSpec,
    from_s: f64,
    to_s: f64,
    out: &mut impl Write,
) -> io::Result<usize> {
    let [width, height] = renderer.size();
    let (num, den) = rate_fraction(spec.rate_hz);
    writeln!(
        out,
        "YUV4MPEG2 W{width} H{height} F{num}:{den} Ip A1:1 C444 XCOLORRANGE=FULL"
    )?;
    let mut image = RgbImage::new(width, height);
    let pixels = width as usize * height as usize;
    let mut planes = vec![0u8; 3 * pixels];
    let times = frame_times(spec, from_s, to_s);
    for &t in &times {
        renderer.render_into(t, &mut image);
        for (i, p) in image.pixels().enumerate() {
            let [r, g, b] = p.0.map(f64::from);
            let y = 0.299 * r + 0.587 * g + 0.114 * b;
            planes[i] = byte(y);
            planes[pixels + i] = byte(128.0 + 0.564 * (b - y));
            planes[2 * pixels + i] = byte(128.0 + 0.713 * (r - y));
        }
        out.write_all(b"FRAME\n")?;
        out.write_all(&planes)?;
    }
    out.flush()?;
    Ok(times.len())
}

/// Writes the frames of `spec`'s camera in `[from_s, to_s)` as raw RGB24, row-major, one frame
/// after the other (no header: the reader is told the size and rate); returns how many.
pub fn write_raw_rgb(
    renderer: &mut CameraRenderer,
    spec: &SensorSpec,
    from_s: f64,
    to_s: f64,
    out: &mut impl Write,
) -> io::Result<usize> {
    let [width, height] = renderer.size();
    let mut image = RgbImage::new(width, height);
    let times = frame_times(spec, from_s, to_s);
    for &t in &times {
        renderer.render_into(t, &mut image);
        out.write_all(image.as_raw())?;
    }
    out.flush()?;
    Ok(times.len())
}

fn byte(x: f64) -> u8 {
    x.round().clamp(0.0, 255.0) as u8
}

/// A frame rate as the fraction YUV4MPEG2 writes (to a thousandth of a frame per second).
fn rate_fraction(rate_hz: f64) -> (u64, u64) {
    let num = (rate_hz * 1000.0).round() as u64;
    let common = gcd(num, 1000);
    (num / common, 1000 / common)
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a.max(1)
    } else {
        gcd(b, a % b)
    }
}
