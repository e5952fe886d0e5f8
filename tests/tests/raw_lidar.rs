//! Raw LIDAR end to end: scans ray-cast from the scenario's truth (`simulator::render::lidar`), the
//! LIDAR front end as `edge-agent lidar` runs it (its default configuration, the descriptor's region
//! filter, one set per scan), the server's offline replay, and OSPA against the truth. Also an
//! outdoor scene, a level VLP-16 1.8 m up with walkers at 5–25 m and two poles: the front end alone,
//! and end to end through the real `edge-agent lidar --scans` and the server's replay.

use std::time::Instant;

use frontends::lidar::{LidarConfig, LidarPipeline, PointCloud};
use fusion_server::config::ServerConfig;
use fusion_server::replay::replay;
use protocol::{LidarModel, MeasurementSet, ReplayLine, SensorModel, TruthSet};
use simulator::render::{render_lidar_scan, BeamLayout, LidarScene, Pole, ScanPattern};
use simulator::{Scenario, Simulation};

/// Unix time of the run's start.
const START: f64 = 1_763_700_000.0;
/// The room's scans used: everyone is in by 6 s.
const FIRST_S: f64 = 6.0;
const LAST_S: f64 = 30.0;
/// Two heads closer than this horizontally belong to people whose bodies overlap: seen from above
/// they are one surface. The room's people keep 0.5 m apart, so no miss should be of such a head.
const TOUCHING_M: f64 = 0.3;
/// People farther apart than this (heads, horizontally) stand clear of one another.
const APART_M: f64 = 0.6;
/// Track sets scored from this long after the first scan (the tracks' confirmation).
const SETTLE_S: f64 = 2.0;

fn lidar_model(scenario: &Scenario, sensor: &str) -> LidarModel {
    let (_, spec) = scenario.sensor(sensor).unwrap();
    let SensorModel::Lidar(model) = &spec.model else {
        panic!("{sensor} is a LIDAR")
    };
    model.clone()
}

/// What `edge-agent lidar` keeps of a scan's measurements: those inside the descriptor's region (each then
/// published with its covariance, as the room test below does).
fn in_region(model: &LidarModel, [range, _, elevation]: &[f64; 3]) -> bool {
    let [low, high] = model.elevation_limits;
    *range <= model.max_range && (low..=high).contains(elevation)
}

/// `v` rotated by the unit quaternion `[w, x, y, z]`: v + 2w (u × v) + 2 u × (u × v).
fn rotate([w, x, y, z]: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = [x, y, z];
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    [0, 1, 2].map(|i| v[i] + 2.0 * (w * uv[i] + uuv[i]))
}

/// Sensor-frame point of a world point (the descriptor's quaternion rotates sensor into world).
fn to_sensor(model: &LidarModel, world: [f64; 3]) -> [f64; 3] {
    let [w, x, y, z] = model.orientation;
    let offset = [0, 1, 2].map(|i| world[i] - model.position[i]);
    rotate([w, -x, -y, -z], offset)
}

/// Sensor-frame direction of the world's up.
fn sensor_up(model: &LidarModel) -> [f64; 3] {
    let [w, x, y, z] = model.orientation;
    rotate([w, -x, -y, -z], [0.0, 0.0, 1.0])
}

/// The heads of the targets present at `t`, in the sensor frame.
fn heads(scenario: &Scenario, model: &LidarModel, seed: u64, t: f64) -> Vec<[f64; 3]> {
    scenario
        .present_at(seed, t)
        .into_iter()
        .map(|(_, head)| to_sensor(model, head))
        .collect()
}

/// Front-end figures over the scans: objects matched to a truth head within 0.5 m.
#[derive(Debug, Default)]
struct FrontEndFigures {
    scans: usize,
    heads: usize,
    matched: usize,
    /// Heads not matched while another head was within [`TOUCHING_M`] horizontally.
    missed_touching: usize,
    extra: usize,
    horizontal_error: f64,
    height_error: f64,
    render_s: f64,
    frontend_s: f64,
}

/// The room run with `seed` through the front end: the replay lines (descriptor, sets, truth) and figures.
fn room_lines(seed: u64) -> (Vec<ReplayLine>, FrontEndFigures) {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    let simulation = Simulation::new(scenario.clone(), seed).unwrap();
    let (index, spec) = scenario.sensor("lidar").unwrap();
    let model = lidar_model(&scenario, "lidar");
    let descriptor = simulation.descriptors()[index].clone();
    let pattern = ScanPattern::ceiling(&model);
    let scene = LidarScene::default_room();
    let pipeline = LidarPipeline::new(LidarConfig::default()).unwrap();
    let mut figures = FrontEndFigures::default();
    let mut timed: Vec<(f64, ReplayLine)> = Vec::new();
    for k in 0..spec.frame_count(LAST_S) {
        let t = spec.frame_time(k);
        if t < FIRST_S {
            continue;
        }
        let clock = Instant::now();
        let scan = render_lidar_scan(&scenario, "lidar", &scene, &pattern, seed, t).unwrap();
        figures.render_s += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let cloud = PointCloud::from_points(scan.points());
        let segmentation = pipeline.segment(&cloud);
        let kept: Vec<[f64; 3]> = pipeline
            .measurements(&cloud)
            .into_iter()
            .filter(|m| in_region(&model, m))
            .collect();
        let measurements: Vec<Vec<f64>> = kept.iter().map(|m| m.to_vec()).collect();
        figures.frontend_s += clock.elapsed().as_secs_f64();
        let heads = heads(&scenario, &model, seed, t);
        score_objects(
            &heads,
            &segmentation
                .objects
                .iter()
                .map(|o| o.centre)
                .collect::<Vec<_>>(),
            &model,
            &mut figures,
        );
        let covariances = pipeline.covariances(&kept, model.noise_std).map(|all| {
            all.iter()
                .map(|c| c.iter().map(|row| row.to_vec()).collect())
                .collect()
        });
        let mut set = MeasurementSet::new(descriptor.sensor.clone(), k, START + t, measurements);
        set.covariances = covariances;
        timed.push((START + t, ReplayLine::Measurements(set)));
    }
    for k in 0..scenario.truth_count(LAST_S) {
        let truth: TruthSet = simulation.truth_set(k);
        if truth.stamp >= START + FIRST_S {
            timed.push((truth.stamp, ReplayLine::Truth(truth)));
        }
    }
    timed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut lines = vec![ReplayLine::Descriptor(descriptor)];
    lines.extend(timed.into_iter().map(|(_, line)| line));
    (lines, figures)
}

/// Matches each truth head (sensor frame) to the nearest object within 0.5 m; accumulates the errors
/// in the ground's frame (world z is the sensor frame's `up` of the model).
fn score_objects(
    heads: &[[f64; 3]],
    objects: &[[f64; 3]],
    model: &LidarModel,
    figures: &mut FrontEndFigures,
) {
    let up = sensor_up(model);
    figures.scans += 1;
    figures.heads += heads.len();
    let mut used = vec![false; objects.len()];
    let norm = |v: [f64; 3]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    for head in heads {
        let nearest = objects
            .iter()
            .enumerate()
            .filter(|(i, _)| !used[*i])
            .map(|(i, o)| (i, [0, 1, 2].map(|a| o[a] - head[a])))
            .min_by(|a, b| norm(a.1).total_cmp(&norm(b.1)));
        let horizontal = |v: [f64; 3]| {
            let vertical: f64 = (0..3).map(|a| v[a] * up[a]).sum();
            (norm([0, 1, 2].map(|a| v[a] - up[a] * vertical)), vertical)
        };
        if let Some((i, error)) = nearest.filter(|(_, e)| norm(*e) < 0.5) {
            used[i] = true;
            figures.matched += 1;
            let (across, vertical) = horizontal(error);
            figures.height_error += vertical.abs();
            figures.horizontal_error += across;
        } else if heads.iter().any(|other| {
            other != head && horizontal([0, 1, 2].map(|a| other[a] - head[a])).0 < TOUCHING_M
        }) {
            figures.missed_touching += 1;
        }
    }
    figures.extra += used.iter().filter(|u| !**u).count();
}

/// What the server's replay made of a run, scored from `FIRST_S + SETTLE_S` on.
struct ServerFigures {
    ospa: f64,
    /// Share of the track sets with as many tracks as people.
    right: f64,
    /// Track sets with more tracks than people, and with fewer.
    over: usize,
    under: usize,
    sets: usize,
    /// Share right among the track sets in which no two people are within [`APART_M`], and
    /// how many such sets there are.
    right_apart: f64,
    apart_sets: usize,
}

impl std::fmt::Display for ServerFigures {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "mean OSPA {:.3} m from {:.0} s on, count right in {:.1} % of track sets \
             (too many tracks in {}, too few in {}, of {}; right in {:.1} % of the {} sets in \
             which no two people are within {APART_M} m)",
            self.ospa,
            FIRST_S + SETTLE_S,
            100.0 * self.right,
            self.over,
            self.under,
            self.sets,
            100.0 * self.right_apart,
            self.apart_sets
        )
    }
}

/// Runs the server's offline replay over `lines` (in stamp order) of the room's run `seed` and
/// scores it.
fn server_figures(lines: &[ReplayLine], seed: u64) -> ServerFigures {
    let mut input = Vec::new();
    for line in lines {
        serde_json::to_writer(&mut input, line).unwrap();
        input.push(b'\n');
    }
    let report = replay(ServerConfig::default(), input.as_slice(), std::io::sink()).unwrap();
    assert_eq!(report.bad_lines, 0);
    let from = START + FIRST_S + SETTLE_S;
    let scored: Vec<_> = report.scores.iter().filter(|s| s.stamp >= from).collect();
    let count = |keep: &dyn Fn(usize, usize) -> bool| {
        scored
            .iter()
            .filter(|s| keep(s.track_count, s.truth_count))
            .count()
    };
    let room = simulator::default_room();
    let apart: Vec<_> = scored
        .iter()
        .filter(|s| {
            room.closest_pair_m(seed, s.stamp - START)
                .is_none_or(|d| d >= APART_M)
        })
        .collect();
    let apart_right = apart
        .iter()
        .filter(|s| s.track_count == s.truth_count)
        .count();
    ServerFigures {
        right_apart: apart_right as f64 / apart.len().max(1) as f64,
        apart_sets: apart.len(),
        ospa: report.mean_ospa_from(from).unwrap(),
        right: count(&|tracks, truth| tracks == truth) as f64 / scored.len() as f64,
        over: count(&|tracks, truth| tracks > truth),
        under: count(&|tracks, truth| tracks < truth),
        sets: scored.len(),
    }
}

/// The LIDAR's simulated sets of the room (the simulator's measurement model: independent misses
/// and uniform clutter as the descriptor says) with the truth, in stamp order: what the fusion
/// makes of this sensor when its front end is as good as its descriptor claims.
fn simulated_lines(seed: u64) -> Vec<ReplayLine> {
    let mut scenario = simulator::default_room();
    scenario.start = Some(START);
    scenario.sensors.retain(|s| s.sensor.as_str() == "lidar");
    let (descriptors, sets) = simulator::descriptors_and_sets(&scenario, seed, LAST_S).unwrap();
    let simulation = Simulation::new(scenario.clone(), seed).unwrap();
    let truths = (0..scenario.truth_count(LAST_S)).map(|k| simulation.truth_set(k));
    let mut timed: Vec<(f64, ReplayLine)> = sets
        .into_iter()
        .map(|s| (s.stamp, ReplayLine::Measurements(s)))
        .chain(truths.map(|t| (t.stamp, ReplayLine::Truth(t))))
        .filter(|(stamp, _)| *stamp >= START + FIRST_S)
        .collect();
    timed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut lines: Vec<ReplayLine> = descriptors
        .into_iter()
        .map(ReplayLine::Descriptor)
        .collect();
    lines.extend(timed.into_iter().map(|(_, line)| line));
    lines
}

#[test]
fn room_tracks_from_raw_lidar_scans() {
    let (mut worst_ospa, mut worst_right) = (0.0f64, 1.0f64);
    let (mut sum_ospa, mut sum_right) = (0.0, 0.0);
    for seed in [1, 2, 3] {
        println!(
            "room seed {seed}, the LIDAR's simulated sets: {}",
            server_figures(&simulated_lines(seed), seed)
        );
        let (lines, f) = room_lines(seed);
        let server = server_figures(&lines, seed);
        let matched = f.matched.max(1) as f64;
        println!(
            "room seed {seed}: {} scans, front end: {:.1} % of heads found ({} of the {} missed \
             within {TOUCHING_M} m of another head), {:.2} extra objects per scan, \
             errors horizontal {:.3} m, height {:.3} m; render {:.1} ms, front end {:.1} ms per scan; \
             server: {server}",
            f.scans,
            100.0 * f.matched as f64 / f.heads as f64,
            f.missed_touching,
            f.heads - f.matched,
            f.extra as f64 / f.scans as f64,
            f.horizontal_error / matched,
            f.height_error / matched,
            1e3 * f.render_s / f.scans as f64,
            1e3 * f.frontend_s / f.scans as f64,
        );
        worst_ospa = worst_ospa.max(server.ospa);
        worst_right = worst_right.min(server.right);
        sum_ospa += server.ospa;
        sum_right += server.right;
    }
    println!(
        "room over 3 seeds: mean OSPA {:.3} m (worst {worst_ospa:.3}), count right {:.1} % (worst {:.1} %)",
        sum_ospa / 3.0,
        100.0 * sum_right / 3.0,
        100.0 * worst_right
    );
    // The goal: OSPA ≤ 0.15 m with the count right in ≥ 90 % of the sets. Today 0.050–0.066 m and
    // 95.5–100 % (98.5 % over the seeds; 0.050–0.057 m and 99.4 % without the server's occlusion
    // model), against 0.04–0.05 m and 100 % for the LIDAR's simulated
    // sets: the front end finds 98–99 % of heads with 0.01–0.03 extra objects per scan (a person's
    // shoulder, arm or legs seen as a segment of their own is dropped, `frontends/src/lidar/body_parts.rs`).
    // With a range jump of 0.25 m (and body parts dropped only 0.3 m below a head) a person who
    // walked within about 0.4 m of a long wall joined the wall's segment and went unseen for
    // 0.5–1.5 s: 0.055–0.086 m and 90.0–100 %. Each seed is held to the goal.
    assert!(worst_ospa <= 0.15, "mean OSPA {worst_ospa:.3} m");
    assert!(
        sum_right / 3.0 >= 0.9,
        "count right in {:.1} % over the seeds",
        100.0 * sum_right / 3.0
    );
    assert!(
        worst_right >= 0.9,
        "count right in {:.1} %",
        100.0 * worst_right
    );
}

/// Four walkers 5–25 m from a level VLP-16 1.8 m up, two poles among them.
const OUTDOOR: &str = r#"
duration_s = 10.0
truth_rate_hz = 10.0
[[targets]]
id = 1
motion = { kind = "constant_velocity", position = [5.0, 1.0, 1.75], velocity = [0.0, 0.5, 0.0] }
[[targets]]
id = 2
motion = { kind = "constant_velocity", position = [11.0, -3.0, 1.70], velocity = [0.3, 0.4, 0.0] }
[[targets]]
id = 3
motion = { kind = "constant_velocity", position = [20.0, 4.0, 1.80], velocity = [0.0, -0.6, 0.0] }
[[targets]]
id = 4
motion = { kind = "constant_velocity", position = [25.0, -2.0, 1.75], velocity = [-0.4, 0.3, 0.0] }
[[sensors]]
sensor = "vlp16"
detection_probability = 0.9
clutter_rate = 1.0
rate_hz = 10.0
phase_s = 0.0
[sensors.model]
kind = "lidar"
position = [0.0, 0.0, 1.8]
orientation = [1.0, 0.0, 0.0, 0.0]
noise_std = [0.05, 0.005, 0.01]
max_range = 100.0
elevation_limits = [-0.27, 0.27]
"#;

const POLES: [Pole; 2] = [
    Pole {
        centre: [15.0, 0.5],
        radius: 0.08,
        height: 4.0,
    },
    Pole {
        centre: [22.0, -5.0],
        radius: 0.1,
        height: 3.5,
    },
];

#[test]
fn outdoor_walkers_are_found_at_their_centres_out_to_25_m_and_poles_are_not() {
    let scenario = Scenario::from_toml_str(OUTDOOR).unwrap();
    let model = lidar_model(&scenario, "vlp16");
    let scene = LidarScene::open_ground(POLES.to_vec());
    let pattern = ScanPattern::new(BeamLayout::vlp16());
    let pipeline = LidarPipeline::new(LidarConfig::default()).unwrap();
    let horizontal = |p: [f64; 3]| p[0].hypot(p[1]);
    let (mut far_heads, mut far_found, mut worst_far_range_error) = (0, 0, 0.0f64);
    let mut range_errors = Vec::new();
    for step in 0..10 {
        let t = 0.5 * step as f64;
        let scan = render_lidar_scan(&scenario, "vlp16", &scene, &pattern, 5, t).unwrap();
        let segmentation = pipeline.segment(&PointCloud::from_points(scan.points()));
        assert!(segmentation.range_image);
        for pole in &POLES {
            let near_pole = segmentation
                .objects
                .iter()
                .any(|o| (o.centre[0] - pole.centre[0]).hypot(o.centre[1] - pole.centre[1]) < 0.5);
            assert!(!near_pole, "t = {t}: a pole reported as a person");
        }
        for (id, head) in heads(&scenario, &model, 5, t).iter().enumerate() {
            let nearest = segmentation
                .objects
                .iter()
                .map(|o| o.centre)
                .min_by(|a, b| {
                    let d = |p: &[f64; 3]| (p[0] - head[0]).hypot(p[1] - head[1]);
                    d(a).total_cmp(&d(b))
                })
                .filter(|p| (p[0] - head[0]).hypot(p[1] - head[1]) < 0.5);
            let far = horizontal(*head) >= 20.0;
            far_heads += usize::from(far);
            let Some(centre) = nearest else {
                println!(
                    "t = {t:.1}: walker {} at {:.1} m not found",
                    id + 1,
                    horizontal(*head)
                );
                continue;
            };
            let range_error = horizontal(centre) - horizontal(*head);
            range_errors.push(range_error);
            if far {
                far_found += 1;
                worst_far_range_error = worst_far_range_error.max(range_error.abs());
            }
            if step % 3 == 0 {
                println!(
                    "t = {t:.1}: walker {} at {:5.2} m: centre off by {:+.3} m in range, {:.3} m across",
                    id + 1,
                    horizontal(*head),
                    range_error,
                    (centre[1] * head[0] - centre[0] * head[1]).abs() / horizontal(*head),
                );
            }
        }
    }
    let mean = range_errors.iter().sum::<f64>() / range_errors.len() as f64;
    let mean_abs = range_errors.iter().map(|e| e.abs()).sum::<f64>() / range_errors.len() as f64;
    println!(
        "outdoor: {} of {far_heads} walker sightings at 20 m or more found (worst range error {worst_far_range_error:.3} m); \
         over all {} found: range error mean {mean:+.3} m, mean |error| {mean_abs:.3} m",
        far_found,
        range_errors.len()
    );
    // One sighting in 20 is lost today (walker 3 at 20.4 m, side on: two rings of four returns, one dropped).
    assert!(
        far_found * 10 >= far_heads * 9,
        "people at 20+ m missed: {far_found} of {far_heads}"
    );
    assert!(
        worst_far_range_error < 0.08,
        "far range error {worst_far_range_error:.3} m"
    );
    assert!(mean.abs() < 0.03 && mean_abs < 0.05);
}

/// Seconds of the outdoor scene run end to end.
const OUTDOOR_S: f64 = 20.0;

/// What a user of the outdoor VLP-16 would write for the server: the site's volume around the
/// sensor; every other key keeps its default.
const OUTDOOR_SERVER: &str = r#"
[site]
name = "default"
volume_min = [-2.0, -15.0, 0.0]
volume_max = [30.0, 15.0, 2.5]
"#;

/// The outdoor scene's scans rendered for `OUTDOOR_S` seconds of run `seed` as KITTI files,
/// through the real `edge-agent lidar --scans` (its default front end, the descriptor it
/// announces), and the server's replay with [`OUTDOOR_SERVER`]: mean OSPA(x, y) (c = 1 m) and
/// the share of track sets with the right count, from 2 s on (confirmation).
fn outdoor_tracks(seed: u64) -> (f64, f64) {
    let mut scenario = Scenario::from_toml_str(OUTDOOR).unwrap();
    scenario.start = Some(START);
    scenario.duration_s = OUTDOOR_S;
    let (_, spec) = scenario.sensor("vlp16").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let scans = dir.path().join("scans");
    std::fs::create_dir_all(&scans).unwrap();
    let (scene, pattern) = (
        LidarScene::open_ground(POLES.to_vec()),
        ScanPattern::new(BeamLayout::vlp16()),
    );
    for k in 0..spec.frame_count(OUTDOOR_S) {
        let scan = render_lidar_scan(
            &scenario,
            "vlp16",
            &scene,
            &pattern,
            seed,
            spec.frame_time(k),
        )
        .unwrap();
        let cloud = PointCloud::from_points(scan.points());
        frontends::lidar::write_kitti_bin(scans.join(format!("{k:06}.bin")), &cloud).unwrap();
    }
    let descriptor = dir.path().join("vlp16.json");
    std::fs::write(
        &descriptor,
        serde_json::to_vec(&spec.descriptor(&scenario.site)).unwrap(),
    )
    .unwrap();
    let output = std::process::Command::new(checker::processes::binary("edge-agent").unwrap())
        .args([
            "lidar",
            "--rate",
            "10",
            "--start",
            &(START + spec.phase_s).to_string(),
            "--output",
            "-",
        ])
        .arg("--scans")
        .arg(&scans)
        .arg("--descriptor")
        .arg(&descriptor)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut input = output.stdout;
    for k in 0..scenario.truth_count(OUTDOOR_S) {
        serde_json::to_writer(
            &mut input,
            &ReplayLine::Truth(simulator::truth_set(&scenario, seed, START, k)),
        )
        .unwrap();
        input.push(b'\n');
    }
    let config_file = dir.path().join("server.toml");
    std::fs::write(&config_file, OUTDOOR_SERVER).unwrap();
    let config = ServerConfig::load(Some(&config_file)).unwrap();
    let report = replay(config, input.as_slice(), std::io::sink()).unwrap();
    assert_eq!(report.bad_lines, 0);
    horizontal_figures(&report.tracks, &report.truth, START + 2.0)
}

/// Mean OSPA(x, y) (c = 1 m, p = 1) and the share of right counts of the track sets from `from` on,
/// each against the truth set nearest in time.
fn horizontal_figures(tracks: &[protocol::TrackSet], truth: &[TruthSet], from: f64) -> (f64, f64) {
    let params = gmphd::metrics::MetricParams::new(1.0, 1.0).unwrap();
    let plane = |p: &[f64; 3]| nalgebra::DVector::from_row_slice(&p[..2]);
    let (mut sum, mut right, mut n) = (0.0, 0usize, 0usize);
    for set in tracks.iter().filter(|s| s.stamp >= from) {
        let Some(nearest) = truth.iter().min_by(|a, b| {
            (a.stamp - set.stamp)
                .abs()
                .total_cmp(&(b.stamp - set.stamp).abs())
        }) else {
            continue;
        };
        let x: Vec<_> = nearest.objects.iter().map(|o| plane(&o.position)).collect();
        let y: Vec<_> = set.tracks.iter().map(|t| plane(&t.position)).collect();
        sum += gmphd::metrics::ospa(&x, &y, params).unwrap().distance;
        right += usize::from(x.len() == y.len());
        n += 1;
    }
    (sum / n.max(1) as f64, right as f64 / n.max(1) as f64)
}

#[test]
fn outdoor_walkers_are_tracked_out_to_25_m() {
    for seed in [1, 2, 3] {
        let (ospa_xy, right) = outdoor_tracks(seed);
        println!(
            "outdoor seed {seed}: four walkers at 5-25 m, mean OSPA(x, y) {ospa_xy:.3} m, count right {:.1} %",
            100.0 * right
        );
        // Seeds 1-3: 0.025-0.026 m and 100 %. From 8 s on walker 2 (13.4 m) hides walker 4
        // (21.8 m) on the same bearing for 1.7 s: no return of walker 4 exists. The server's
        // occlusion model (`filter.occlusion_radius_m`) expects no detection behind walker 2, so
        // walker 4's track waits there; without it (0.040-0.042 m, 91.7-92.2 %) the track ended
        // and was born again.
        assert!(ospa_xy <= 0.1, "mean OSPA(x, y) {ospa_xy:.3} m");
        assert!(right >= 0.95, "count right in {:.1} %", 100.0 * right);
    }
}
