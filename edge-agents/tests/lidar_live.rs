//! Live LIDAR inputs: VLP-16 packets of rendered scans over loopback UDP give the clusters of the same scans
//! read as PCD files, one set per rotation, with malformed packets counted and skipped; a followed directory
//! takes scans as they appear.

mod common;

use std::io::{BufRead, BufReader};
use std::net::UdpSocket;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

use common::{check_replay, edge_agent_ok, START};
use frontends::lidar::{to_point, write_pcd, PcdEncoding, PointCloud};
use protocol::MeasurementSet;

const DESCRIPTOR: &str = r#"
sensor = "lidar1"
detection_probability = 0.9
clutter_rate = 1.0
[model]
kind = "lidar"
position = [0.0, 0.0, 1.5]
orientation = [1.0, 0.0, 0.0, 0.0]
noise_std = [0.05, 0.01, 0.01]
max_range = 20.0
elevation_limits = [-1.0, 1.0]
"#;

/// VLP-16 elevations by laser id (the manual's table).
const ELEVATIONS: [f64; 16] = [
    -15.0, 1.0, -13.0, 3.0, -11.0, 5.0, -9.0, 7.0, -7.0, 9.0, -5.0, 11.0, -3.0, 13.0, -1.0, 15.0,
];
/// Ground this far below the sensor.
const HEIGHT: f64 = 1.5;
/// Blocks of 0.4° (two firings 0.2° apart) per rotation: 75 packets.
const BLOCKS_PER_ROTATION: usize = 900;

/// Person-sized cylinders (x, y, radius) standing on the ground, 1.8 m tall, moving a little each rotation.
fn people(rotation: usize) -> [(f64, f64, f64); 3] {
    let shift = 0.1 * rotation as f64;
    [
        (4.0 + shift, 1.0, 0.25),
        (6.0, -2.0 - shift, 0.25),
        (-3.0, 3.0 + shift, 0.3),
    ]
}

/// Distance along a unit direction (sensor frame) to the ground or the nearest cylinder, within 100 m.
fn cast(direction: [f64; 3], rotation: usize) -> Option<f64> {
    let [dx, dy, dz] = direction;
    let mut best = if dz < 0.0 {
        -HEIGHT / dz
    } else {
        f64::INFINITY
    };
    for (cx, cy, r) in people(rotation) {
        let a = dx * dx + dy * dy;
        let b = -2.0 * (dx * cx + dy * cy);
        let c = cx * cx + cy * cy - r * r;
        let disc = b * b - 4.0 * a * c;
        if a < 1e-12 || disc < 0.0 {
            continue;
        }
        let t = (-b - disc.sqrt()) / (2.0 * a);
        let z = t * dz;
        if t > 0.0 && (-HEIGHT..=0.3).contains(&z) && t < best {
            best = t;
        }
    }
    (best < 100.0).then_some(best)
}

/// One rotation as VLP-16 packets and as the points those packets decode to (2 mm quantised), in order.
fn render(rotation: usize) -> (Vec<Vec<u8>>, PointCloud) {
    let mut packets = Vec::new();
    let mut points = Vec::new();
    for first in (0..BLOCKS_PER_ROTATION).step_by(12) {
        let mut bytes = vec![0u8; 1206];
        for b in 0..12 {
            let block = first + b;
            let units = (block * 40) as u16;
            let base = b * 100;
            bytes[base..base + 2].copy_from_slice(&[0xFF, 0xEE]);
            bytes[base + 2..base + 4].copy_from_slice(&units.to_le_bytes());
            for channel in 0..32 {
                let azimuth = f64::from(units) / 100.0 + if channel >= 16 { 0.2 } else { 0.0 };
                let elevation = ELEVATIONS[channel % 16];
                let (a, e) = (azimuth.to_radians(), elevation.to_radians());
                let direction = [e.cos() * a.cos(), -e.cos() * a.sin(), e.sin()];
                let distance = cast(direction, rotation)
                    .map_or(0u16, |t| (t / 0.002).round().min(65_535.0) as u16);
                let at = base + 4 + 3 * channel;
                bytes[at..at + 2].copy_from_slice(&distance.to_le_bytes());
                bytes[at + 2] = 50;
                if distance > 0 {
                    points.push(to_point(f64::from(distance) * 0.002, azimuth, elevation));
                }
            }
        }
        bytes[1204] = 0x37;
        bytes[1205] = 0x22;
        packets.push(bytes);
    }
    (packets, PointCloud::from_points(points))
}

/// Starts a live lidar agent with `args`, its stderr lines sent to the returned receiver.
fn live_agent(descriptor: &Path, args: &[&str]) -> (Child, Receiver<String>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_edge-agent"))
        .args(["lidar", "--descriptor"])
        .arg(descriptor)
        .args(args)
        .args(["--output", "-"])
        .env("RUST_LOG", "info")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("edge-agent starts");
    let stderr = child.stderr.take().expect("stderr");
    let (sender, lines) = channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            eprintln!("agent: {line}");
            let _ = sender.send(line);
        }
    });
    (child, lines)
}

/// Waits for a stderr line containing `text`; every line seen is kept in `log`.
fn wait_for(lines: &Receiver<String>, text: &str, log: &mut Vec<String>) {
    let deadline = Instant::now() + Duration::from_secs(20);
    while Instant::now() < deadline {
        if let Ok(line) = lines.recv_timeout(Duration::from_millis(100)) {
            let found = line.contains(text);
            log.push(line);
            if found {
                return;
            }
        }
    }
    panic!("no `{text}` in the agent's log: {log:#?}");
}

/// Centroids of a set as Cartesian points.
fn centroids(set: &MeasurementSet) -> Vec<[f64; 3]> {
    set.measurements
        .iter()
        .map(|m| {
            let (r, a, e) = (m[0], m[1], m[2]);
            [r * e.cos() * a.cos(), r * e.cos() * a.sin(), r * e.sin()]
        })
        .collect()
}

fn assert_same_clusters(live: &MeasurementSet, recorded: &MeasurementSet) -> f64 {
    let (a, b) = (centroids(live), centroids(recorded));
    assert_eq!(a.len(), b.len(), "{live:?} against {recorded:?}");
    let mut worst = 0.0f64;
    for p in &a {
        let nearest = b
            .iter()
            .map(|q| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 0.02,
            "centroid {p:?} is {nearest} m from the PCD path's"
        );
        worst = worst.max(nearest);
    }
    worst
}

#[test]
fn velodyne_packets_give_the_clusters_of_the_pcd_scans_one_set_per_rotation() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("lidar.toml");
    std::fs::write(&descriptor, DESCRIPTOR).expect("descriptor");
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).expect("scans dir");
    let rotations: Vec<_> = (0..3).map(render).collect();
    for (index, (_, cloud)) in rotations.iter().enumerate() {
        write_pcd(
            scans.join(format!("{index:03}.pcd")),
            cloud,
            PcdEncoding::Binary,
        )
        .expect("pcd");
    }
    let recorded = check_replay(&edge_agent_ok(&[
        "lidar",
        "--descriptor",
        descriptor.to_str().unwrap(),
        "--scans",
        scans.to_str().unwrap(),
        "--rate",
        "10",
        "--start",
        START,
        "--output",
        "-",
    ]));
    assert_eq!(recorded.sets.len(), 3);
    assert!(
        recorded.sets.iter().all(|s| s.measurements.len() == 3),
        "{:?}",
        recorded.sets
    );

    let port = UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let address = format!("127.0.0.1:{port}");
    let (agent, lines) = live_agent(
        &descriptor,
        &["--velodyne", &address, "--idle-timeout-s", "1"],
    );
    let mut log = Vec::new();
    wait_for(&lines, "listening for Velodyne data packets", &mut log);
    let sender = UdpSocket::bind("127.0.0.1:0").unwrap();
    let began = Instant::now();
    let mut sent = 0u32;
    for (rotation, (packets, _)) in rotations.iter().enumerate() {
        for (index, packet) in packets.iter().enumerate() {
            if rotation == 1 && index == 10 {
                // Malformed: a position-packet size, a bad flag, and an empty datagram.
                sender.send_to(&[0u8; 512], &address).unwrap();
                let mut bad = packet.clone();
                bad[500] = 0x12;
                sender.send_to(&bad, &address).unwrap();
                sender.send_to(&[], &address).unwrap();
            }
            sender.send_to(packet, &address).unwrap();
            sent += 1;
            // A VLP-16's pace: 754 packets a second.
            let due = began + Duration::from_micros(1326 * u64::from(sent));
            std::thread::sleep(due.saturating_duration_since(Instant::now()));
        }
    }
    // The first packet of a fourth rotation closes the third.
    sender.send_to(&render(3).0[0], &address).unwrap();
    let output = agent.wait_with_output().expect("agent ends");
    log.extend(lines.try_iter());
    assert!(output.status.success(), "{log:#?}");
    assert!(
        log.iter()
            .any(|l| l.contains("malformed Velodyne packet skipped")),
        "{log:#?}"
    );
    assert!(
        log.iter().any(|l| l.contains("the LIDAR input ended")),
        "{log:#?}"
    );
    let live = check_replay(&output.stdout);
    assert_eq!(live.sets.len(), 3, "one set per rotation");
    let worst = live
        .sets
        .iter()
        .zip(&recorded.sets)
        .map(|(a, b)| assert_same_clusters(a, b))
        .fold(0.0, f64::max);
    let gaps: Vec<String> = live
        .sets
        .windows(2)
        .map(|w| format!("{:.1} ms", (w[1].stamp - w[0].stamp) * 1e3))
        .collect();
    println!("velodyne: 3 rotations, 3 sets, largest centroid difference to the PCD path {:.2} mm, stamps apart {gaps:?}", worst * 1e3);
}

#[test]
fn a_followed_directory_takes_each_complete_scan_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let descriptor = dir.path().join("lidar.toml");
    std::fs::write(&descriptor, DESCRIPTOR).expect("descriptor");
    let scans = dir.path().join("scans");
    std::fs::create_dir(&scans).expect("scans dir");
    let (agent, lines) = live_agent(
        &descriptor,
        &["--scans", scans.to_str().unwrap(), "--follow"],
    );
    let mut log = Vec::new();
    wait_for(&lines, "following the directory", &mut log);
    for index in 0..3 {
        let cloud = render(index).1;
        if index == 1 {
            // Written under a hidden name and renamed into place.
            let hidden = scans.join(".001.pcd");
            write_pcd(&hidden, &cloud, PcdEncoding::Binary).expect("pcd");
            std::fs::rename(&hidden, scans.join("001.pcd")).expect("rename");
        } else {
            write_pcd(
                scans.join(format!("{index:03}.pcd")),
                &cloud,
                PcdEncoding::Binary,
            )
            .expect("pcd");
        }
        std::fs::write(scans.join(format!("notes{index}.txt")), "not a scan").expect("other file");
        std::thread::sleep(Duration::from_millis(400));
    }
    std::thread::sleep(Duration::from_millis(500));
    let stopped = Command::new("kill")
        .args(["-TERM", &agent.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(stopped.success());
    let output = agent.wait_with_output().expect("agent ends");
    log.extend(lines.try_iter());
    assert!(output.status.success(), "{log:#?}");
    let live = check_replay(&output.stdout);
    assert_eq!(live.sets.len(), 3, "each scan once: {log:#?}");
    assert!(
        live.sets.iter().all(|s| s.measurements.len() == 3),
        "{:?}",
        live.sets
    );
    println!(
        "follow: 3 scans written 400 ms apart, stamps apart {:?} s",
        live.sets
            .windows(2)
            .map(|w| w[1].stamp - w[0].stamp)
            .collect::<Vec<_>>()
    );
}
