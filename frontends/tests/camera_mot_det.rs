//! MOT Challenge `det.txt` reading: grouping by frame, score threshold, anchors, and errors naming
//! the file, the line and the problem.

use std::fs;

use frontends::camera::{
    parse_mot_line, read_mot_detections, FrameRate, MotDetConfig, PointAnchor,
};

const RATE: FrameRate = FrameRate {
    start: 0.0,
    fps: 10.0,
};

const DET_TXT: &str = "\
1,-1,100,50,40,100,0.9,-1,-1,-1
1,-1,300.5,60,20,80,0.4,-1,-1,-1
1,-1,10,20,30,40,0.75

3,-1,200,100,50,120,0.95,-1,-1
3,-1,0,0,10,10
4,-1,5,5,10,10,0.1,-1,-1,-1\r
";

#[test]
fn detections_are_grouped_by_frame_above_the_score_threshold() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("det.txt");
    fs::write(&path, DET_TXT).expect("written");
    let config = MotDetConfig::default();
    assert_eq!(config.min_score, 0.5);
    let frames = read_mot_detections(&path, &config, &RATE).expect("read");
    assert_eq!(frames.len(), 4, "frames 1..=4, including empty ones");
    let indices: Vec<usize> = frames.iter().map(|f| f.frame_index).collect();
    assert_eq!(indices, [0, 1, 2, 3]);
    let stamps: Vec<f64> = frames.iter().map(|f| f.stamp).collect();
    assert_eq!(stamps, [0.0, 0.1, 0.2, 0.3]);
    // Frame 1: the 0.4 box is dropped; top-centres of the others.
    assert_eq!(frames[0].points, [[120.0, 50.0], [25.0, 20.0]]);
    assert!(frames[1].points.is_empty(), "frame 2 has no boxes");
    // Frame 3: the box without a score is kept.
    assert_eq!(frames[2].points, [[225.0, 100.0], [5.0, 0.0]]);
    assert!(frames[3].points.is_empty(), "frame 4's only box scores 0.1");
    let vectors = frames[0].measurement_vectors();
    assert_eq!(vectors.len(), 2);
    assert_eq!(vectors[0].as_slice(), &[120.0, 50.0]);
}

#[test]
fn anchor_and_threshold_are_configurable() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("det.txt");
    fs::write(&path, DET_TXT).expect("written");
    let centroid = MotDetConfig {
        min_score: 0.0,
        anchor: PointAnchor::Centroid,
    };
    let frames = read_mot_detections(&path, &centroid, &RATE).expect("read");
    assert_eq!(
        frames[0].points,
        [[120.0, 100.0], [310.5, 100.0], [25.0, 40.0]]
    );
    let feet = MotDetConfig {
        min_score: 0.0,
        anchor: PointAnchor::BottomCentre,
    };
    let frames = read_mot_detections(&path, &feet, &RATE).expect("read");
    assert_eq!(frames[3].points, [[10.0, 15.0]]);
}

#[test]
fn malformed_lines_name_the_file_line_and_problem() {
    let cases = [
        ("1,-1,10,10,5", "expected at least 6 comma-separated fields"),
        (
            "1,-1,10,10,5,5,0.9,-1,-1,-1,7",
            "expected at most 10 fields",
        ),
        ("1,-1,ten,10,5,5,0.9", "left \"ten\" is not a number"),
        (
            "0,-1,10,10,5,5,0.9",
            "frame \"0\" is not a whole number >= 1",
        ),
        (
            "2.5,-1,10,10,5,5,0.9",
            "frame \"2.5\" is not a whole number >= 1",
        ),
        ("1,-1,10,10,-5,5,0.9", "box size -5 x 5 is not positive"),
        ("1,-1,10,10,5,5,NaN", "score \"NaN\" is not finite"),
        ("1,-1,10,10,5,5,0.9,a,-1,-1", "x \"a\" is not a number"),
        (
            "5000000,-1,10,10,5,5,0.9",
            "beyond the supported 1000000 frames",
        ),
    ];
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("det.txt");
    for (bad, problem) in cases {
        fs::write(&path, format!("1,-1,1,1,5,5,0.9,-1,-1,-1\n\n{bad}\n")).expect("written");
        let message = read_mot_detections(&path, &MotDetConfig::default(), &RATE)
            .expect_err("malformed")
            .to_string();
        assert!(message.contains("det.txt, line 3: "), "{message}");
        assert!(message.contains(problem), "{message:?} lacks {problem:?}");
    }
    let missing = dir.path().join("absent.txt");
    let message = read_mot_detections(&missing, &MotDetConfig::default(), &RATE)
        .expect_err("missing")
        .to_string();
    assert!(
        message.contains("cannot read") && message.contains("absent.txt"),
        "{message}"
    );
}

#[test]
fn a_line_parses_with_optional_trailing_columns() {
    let full = parse_mot_line("7,-1,1.5,2.5,10,20,0.8,-1,-1,-1").expect("valid");
    assert_eq!(full.frame, 7);
    assert_eq!(full.score, Some(0.8));
    assert_eq!(full.point(PointAnchor::TopCentre), [6.5, 2.5]);
    let bare = parse_mot_line("7,-1,1.5,2.5,10,20").expect("valid");
    assert_eq!(bare.score, None);
    let empty_score = parse_mot_line(" 7 , -1 , 1.5 , 2.5 , 10 , 20 , ,").expect("valid");
    assert_eq!(empty_score.score, None);
}

#[test]
fn empty_file_gives_no_frames() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("det.txt");
    fs::write(&path, "\n\n").expect("written");
    let frames = read_mot_detections(&path, &MotDetConfig::default(), &RATE).expect("read");
    assert!(frames.is_empty());
}
