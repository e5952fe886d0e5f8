//! The default room scenario (3 people, 2 cameras, 4 microphone pairs, 1 LIDAR) through the
//! offline pipeline: accuracy against the simulator's truth, and byte-for-byte determinism.

use fusion_server::config::ServerConfig;
use fusion_server::replay::replay;

fn room_replay_file(seed: u64, duration_s: f64) -> Vec<u8> {
    let mut scenario = simulator::default_room();
    scenario.start = Some(1_763_700_000.0);
    let mut out = Vec::new();
    for line in simulator::replay_lines(&scenario, seed, duration_s).expect("room scenario") {
        serde_json::to_writer(&mut out, &line).unwrap();
        out.push(b'\n');
    }
    out
}

#[test]
fn room_tracks_are_accurate_once_everyone_is_in() {
    let input = room_replay_file(7, 30.0);
    let mut output = Vec::new();
    let report = replay(ServerConfig::default(), input.as_slice(), &mut output).unwrap();
    assert_eq!(report.bad_lines, 0);
    let start = report.truth.first().unwrap().stamp;
    let all_in = report
        .truth
        .iter()
        .find(|t| t.objects.len() == 3)
        .map(|t| t.stamp)
        .unwrap();
    let settled = all_in + 2.0;
    let ospa_all = report.mean_ospa().unwrap();
    let ospa_settled = report.mean_ospa_from(settled).unwrap();
    let right = report
        .scores
        .iter()
        .filter(|s| s.stamp >= settled)
        .filter(|s| s.truth_count == s.track_count)
        .count() as f64
        / report.scores.iter().filter(|s| s.stamp >= settled).count() as f64;
    println!(
        "room, 30 s: {} track sets; mean OSPA {ospa_all:.3} m overall, {ospa_settled:.3} m from {:.1} s on; count right in {:.1} % of sets",
        report.outputs,
        settled - start,
        100.0 * right
    );
    assert!(
        ospa_settled < 0.2,
        "mean OSPA {ospa_settled} m once all are in"
    );
}

#[test]
fn replay_is_byte_for_byte_deterministic() {
    let input = room_replay_file(3, 8.0);
    let mut first = Vec::new();
    let mut second = Vec::new();
    replay(ServerConfig::default(), input.as_slice(), &mut first).unwrap();
    replay(ServerConfig::default(), input.as_slice(), &mut second).unwrap();
    assert!(!first.is_empty());
    assert_eq!(first, second);
}
