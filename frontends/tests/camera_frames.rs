//! Frame directory input: PNG round trip, JPEG decoding, stamps from a frame rate or a stamps file,
//! and errors that name the file and the problem; plus the pipeline run from a PNG directory.

mod camera_scene;

use std::fs;
use std::path::Path;

use camera_scene::{Scene, EMPTY_FRAMES, PEOPLE_FRAMES};
use frontends::camera::{
    CameraConfig, CameraError, CameraPipeline, FrameDirectory, FrameRate, FrameTiming,
};
use image::{Rgb, RgbImage};

const SEED: u64 = 7;

fn rate(start: f64, fps: f64) -> FrameTiming {
    FrameTiming::Rate(FrameRate { start, fps })
}

/// Writes frames `0..count` of the scene as `frame_NNNN.png`, in reverse order so that the listing
/// order cannot come from creation order.
fn write_scene_pngs(dir: &Path, count: usize) -> Vec<RgbImage> {
    let mut scene = Scene::new(SEED);
    let frames: Vec<RgbImage> = (0..count).map(|k| scene.render(k)).collect();
    for (k, frame) in frames.iter().enumerate().rev() {
        frame
            .save(dir.join(format!("frame_{k:04}.png")))
            .expect("PNG written");
    }
    frames
}

#[test]
fn png_directory_round_trips_in_name_order_with_rate_stamps() {
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = write_scene_pngs(dir.path(), 4);
    fs::write(dir.path().join("notes.txt"), "not a frame").expect("written");
    let listing = FrameDirectory::open(dir.path(), &rate(100.0, 25.0)).expect("opened");
    assert_eq!(listing.len(), 4);
    assert!(!listing.is_empty());
    assert_eq!(listing.stamps(), &[100.0, 100.04, 100.08, 100.12]);
    for (k, frame) in listing.iter().enumerate() {
        let frame = frame.expect("decoded");
        assert_eq!(frame.index, k);
        assert_eq!(
            frame.path.file_name().and_then(|n| n.to_str()),
            Some(format!("frame_{k:04}.png").as_str())
        );
        assert!(
            frame.image == frames[k],
            "frame {k} changed in the PNG round trip"
        );
    }
}

#[test]
fn stamps_file_gives_one_stamp_per_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    write_scene_pngs(dir.path(), 3);
    let stamps = dir.path().join("stamps.txt");
    fs::write(&stamps, "# capture times (s)\n10.0\n\n10.05\n  10.125  \n").expect("written");
    let listing =
        FrameDirectory::open(dir.path(), &FrameTiming::StampsFile(stamps)).expect("opened");
    assert_eq!(listing.stamps(), &[10.0, 10.05, 10.125]);
}

fn open_error(dir: &Path, timing: &FrameTiming) -> String {
    FrameDirectory::open(dir, timing)
        .expect_err("must fail")
        .to_string()
}

#[test]
fn bad_stamps_files_name_the_file_line_and_problem() {
    let dir = tempfile::tempdir().expect("tempdir");
    write_scene_pngs(dir.path(), 3);
    let stamps = dir.path().join("stamps.txt");
    let timing = FrameTiming::StampsFile(stamps.clone());
    let cases = [
        ("1.0\n2.0\nsoon\n", "line 3: \"soon\" is not a number"),
        (
            "1.0\n# comment\n0.5\n3\n",
            "line 3: stamp 0.5 is not after the previous stamp 1",
        ),
        ("1.0\ninf\n3\n", "line 2: stamp \"inf\" is not finite"),
        (
            "1.0\n2.0\n",
            "lists 2 stamps but the frame directory holds 3 frames",
        ),
    ];
    for (text, expected) in cases {
        fs::write(&stamps, text).expect("written");
        let message = open_error(dir.path(), &timing);
        assert!(message.contains("stamps.txt"), "{message}");
        assert!(message.contains(expected), "{message:?} lacks {expected:?}");
    }
    let missing = FrameTiming::StampsFile(dir.path().join("absent.txt"));
    let message = open_error(dir.path(), &missing);
    assert!(
        message.contains("cannot read") && message.contains("absent.txt"),
        "{message}"
    );
}

#[test]
fn directory_problems_are_reported() {
    let dir = tempfile::tempdir().expect("tempdir");
    let message = open_error(dir.path(), &rate(0.0, 25.0));
    assert!(message.contains("holds no .png"), "{message}");

    write_scene_pngs(dir.path(), 1);
    let message = open_error(dir.path(), &rate(0.0, 0.0));
    assert!(message.contains("fps must be finite and > 0"), "{message}");

    fs::write(dir.path().join("frame_0001.PNG"), b"not really a png").expect("written");
    let listing = FrameDirectory::open(dir.path(), &rate(0.0, 25.0)).expect("opened");
    assert_eq!(listing.len(), 2, "upper-case extensions count");
    let error = listing.load(1).expect_err("garbage is not an image");
    assert!(matches!(error, CameraError::FrameDecode { .. }));
    let message = error.to_string();
    assert!(
        message.contains("cannot decode frame") && message.contains("frame_0001.PNG"),
        "{message}"
    );
    let message = listing.load(2).expect_err("past the end").to_string();
    assert!(
        message.contains("frame index 2 is out of range: the directory holds 2 frames"),
        "{message}"
    );
}

#[test]
fn jpeg_frames_are_decoded_to_rgb() {
    let dir = tempfile::tempdir().expect("tempdir");
    let image = RgbImage::from_pixel(64, 48, Rgb([200, 120, 40]));
    image.save(dir.path().join("a.jpg")).expect("JPEG written");
    image.save(dir.path().join("b.jpeg")).expect("JPEG written");
    let listing = FrameDirectory::open(dir.path(), &rate(0.0, 10.0)).expect("opened");
    for frame in listing.iter() {
        let frame = frame.expect("decoded");
        assert_eq!(frame.image.dimensions(), (64, 48));
        let Rgb(pixel) = *frame.image.get_pixel(10, 10);
        for (got, want) in pixel.iter().zip([200, 120, 40]) {
            assert!(
                got.abs_diff(want) <= 4,
                "JPEG pixel {pixel:?} far from [200, 120, 40]"
            );
        }
    }
}

#[test]
fn frame_of_another_size_is_named_in_the_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    write_scene_pngs(dir.path(), 2);
    RgbImage::new(32, 32)
        .save(dir.path().join("frame_0002.png"))
        .expect("written");
    let listing = FrameDirectory::open(dir.path(), &rate(0.0, 25.0)).expect("opened");
    let mut pipeline = CameraPipeline::new(CameraConfig::default()).expect("valid");
    let message = pipeline
        .process_directory(&listing)
        .expect_err("size changes")
        .to_string();
    assert!(
        message.contains("frame_0002.png")
            && message.contains("32x32 px")
            && message.contains("640x480 px"),
        "{message}"
    );
}

#[test]
fn pipeline_on_a_png_directory_matches_the_in_memory_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = write_scene_pngs(dir.path(), EMPTY_FRAMES + PEOPLE_FRAMES);
    let listing = FrameDirectory::open(dir.path(), &rate(5.0, 25.0)).expect("opened");
    let from_files = CameraPipeline::new(CameraConfig::default())
        .expect("valid")
        .process_directory(&listing)
        .expect("processed");

    let mut pipeline = CameraPipeline::new(CameraConfig::default()).expect("valid");
    let mut in_memory = Vec::new();
    for (k, frame) in frames.iter().enumerate() {
        let stamp = 5.0 + k as f64 / 25.0;
        if let Some(d) = pipeline
            .process_frame(frame, k, stamp, "memory")
            .expect("ok")
        {
            in_memory.push(d);
        }
    }
    assert_eq!(from_files.len(), PEOPLE_FRAMES);
    assert_eq!(from_files, in_memory);
    let people_seen = from_files.iter().filter(|d| !d.points.is_empty()).count();
    assert_eq!(
        people_seen, PEOPLE_FRAMES,
        "every frame with people has detections"
    );
}
