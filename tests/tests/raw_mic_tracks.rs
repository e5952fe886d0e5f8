//! Two talkers in the default room, heard only by its four microphone pairs, end to end from the
//! raw signal: the rendered audio of each pair (speech-like voices through the image-source room,
//! T60 0.3 s, SNR 20 dB) through the mic-pair front end, its TDOA sets with the descriptor the
//! agent publishes through `fusion-server replay`'s engine, scored in the horizontal plane against
//! the truth in the frames in which someone talks; and the same with exact TDOAs in place of the
//! front end's, which tells the fusion's part of the gap from the front end's; and the front
//! end's misses and its clutter each alone.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use checker::processes::binary;
use checker::raw_inputs::write_stereo_wav;
use checker::replay_file;
use checker::talker_room::{server_config, two_talker_room, START};
use evaluation::TRUTH_TOLERANCE_S;
use fusion_server::config::ServerConfig;
use fusion_server::replay::replay;
use gmphd::metrics::{ospa, MetricParams};
use nalgebra::DVector;
use protocol::{MeasurementSet, ReplayLine, SensorModel, TrackSet, TruthSet};
use simulator::render::{render_mic_pair, AcousticRoom, Talker};
use simulator::{Scenario, SensorSpec};

/// Seconds simulated.
const SECONDS: f64 = 40.0;
/// Scored from here on: both talkers have appeared and talked by then.
const SETTLED_S: f64 = 6.0;

/// One pair's rendered audio through the real `edge-agent mic-pair --wav` (its front end, and the
/// descriptor it announces, refined from its own output): its replay lines.
fn agent_lines(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    dir: &Path,
) -> (Vec<ReplayLine>, Vec<Talker>) {
    let name = spec.sensor.as_str();
    let rendered =
        render_mic_pair(scenario, name, &AcousticRoom::default(), seed, SECONDS).unwrap();
    let wav = dir.join(format!("{name}.wav"));
    write_stereo_wav(&rendered, &wav).unwrap();
    let descriptor = dir.join(format!("{name}.json"));
    let given = spec.descriptor(&scenario.site);
    std::fs::write(&descriptor, serde_json::to_vec(&given).unwrap()).unwrap();
    let output = dir.join(format!("{name}.jsonl"));
    let mut command = Command::new(binary("edge-agent").unwrap());
    command
        .args(["mic-pair", "--wav"])
        .arg(&wav)
        .arg("--descriptor")
        .arg(&descriptor)
        .args(["--start", &START.to_string(), "--output"])
        .arg(&output)
        .env("RUST_LOG", "warn");
    let status = command.status().unwrap();
    assert!(status.success(), "edge-agent mic-pair failed for {name}");
    let lines = std::fs::read_to_string(&output)
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    (lines, rendered.talkers)
}

/// Every pair's agent lines (in the scenario's order of its sensors), and every talker's spurts,
/// shared by all pairs.
fn all_agent_lines(scenario: &Scenario, seed: u64) -> (Vec<Vec<ReplayLine>>, Vec<Talker>) {
    let dir = tempfile::tempdir().unwrap();
    let mut talkers = Vec::new();
    let mut pairs = Vec::new();
    for spec in &scenario.sensors {
        let (lines, heard) = agent_lines(scenario, spec, seed, dir.path());
        pairs.push(lines);
        talkers = heard;
    }
    (pairs, talkers)
}

/// The replay file: the simulator's truth and each pair's agent output, merged in stamp order.
/// Also returns every talker's spurts, shared by all pairs.
fn replay_file(scenario: &Scenario, seed: u64) -> (Vec<u8>, Vec<Talker>) {
    let (pairs, talkers) = all_agent_lines(scenario, seed);
    (merged(scenario, seed, pairs), talkers)
}

/// The simulator's truth and each pair's lines, merged in stamp order.
fn merged(scenario: &Scenario, seed: u64, pairs: Vec<Vec<ReplayLine>>) -> Vec<u8> {
    let truth = simulator::replay_lines(scenario, seed, SECONDS)
        .unwrap()
        .filter_map(|line| match line {
            ReplayLine::Truth(truth) => Some(truth),
            _ => None,
        });
    replay_file::replay_file(truth, pairs)
}

/// What a perfect front end would send: per frame of the agent's (4096 samples, stamped at its
/// centre), the exact TDOA of each talker's mouth in the frames in which the talker is heard
/// ([`Talker::is_active`]), nothing else; the pair's given descriptor.
fn exact_lines(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    talkers: &[Talker],
) -> Vec<ReplayLine> {
    let descriptor = spec.descriptor(&scenario.site);
    let mut lines = vec![ReplayLine::Descriptor(descriptor)];
    let frames = (SECONDS * f64::from(RATE)) as usize / FRAME;
    for frame in 0..frames {
        let centre = (frame * FRAME + FRAME / 2) as f64 / f64::from(RATE);
        let tdoas = talking_tdoas(scenario, spec, seed, talkers, centre)
            .into_iter()
            .map(|tau| vec![tau])
            .collect();
        let set = MeasurementSet::new(spec.sensor.clone(), frame as u64, START + centre, tdoas);
        lines.push(ReplayLine::Measurements(set));
    }
    lines
}

/// The agent's frames: samples per frame and per second.
const FRAME: usize = 4096;
const RATE: u32 = 16_000;

/// The exact TDOA, at the pair of `spec`, of each talker who is heard in the agent's frame
/// centred `centre` seconds after the start.
fn talking_tdoas(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    talkers: &[Talker],
    centre: f64,
) -> Vec<f64> {
    let SensorModel::MicPair(model) = &spec.model else {
        panic!("{} is a mic pair", spec.sensor)
    };
    let first = (centre * f64::from(RATE)).round() as usize - FRAME / 2;
    talkers
        .iter()
        .enumerate()
        .filter(|(_, talker)| talker.is_active(first, FRAME, RATE))
        .map(|(index, _)| {
            let mut mouth = scenario.position_of(index, seed, centre);
            mouth[2] -= simulator::render::mic_pair::MOUTH_BELOW_HEAD_M;
            let [m1, m2] = model.mics;
            (distance(mouth, m2) - distance(mouth, m1)) / model.speed_of_sound
        })
        .collect()
}

/// One pair's agent lines with each set's TDOAs sorted by whether a talking talker explains
/// them (within two samples): `true_part` keeps only those that one does; otherwise the set
/// keeps only those that none does and gets the exact TDOAs in place of the rest.
fn split_lines(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    talkers: &[Talker],
    lines: &[ReplayLine],
    true_part: bool,
) -> Vec<ReplayLine> {
    const TOLERANCE_S: f64 = 2.0 / RATE as f64;
    let mut out = lines.to_vec();
    for line in &mut out {
        let ReplayLine::Measurements(set) = line else {
            continue;
        };
        let exact = talking_tdoas(scenario, spec, seed, talkers, set.stamp - START);
        let explained = |z: &Vec<f64>| exact.iter().any(|tau| (z[0] - tau).abs() <= TOLERANCE_S);
        set.measurements.retain(|z| explained(z) == true_part);
        set.covariances = None;
        if !true_part {
            set.measurements.extend(exact.iter().map(|&tau| vec![tau]));
        }
    }
    out
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

fn someone_talks(talkers: &[Talker], t: f64) -> bool {
    talkers
        .iter()
        .any(|talker| talker.spurts.iter().any(|&(a, b)| a <= t && t < b))
}

fn horizontal(points: impl Iterator<Item = [f64; 3]>) -> Vec<DVector<f64>> {
    points.map(|p| DVector::from_row_slice(&p[..2])).collect()
}

/// Mean OSPA(x, y) (c = 1 m, p = 1) and the share of track sets with the right count, over the
/// settled track sets stamped while someone talks.
fn figures(tracks: &[TrackSet], truth: &[TruthSet], talkers: &[Talker]) -> (f64, f64, usize) {
    let truth: BTreeMap<u64, &TruthSet> = truth.iter().map(|t| (t.stamp.to_bits(), t)).collect();
    let params = MetricParams::new(1.0, 1.0).unwrap();
    let (mut sum, mut right, mut n) = (0.0, 0usize, 0usize);
    for set in tracks {
        let t = set.stamp - START;
        if t < SETTLED_S || !someone_talks(talkers, t) {
            continue;
        }
        let Some(nearest) = truth
            .values()
            .min_by(|a, b| {
                (a.stamp - set.stamp)
                    .abs()
                    .total_cmp(&(b.stamp - set.stamp).abs())
            })
            .filter(|n| (n.stamp - set.stamp).abs() <= TRUTH_TOLERANCE_S)
        else {
            continue;
        };
        let x = horizontal(nearest.objects.iter().map(|o| o.position));
        let y = horizontal(set.tracks.iter().map(|t| t.position));
        sum += ospa(&x, &y, params).unwrap().distance;
        right += usize::from(x.len() == y.len());
        n += 1;
    }
    (sum / n.max(1) as f64, right as f64 / n.max(1) as f64, n)
}

/// Replays `input` with `config`, prints its figures under `what` and returns the mean
/// OSPA(x, y) and the share of sets with the right count (see [`figures`]).
fn replayed_figures(
    config: ServerConfig,
    input: &[u8],
    talkers: &[Talker],
    what: &str,
) -> (f64, f64) {
    let report = replay(config, input, std::io::sink()).unwrap();
    assert_eq!(report.bad_lines, 0);
    let (ospa_xy, right, n) = figures(&report.tracks, &report.truth, talkers);
    println!(
        "{what}: {n} track sets while someone talks after {SETTLED_S} s: mean OSPA(x, y) {ospa_xy:.3} m, count right {:.0} %",
        100.0 * right
    );
    (ospa_xy, right)
}

#[test]
fn two_talkers_are_tracked_from_the_rendered_audio() {
    let scenario = two_talker_room(SECONDS);
    for seed in [1, 2, 3] {
        let (input, talkers) = replay_file(&scenario, seed);
        let what = format!("seed {seed}");
        let (ospa_xy, right) = replayed_figures(server_config().unwrap(), &input, &talkers, &what);
        // Floors under today's figures (0.43-0.49 m, 47-76 %; over seeds 1-5 0.432 m and 69 %, over
        // seeds 6-10 0.456 m and 55 %), far from the goal of 0.25 m and 80 %: they catch a chain gone
        // worse. A seed's count right moves by 20 points and more with small changes. Here the
        // talkers walk; on standing talkers synthesized elsewhere (`tools/speech_scene/`, 25 scenes)
        // the same chain gives 0.187 m and 93 %. Exact TDOAs in place of the front end's give
        // 0.13-0.31 m and 65-99 % (the test below).
        assert!(ospa_xy <= 0.58, "mean OSPA(x, y) {ospa_xy:.3} m");
        assert!(right >= 0.33, "count right in {:.0} %", 100.0 * right);
    }
}

/// The talkers' configuration for sets without side peaks: exact TDOAs have none, so the model
/// of them (`filter.tdoa_side_peak_offset_s`, on by default for what a real front end sends) is
/// turned off, as a user who fed such sets would. With it on, seed 1 gives 0.369 m and 52 %:
/// beside a track whose TDOA is uncertain, a side-peak hypothesis that no side peak confirms
/// spreads the track over three hyperbolas.
fn without_side_peaks() -> ServerConfig {
    let mut config = server_config().unwrap();
    config.filter.tdoa_side_peak_offset_s = 0.0;
    config
}

/// The fusion's part of the gap: the same chain with a perfect front end's sets in place of the
/// agent's (every talking talker's exact TDOA in every pair, no clutter) and the same descriptors:
/// a talker's pauses must not cost its track.
#[test]
fn exact_tdoas_show_what_the_fusion_makes_of_intermittent_talkers() {
    let scenario = two_talker_room(SECONDS);
    let (_, first) = scenario.sensor("mics_s").unwrap();
    assert!(matches!(first.model, SensorModel::MicPair(_)));
    for seed in [1, 2, 3] {
        let rendered =
            render_mic_pair(&scenario, "mics_s", &AcousticRoom::default(), seed, SECONDS).unwrap();
        let pairs = scenario
            .sensors
            .iter()
            .map(|spec| exact_lines(&scenario, spec, seed, &rendered.talkers))
            .collect();
        let input = merged(&scenario, seed, pairs);
        let (ospa_xy, right) = replayed_figures(
            without_side_peaks(),
            &input,
            &rendered.talkers,
            &format!("seed {seed}, exact TDOAs"),
        );
        // Floors under today's figures (0.13-0.31 m, 65-99 %; seed 1 is the hard one, where a
        // talker's track is lost for a while). Before the pauses were modelled and labels were
        // Bernoulli, 0.43-0.51 m and 16-37 %: each set without a silent talker counted as a miss,
        // its track was gone within a second, and its fading component merged into the talking
        // one's.
        assert!(ospa_xy <= 0.33, "mean OSPA(x, y) {ospa_xy:.3} m");
        assert!(right >= 0.6, "count right in {:.0} %", 100.0 * right);
    }
}

/// The front end's part of the gap, split in two: its TDOAs that a talking talker explains
/// (the clutter taken away, its misses left) and the exact TDOAs with its clutter added (its
/// misses taken away), each through the same chain.
#[test]
fn the_front_ends_misses_and_its_clutter_each_alone() {
    let scenario = two_talker_room(SECONDS);
    for seed in [1, 2, 3] {
        let (agents, talkers) = all_agent_lines(&scenario, seed);
        for (true_part, what) in [
            (true, "the TDOAs a talker explains"),
            (false, "the exact TDOAs and the clutter"),
        ] {
            let pairs = scenario
                .sensors
                .iter()
                .zip(&agents)
                .map(|(spec, lines)| split_lines(&scenario, spec, seed, &talkers, lines, true_part))
                .collect();
            let input = merged(&scenario, seed, pairs);
            let (ospa_xy, _) = replayed_figures(
                server_config().unwrap(),
                &input,
                &talkers,
                &format!("seed {seed}, {what} of the front end"),
            );
            // A ceiling over today's figures: the TDOAs a talker explains alone 0.39-0.56 m and
            // 16-59 % (a talker heard in fewer than half the frames: one track jumps from talker to
            // talker), the exact TDOAs with the clutter 0.26-0.40 m and 48-77 %. Either half of
            // what the front end gets wrong costs most of the goal on its own.
            assert!(ospa_xy <= 0.7, "mean OSPA(x, y) {ospa_xy:.3} m");
        }
    }
}
