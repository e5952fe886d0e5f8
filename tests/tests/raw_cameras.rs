//! The default room's two cameras rendered from the truth (`simulator::render::camera`: textured
//! people walking and occluding one another over a textured room, soft shadows, illumination
//! drift, sensor noise), written as PNG frame directories and run through the real
//! `edge-agent camera --frames` (its default front end: the multi-Bernoulli image tracker on the
//! background-subtracted frames, head tops with covariances, the descriptor calibrated from the
//! tracker's own account), then fused by the server's replay: mean 3-D OSPA and the share of track
//! sets with the right count against the truth, for several seeds.

use std::path::Path;
use std::process::Command;

use checker::processes::binary;
use protocol::{ReplayLine, SensorDescriptor};
use simulator::render::camera::{write_frame_directory, CameraRenderer, CameraRoom};
use simulator::{truth_set, Scenario};

/// Unix time of scenario time 0.
const START: f64 = 1_763_700_000.0;
/// The cameras run from before anybody is in the room (target 1 walks in at 0.5 s), so that the
/// background model learns the empty room.
const FROM_S: f64 = -1.0;
/// Seconds rendered.
const TO_S: f64 = 30.0;
/// Scores count from here: every person has walked in and been confirmed.
const SCORED_FROM_S: f64 = 6.0;
const CAMERAS: [&str; 2] = ["cam1", "cam2"];

/// Mean OSPA and share of right counts of one seed.
#[derive(Default)]
struct Figures {
    ospa: f64,
    right_count: f64,
    track_ids: usize,
    /// Share right among the track sets in which no two people are within [`APART_M`], and how
    /// many such sets there are.
    right_apart: f64,
    apart_sets: usize,
    /// Over the cameras: the smallest share of the visible heads published and the most published
    /// points per set near no head.
    worst_found: f64,
    worst_false: f64,
}

/// People farther apart than this (heads, horizontally) stand clear of one another.
const APART_M: f64 = 0.6;

/// Whether at scenario time `t` every two people present are at least [`APART_M`] apart.
fn everyone_apart(scenario: &Scenario, seed: u64, t: f64) -> bool {
    scenario
        .closest_pair_m(seed, t)
        .is_none_or(|d| d >= APART_M)
}

/// Renders `camera` and runs it through `edge-agent camera --frames`; returns its replay lines.
fn camera_sets(scenario: &Scenario, camera: &str, seed: u64, dir: &Path) -> String {
    let (_, spec) = scenario.sensor(camera).unwrap();
    let mut renderer = CameraRenderer::new(scenario, camera, &CameraRoom::default(), seed).unwrap();
    let frames = dir.join(camera);
    let rendered = write_frame_directory(&mut renderer, spec, FROM_S, TO_S, &frames).unwrap();
    let descriptor_path = dir.join(format!("{camera}.json"));
    let descriptor: SensorDescriptor = spec.descriptor(&scenario.site);
    std::fs::write(
        &descriptor_path,
        serde_json::to_string(&descriptor).unwrap(),
    )
    .unwrap();
    let output = Command::new(binary("edge-agent").unwrap())
        .arg("camera")
        .arg("--descriptor")
        .arg(&descriptor_path)
        .arg("--frames")
        .arg(&frames)
        .args(["--fps", &spec.rate_hz.to_string()])
        .args(["--start", &(START + rendered.times[0]).to_string()])
        .args(["--output", "-"])
        .env("RUST_LOG", "warn")
        .output()
        .expect("edge-agent runs");
    assert!(
        output.status.success(),
        "edge-agent failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

fn figures(seed: u64) -> Figures {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    let dir = tempfile::tempdir().unwrap();
    let mut lines: Vec<ReplayLine> = Vec::new();
    let outputs: Vec<String> = std::thread::scope(|scope| {
        let jobs: Vec<_> = CAMERAS
            .iter()
            .map(|camera| {
                let (scenario, dir) = (&scenario, dir.path());
                scope.spawn(move || camera_sets(scenario, camera, seed, dir))
            })
            .collect();
        jobs.into_iter().map(|j| j.join().unwrap()).collect()
    });
    let mut sets = Vec::new();
    let mut cameras = Vec::new();
    for (camera, text) in CAMERAS.iter().zip(&outputs) {
        let mut own = Vec::new();
        for line in text.lines() {
            match serde_json::from_str::<ReplayLine>(line).unwrap() {
                ReplayLine::Measurements(set) => own.push(set),
                other => lines.push(other),
            }
        }
        let heads = head_figures(&scenario, camera, seed, &own);
        heads.print(camera);
        cameras.push(heads);
        sets.extend(own);
    }
    Figures {
        worst_found: cameras
            .iter()
            .map(HeadFigures::found_share)
            .fold(1.0, f64::min),
        worst_false: cameras
            .iter()
            .map(HeadFigures::false_per_set)
            .fold(0.0, f64::max),
        ..fuse(&scenario, seed, lines, sets)
    }
}

/// A published point within this many pixels of a projected head is that head's.
const NEAR_PX: f64 = 25.0;

/// One camera's published points against the projected truth heads, from `SCORED_FROM_S` on:
/// what the fusion is given, to tell the front end's share of the figures from the fusion's.
#[derive(Debug, Default)]
struct HeadFigures {
    sets: usize,
    /// Heads inside the image, summed over the sets.
    heads: usize,
    /// Of those, the ones with a published point near them.
    found: usize,
    /// Published points near no head.
    false_points: usize,
    /// Sums over the found heads: point − head (u, v), its squared length, and the published
    /// variance (the mean of the covariance's diagonal).
    offset: [f64; 2],
    squared_error: f64,
    variance: f64,
}

impl HeadFigures {
    /// Share of the visible heads with a published point near them.
    fn found_share(&self) -> f64 {
        self.found as f64 / self.heads.max(1) as f64
    }

    /// Published points near no head, per set.
    fn false_per_set(&self) -> f64 {
        self.false_points as f64 / self.sets.max(1) as f64
    }

    fn print(&self, camera: &str) {
        let found = self.found.max(1) as f64;
        println!(
            "  {camera}: {} sets, {:.1} % of the visible heads published, {:.2} points per set \
             near no head; found heads: mean offset ({:.1}, {:.1}) px, RMS error {:.1} px, \
             published σ {:.1} px",
            self.sets,
            100.0 * self.found as f64 / self.heads.max(1) as f64,
            self.false_points as f64 / self.sets.max(1) as f64,
            self.offset[0] / found,
            self.offset[1] / found,
            (self.squared_error / found).sqrt(),
            (self.variance / found).sqrt(),
        );
    }

    /// Adds one set, whose visible projected heads are `heads`.
    fn add(&mut self, set: &protocol::MeasurementSet, heads: &[[f64; 2]]) {
        let distance = |m: &[f64], h: &[f64; 2]| (m[0] - h[0]).hypot(m[1] - h[1]);
        self.sets += 1;
        self.heads += heads.len();
        for head in heads {
            let nearest = set
                .measurements
                .iter()
                .enumerate()
                .min_by(|(_, a), (_, b)| distance(a, head).total_cmp(&distance(b, head)));
            let Some((i, m)) = nearest.filter(|(_, m)| distance(m, head) <= NEAR_PX) else {
                continue;
            };
            self.found += 1;
            self.offset[0] += m[0] - head[0];
            self.offset[1] += m[1] - head[1];
            self.squared_error += distance(m, head).powi(2);
            if let Some(c) = &set.covariances {
                self.variance += 0.5 * (c[i][0][0] + c[i][1][1]);
            }
        }
        self.false_points += set
            .measurements
            .iter()
            .filter(|m| heads.iter().all(|h| distance(m, h) > NEAR_PX))
            .count();
    }
}

fn head_figures(
    scenario: &Scenario,
    camera: &str,
    seed: u64,
    sets: &[protocol::MeasurementSet],
) -> HeadFigures {
    let (_, spec) = scenario.sensor(camera).unwrap();
    let protocol::SensorModel::Camera(model) = &spec.model else {
        panic!("{camera} is a camera")
    };
    let p = model.projection;
    let project = |x: [f64; 3]| {
        let row = |r: usize| p[r][0] * x[0] + p[r][1] * x[1] + p[r][2] * x[2] + p[r][3];
        [row(0) / row(2), row(1) / row(2)]
    };
    let [width, height] = model.image_size.map(f64::from);
    let mut figures = HeadFigures::default();
    for set in sets.iter().filter(|s| s.stamp - START >= SCORED_FROM_S) {
        let t = set.stamp - START;
        let heads: Vec<[f64; 2]> = scenario
            .present_at(seed, t)
            .into_iter()
            .map(|(_, head)| project(head))
            .filter(|[u, v]| (0.0..width).contains(u) && (0.0..height).contains(v))
            .collect();
        figures.add(set, &heads);
    }
    figures
}

/// The cameras' own simulated sets (the simulator's measurement model: the projected head with
/// pixel noise, misses and clutter as the descriptors say), fused the same way: what the fusion
/// makes of these two cameras when the front end is as good as its descriptor claims.
fn simulated_figures(seed: u64) -> Figures {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    scenario
        .sensors
        .retain(|s| CAMERAS.contains(&s.sensor.as_str()));
    let (descriptors, sets) = simulator::descriptors_and_sets(&scenario, seed, TO_S).unwrap();
    let lines = descriptors
        .into_iter()
        .map(ReplayLine::Descriptor)
        .collect();
    fuse(&scenario, seed, lines, sets)
}

/// Runs the server's replay over descriptors and sets with the scenario's truth, and scores it.
fn fuse(
    scenario: &Scenario,
    seed: u64,
    mut lines: Vec<ReplayLine>,
    mut sets: Vec<protocol::MeasurementSet>,
) -> Figures {
    sets.sort_by(|a, b| a.stamp.total_cmp(&b.stamp));
    let truth_count = scenario.truth_count(TO_S);
    lines.extend((0..truth_count).map(|k| ReplayLine::Truth(truth_set(scenario, seed, START, k))));
    lines.extend(sets.into_iter().map(ReplayLine::Measurements));
    let input: String = lines
        .iter()
        .map(|l| serde_json::to_string(l).unwrap() + "\n")
        .collect();
    let report = fusion_server::replay::replay(
        fusion_server::config::ServerConfig::default(),
        input.as_bytes(),
        std::io::sink(),
    )
    .unwrap();
    let from = START + SCORED_FROM_S;
    let scored: Vec<_> = report.scores.iter().filter(|s| s.stamp >= from).collect();
    let right = scored
        .iter()
        .filter(|s| s.truth_count == s.track_count)
        .count();
    let apart: Vec<_> = scored
        .iter()
        .filter(|s| everyone_apart(scenario, seed, s.stamp - START))
        .collect();
    let apart_right = apart
        .iter()
        .filter(|s| s.truth_count == s.track_count)
        .count();
    let mut ids: Vec<u64> = report
        .tracks
        .iter()
        .filter(|t| t.stamp >= from)
        .flat_map(|t| t.tracks.iter().map(|track| track.id))
        .collect();
    ids.sort_unstable();
    ids.dedup();
    Figures {
        worst_found: 1.0,
        worst_false: 0.0,
        right_apart: apart_right as f64 / apart.len().max(1) as f64,
        apart_sets: apart.len(),
        ospa: report.mean_ospa_from(from).unwrap(),
        right_count: right as f64 / scored.len().max(1) as f64,
        track_ids: ids.len(),
    }
}

#[test]
fn rendered_cameras_track_the_room_in_3d() {
    let mut all = Vec::new();
    for seed in [1, 2, 3] {
        let reference = simulated_figures(seed);
        println!(
            "seed {seed}, the cameras' simulated sets: mean OSPA {:.3} m, right count {:.1} %, {} track ids",
            reference.ospa,
            100.0 * reference.right_count,
            reference.track_ids
        );
        let f = figures(seed);
        println!(
            "seed {seed}: mean OSPA {:.3} m, right count {:.1} % of track sets ({:.1} % of the {} \
             in which no two people are within {APART_M} m), {} track ids (3 people), from \
             {SCORED_FROM_S} s to {TO_S} s",
            f.ospa,
            100.0 * f.right_count,
            100.0 * f.right_apart,
            f.apart_sets,
            f.track_ids
        );
        all.push(f);
    }
    let n = all.len() as f64;
    let mean_ospa = all.iter().map(|f| f.ospa).sum::<f64>() / n;
    let mean_count = all.iter().map(|f| f.right_count).sum::<f64>() / n;
    let worst_ospa = all.iter().map(|f| f.ospa).fold(0.0, f64::max);
    let worst_count = all.iter().map(|f| f.right_count).fold(1.0, f64::min);
    let worst_found = all.iter().map(|f| f.worst_found).fold(1.0, f64::min);
    let worst_false = all.iter().map(|f| f.worst_false).fold(0.0, f64::max);
    println!(
        "over the seeds: mean OSPA {mean_ospa:.3} m, right count {:.1} %; worst seed {worst_ospa:.3} m, \
         {:.1} %; worst camera {:.1} % of the visible heads, {worst_false:.2} points per set near no head",
        100.0 * mean_count,
        100.0 * worst_count,
        100.0 * worst_found
    );
    // The goal, over seeds 1 to 3: mean OSPA at most 0.10 m and the right count in at least 90 % of
    // the track sets (the cameras' simulated sets give 0.02 m and 100 %). Measured: 0.036, 0.040 and
    // 0.063 m, 97.9, 100 and 95.5 % (0.046 m and 97.8 % over the seeds; 0.019, 0.037 and 0.075 m,
    // 98.5 % without the server's occlusion model); each camera publishes 91 to
    // 99 % of the visible heads within 3.1 to 5.0 px RMS, published with σ 12 to 14 px (the person
    // model's own error, `head_model_error` 0.04 m: with 0.02 m, σ 7 to 8 px, a head point off for a
    // second or two — hair or clothes of the door's or floor's colour — was gated out of its track
    // and doubled it, seed 3 88.9 %), and at most 0.15 points per set near no head. The blobs and
    // point tracker gave 0.29 to 0.36 m and 40 to 57 % (`--front-end blobs`). What is left on seed 3
    // is one person lost for 1.5 s while one camera's tracker misses them and the other sees them
    // behind someone.
    assert!(
        mean_ospa <= 0.10,
        "mean OSPA {mean_ospa:.3} m over the seeds"
    );
    assert!(
        mean_count >= 0.90,
        "right count {:.1} % over the seeds",
        100.0 * mean_count
    );
    assert!(
        worst_ospa <= 0.10,
        "worst seed's mean OSPA {worst_ospa:.3} m"
    );
    assert!(
        worst_count >= 0.85,
        "worst seed's right count {:.1} %",
        100.0 * worst_count
    );
    assert!(
        worst_found >= 0.85,
        "a camera publishes {:.1} % of the visible heads",
        100.0 * worst_found
    );
    assert!(
        worst_false <= 0.3,
        "a camera publishes {worst_false:.2} points per set near no head"
    );
}
