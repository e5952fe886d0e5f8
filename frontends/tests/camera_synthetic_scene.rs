//! End-to-end check of the background-subtraction pipeline on a seeded synthetic scene: three people
//! walking across a textured background, crossing one another (see `camera_scene`).

mod camera_scene;

use std::time::{Duration, Instant};

use camera_scene::{people, Scene, EMPTY_FRAMES, PEOPLE_FRAMES};
use frontends::camera::{BackgroundModelKind, CameraConfig, CameraPipeline, FrameDetections};

/// Head points closer than this to the truth count as hits.
const TOLERANCE_PX: f64 = 3.0;
/// People whose boxes, grown by this margin, overlap are treated as merged or occluded.
const MERGE_MARGIN_PX: f64 = 6.0;
const SEED: u64 = 20_240_611;

fn run_scene(config: CameraConfig) -> Vec<FrameDetections> {
    let mut scene = Scene::new(SEED);
    let mut pipeline = CameraPipeline::new(config).expect("valid configuration");
    let mut out = Vec::new();
    let mut pipeline_time = Duration::ZERO;
    for k in 0..EMPTY_FRAMES + PEOPLE_FRAMES {
        let frame = scene.render(k);
        let stamp = k as f64 / 25.0;
        let started = Instant::now();
        let result = pipeline
            .process_frame(&frame, k, stamp, &format!("frame {k}"))
            .expect("frame of the right size");
        pipeline_time += started.elapsed();
        match result {
            Some(detections) => out.push(detections),
            None => assert!(k < EMPTY_FRAMES, "still learning at frame {k}"),
        }
    }
    // Printed for information only; timing is never asserted.
    println!(
        "pipeline time per frame: {:.1} ms",
        pipeline_time.as_secs_f64() * 1e3 / (EMPTY_FRAMES + PEOPLE_FRAMES) as f64
    );
    out
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

struct SceneScore {
    isolated_person_frames: usize,
    hits: usize,
    worst_hit_error: f64,
    separated_frames: usize,
    separated_frames_with_right_count: usize,
    crossings: usize,
}

/// Scores detections against the truth and checks the count after every crossing.
fn score(detections: &[FrameDetections]) -> SceneScore {
    let mut s = SceneScore {
        isolated_person_frames: 0,
        hits: 0,
        worst_hit_error: 0.0,
        separated_frames: 0,
        separated_frames_with_right_count: 0,
        crossings: 0,
    };
    let mut was_merged = false;
    for frame in detections {
        let truth = people(frame.frame_index);
        if truth.is_empty() {
            assert!(
                frame.points.is_empty(),
                "frame {}: detections {:?} in an empty scene",
                frame.frame_index,
                frame.points
            );
            continue;
        }
        let mut all_separate = true;
        for (i, person) in truth.iter().enumerate() {
            let merged = truth
                .iter()
                .enumerate()
                .any(|(j, other)| i != j && person.near(other, MERGE_MARGIN_PX));
            if merged {
                all_separate = false;
                continue;
            }
            s.isolated_person_frames += 1;
            let error = frame
                .points
                .iter()
                .map(|&p| distance(p, person.head()))
                .fold(f64::INFINITY, f64::min);
            if error <= TOLERANCE_PX {
                s.hits += 1;
                s.worst_hit_error = s.worst_hit_error.max(error);
            } else {
                println!(
                    "frame {}: person {i} head {:?} missed, nearest point {error:.1} px away ({:?})",
                    frame.frame_index,
                    person.head(),
                    frame.points
                );
            }
        }
        if all_separate {
            s.separated_frames += 1;
            let right = frame.points.len() == truth.len();
            if right {
                s.separated_frames_with_right_count += 1;
            }
            if was_merged {
                s.crossings += 1;
                println!(
                    "crossing over at frame {}: {} points for {} people",
                    frame.frame_index,
                    frame.points.len(),
                    truth.len()
                );
                assert!(
                    right,
                    "frame {}: after a crossing {} points for {} people: {:?}",
                    frame.frame_index,
                    frame.points.len(),
                    truth.len(),
                    frame.points
                );
            }
        }
        was_merged = !all_separate;
    }
    s
}

fn check_model(model: BackgroundModelKind) {
    let mut config = CameraConfig::default();
    config.background.model = model;
    let detections = run_scene(config);
    // Both models learn from their first 16 frames by default and report nothing for them.
    assert_eq!(detections.len(), EMPTY_FRAMES + PEOPLE_FRAMES - 16);
    let s = score(&detections);
    let hit_rate = 100.0 * s.hits as f64 / s.isolated_person_frames as f64;
    let count_rate = 100.0 * s.separated_frames_with_right_count as f64 / s.separated_frames as f64;
    println!(
        "{model:?}: head within {TOLERANCE_PX} px in {}/{} isolated person-frames = {hit_rate:.1} % \
         (worst hit {:.2} px); right count in {}/{} separated frames = {count_rate:.1} %; \
         {} crossings",
        s.hits,
        s.isolated_person_frames,
        s.worst_hit_error,
        s.separated_frames_with_right_count,
        s.separated_frames,
        s.crossings
    );
    assert!(
        s.isolated_person_frames > 60,
        "too few isolated person-frames to judge"
    );
    assert!(
        hit_rate >= 90.0,
        "{model:?}: hit rate {hit_rate:.1} % < 90 %"
    );
    assert!(
        count_rate >= 90.0,
        "{model:?}: count right in {count_rate:.1} % < 90 %"
    );
    assert_eq!(s.crossings, 3, "the scene has three crossings");
}

#[test]
fn kde_model_finds_head_points_through_crossings() {
    check_model(BackgroundModelKind::Kde);
}

#[test]
fn running_stats_model_finds_head_points_through_crossings() {
    check_model(BackgroundModelKind::RunningStats);
}
