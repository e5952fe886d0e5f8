//! `edge-agent camera --detections det.txt` on generated pedestrian crowds (`simulator::pedestrians`):
//! the published head points of the single-view tracker against those of `--raw`, both scored by pixel
//! OSPA (c = 50 px, p = 1) against the true head points (top-centre of the ground-truth boxes).

mod common;

use std::path::Path;

use common::{check_replay, edge_agent_ok, START};
use frontends::camera::{parse_mot_text, MotDetConfig};
use gmphd::metrics::{ospa, MetricParams};
use nalgebra::DVector;
use protocol::MeasurementSet;
use simulator::pedestrians::{CrowdConfig, CrowdSequence};

const CUTOFF_PX: f64 = 50.0;

/// The descriptor a user would write for this camera and detector: 2 px head-point noise, 10 % misses,
/// 2 false boxes per frame.
fn descriptor(sequence: &CrowdSequence) -> String {
    let rows: Vec<String> = sequence
        .projection
        .iter()
        .map(|row| format!("[{}, {}, {}, {}]", row[0], row[1], row[2], row[3]))
        .collect();
    let [w, h] = sequence.image_size;
    format!(
        "sensor = \"street\"\ndetection_probability = 0.9\nclutter_rate = 2.0\n[model]\nkind = \"camera\"\n\
         projection = [{}]\nimage_size = [{w}, {h}]\nnoise_std = [2.0, 2.0]\n",
        rows.join(", ")
    )
}

/// Mean OSPA over the published sets, each against the true head points of its frame.
fn mean_ospa(sets: &[MeasurementSet], truth: &[Vec<DVector<f64>>], fps: f64) -> f64 {
    let start: f64 = START.parse().expect("start");
    let params = MetricParams::new(CUTOFF_PX, 1.0).expect("params");
    let total: f64 = sets
        .iter()
        .map(|set| {
            let frame = ((set.stamp - start) * fps).round() as usize;
            let points: Vec<DVector<f64>> = set
                .measurements
                .iter()
                .map(|m| DVector::from_column_slice(m))
                .collect();
            ospa(&truth[frame], &points, params).expect("ospa").distance
        })
        .sum();
    total / sets.len() as f64
}

fn true_heads(sequence: &CrowdSequence) -> Vec<Vec<DVector<f64>>> {
    let boxes = parse_mot_text(&sequence.gt_txt(), Path::new("gt.txt")).expect("gt");
    let mut heads = vec![Vec::new(); sequence.truth.len()];
    for b in boxes {
        let point = b.point(MotDetConfig::default().anchor);
        heads[b.frame - 1].push(DVector::from_column_slice(&point));
    }
    heads
}

#[test]
fn the_published_tracks_beat_the_raw_detections_on_a_crowd() {
    let mut config = CrowdConfig::street(21, 12);
    config.duration_s = 30.0;
    let sequence = CrowdSequence::generate(&config).expect("sequence");
    let dir = tempfile::tempdir().expect("temp dir");
    let (descriptor_path, det_path) = (dir.path().join("street.toml"), dir.path().join("det.txt"));
    std::fs::write(&descriptor_path, descriptor(&sequence)).expect("descriptor");
    std::fs::write(&det_path, sequence.det_txt()).expect("det.txt");
    let fps = sequence.fps.to_string();
    let args = [
        "camera",
        "--descriptor",
        descriptor_path.to_str().expect("utf-8"),
        "--detections",
        det_path.to_str().expect("utf-8"),
        "--fps",
        &fps,
        "--start",
        START,
        "--output",
        "-",
    ];
    let tracked = check_replay(&edge_agent_ok(&args));
    let raw = check_replay(&edge_agent_ok(&[&args[..], &["--raw"]].concat()));
    assert_eq!(
        tracked.sets.len(),
        raw.sets.len(),
        "one set per frame either way"
    );
    let truth = true_heads(&sequence);
    let (raw_ospa, tracked_ospa) = (
        mean_ospa(&raw.sets, &truth, sequence.fps),
        mean_ospa(&tracked.sets, &truth, sequence.fps),
    );
    println!(
        "{} frames: pixel OSPA (c = {CUTOFF_PX} px, p = 1) raw {raw_ospa:.2} px, tracker {tracked_ospa:.2} px, ratio {:.3}",
        raw.sets.len(),
        tracked_ospa / raw_ospa
    );
    assert!(tracked_ospa <= 0.9 * raw_ospa);
}
