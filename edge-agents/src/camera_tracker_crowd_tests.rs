//! The single-view tracker on generated pedestrian crowds (`simulator::pedestrians`), fed as the agent
//! feeds it with `--detections det.txt`: the file read by `frontends::camera::read_mot_detections` with
//! the default MOT settings (top-centre head points), the tracker built from the descriptor's `p_D`,
//! clutter rate and noise with the command line's default settings. Scored by pixel OSPA (c = 50 px, about
//! half a box width to a box height here, p = 1) against the true head points (the same top-centre
//! of the ground-truth boxes), raw detections against tracker output.

use std::path::Path;

use frontends::camera::{parse_mot_text, FrameRate, MotDetConfig};
use gmphd::metrics::{ospa, MetricParams};
use nalgebra::DVector;
use protocol::CameraModel;
use simulator::pedestrians::{CrowdConfig, CrowdSequence};

use super::{
    SingleViewSettings, SingleViewTracker, DEFAULT_ACCEL_NOISE, DEFAULT_BIRTH_RATE,
    DEFAULT_EXTRACTION_THRESHOLD,
};

/// OSPA cut-off, px.
const CUTOFF_PX: f64 = 50.0;
/// What a descriptor of this camera and detector says: σ of a head point (the top edge's jitter;
/// the centre's is 2/√2 px), `p_D` and false boxes per frame.
const NOISE_STD_PX: f64 = 2.0;
const P_D: f64 = 0.9;
const CLUTTER: f64 = 2.0;

/// Mean OSPA of the raw head points and of the tracker's estimates over one sequence.
fn mean_ospa(sequence: &CrowdSequence) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let det = dir.path().join("det.txt");
    std::fs::write(&det, sequence.det_txt()).unwrap();
    let rate = FrameRate {
        start: 1_700_000_000.0,
        fps: sequence.fps,
    };
    let frames =
        frontends::camera::read_mot_detections(&det, &MotDetConfig::default(), &rate).unwrap();
    let truth = true_heads(sequence);
    let camera = CameraModel {
        projection: sequence.projection,
        image_size: sequence.image_size,
        noise_std: [NOISE_STD_PX, NOISE_STD_PX],
    };
    let settings = SingleViewSettings {
        accel_noise: DEFAULT_ACCEL_NOISE,
        birth_rate: DEFAULT_BIRTH_RATE,
        extraction_threshold: DEFAULT_EXTRACTION_THRESHOLD,
    };
    let mut tracker = SingleViewTracker::new(&camera, P_D, CLUTTER, settings).unwrap();
    let params = MetricParams::new(CUTOFF_PX, 1.0).unwrap();
    let (mut raw_sum, mut tracked_sum) = (0.0, 0.0);
    for (frame, truth) in frames.iter().zip(&truth) {
        let estimates = tracker.step(frame.stamp, &frame.points).unwrap();
        let raw = vectors(frame.points.iter().map(|p| p.to_vec()));
        let tracked = vectors(estimates.points.into_iter());
        raw_sum += ospa(truth, &raw, params).unwrap().distance;
        tracked_sum += ospa(truth, &tracked, params).unwrap().distance;
    }
    let n = frames.len().min(truth.len()) as f64;
    (raw_sum / n, tracked_sum / n)
}

/// The head point of each true box, frame by frame, by the agent's own reading of a MOT line.
fn true_heads(sequence: &CrowdSequence) -> Vec<Vec<DVector<f64>>> {
    let boxes = parse_mot_text(&sequence.gt_txt(), Path::new("gt.txt")).unwrap();
    let mut heads = vec![Vec::new(); sequence.truth.len()];
    for b in boxes {
        let point = b.point(MotDetConfig::default().anchor);
        heads[b.frame - 1].push(DVector::from_column_slice(&point));
    }
    heads
}

fn vectors(points: impl Iterator<Item = Vec<f64>>) -> Vec<DVector<f64>> {
    points.map(DVector::from_vec).collect()
}

#[test]
fn the_tracker_beats_its_detections_on_pedestrian_crowds() {
    println!("pixel OSPA (c = {CUTOFF_PX} px, p = 1), mean over the frames of 60 s at 25 fps");
    let mut worst_ratio: f64 = 0.0;
    for (seed, people) in [(1, 3), (2, 6), (3, 10), (4, 15), (5, 8), (6, 12)] {
        let sequence = CrowdSequence::generate(&CrowdConfig::street(seed, people)).unwrap();
        let in_view =
            sequence.truth.iter().map(Vec::len).sum::<usize>() as f64 / sequence.truth.len() as f64;
        let (raw, tracked) = mean_ospa(&sequence);
        let ratio = tracked / raw;
        println!(
            "seed {seed} crowd {people:2} ({in_view:4.1} in view): raw {raw:6.2} px  tracker {tracked:6.2} px  ratio {ratio:.3}"
        );
        worst_ratio = worst_ratio.max(ratio);
    }
    println!("worst ratio {worst_ratio:.3}");
    assert!(
        worst_ratio <= 0.9,
        "the tracker is not 10 % better than its detections"
    );
}
