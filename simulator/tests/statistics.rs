//! Simulated sets have the statistics their descriptors promise: detection frequency,
//! clutter count and measurement noise.

use nalgebra::{DVector, Vector3};
use simulator::{Scenario, Simulation};

const SEED: u64 = 7;

/// A scenario of `targets` still targets (ids 1..) at the given points and one sensor.
fn scenario(points: &[[f64; 3]], sensor: &str) -> Scenario {
    let mut text = String::from("duration_s = 1000.0\ntruth_rate_hz = 1.0\n");
    for (i, p) in points.iter().enumerate() {
        text += &format!(
            "[[targets]]\nid = {}\nmotion = {{ kind = \"constant_velocity\", position = {p:?}, \
             velocity = [0.0, 0.0, 0.0] }}\n",
            i + 1
        );
    }
    text += sensor;
    Scenario::from_toml_str(&text).unwrap()
}

/// A position sensor over a 10 m cube with the given p_D and clutter rate.
fn position_sensor(p_d: f64, clutter: f64) -> String {
    format!(
        "[[sensors]]\nsensor = \"s\"\ndetection_probability = {p_d:?}\nclutter_rate = {clutter:?}\n\
         rate_hz = 10.0\nmodel = {{ kind = \"position\", noise_std = [0.01, 0.01, 0.01], \
         region = {{ min = [0.0, 0.0, 0.0], max = [10.0, 10.0, 10.0] }} }}\n"
    )
}

#[test]
fn detected_fraction_matches_detection_probability() {
    let points = [[1.0, 1.0, 1.0], [5.0, 5.0, 5.0], [9.0, 2.0, 4.0]];
    let simulation =
        Simulation::with_start(scenario(&points, &position_sensor(0.7, 0.0)), SEED, 0.0).unwrap();
    let frames = 2000;
    let detections: usize = (0..frames)
        .map(|k| simulation.measurement_set(0, k).unwrap().measurements.len())
        .sum();
    let fraction = detections as f64 / (frames as usize * points.len()) as f64;
    println!("detected fraction {fraction:.4} (p_D 0.7)");
    // The binomial standard error is 0.006; allow five of them.
    assert!((fraction - 0.7).abs() < 0.03, "fraction {fraction}");
}

#[test]
fn clutter_count_is_poisson_with_the_clutter_rate_and_stays_in_the_region() {
    let simulation =
        Simulation::with_start(scenario(&[], &position_sensor(0.9, 3.5)), SEED, 0.0).unwrap();
    let frames = 4000;
    let counts: Vec<f64> = (0..frames)
        .map(|k| {
            let set = simulation.measurement_set(0, k).unwrap();
            for z in &set.measurements {
                assert!(
                    z.iter().all(|v| (0.0..=10.0).contains(v)),
                    "clutter {z:?} outside"
                );
            }
            set.measurements.len() as f64
        })
        .collect();
    let mean = counts.iter().sum::<f64>() / frames as f64;
    let var = counts.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / frames as f64;
    println!("clutter per set: mean {mean:.3}, variance {var:.3} (rate 3.5)");
    assert!((mean - 3.5).abs() < 0.15, "mean clutter {mean}");
    assert!((var - 3.5).abs() < 0.5, "clutter variance {var}");
}

/// Per-component sample standard deviation of `residual(z, h(x))` over many frames of a
/// sensor seeing one still target with p_D 1 and no clutter.
fn residual_std(point: [f64; 3], sensor: &str, frames: u64) -> Vec<f64> {
    let simulation = Simulation::with_start(scenario(&[point], sensor), SEED, 0.0).unwrap();
    let model = simulation.sensors()[0].model();
    let truth = model.measure(&Vector3::from(point));
    let residuals: Vec<DVector<f64>> = (0..frames)
        .map(|k| {
            let set = simulation.measurement_set(0, k).unwrap();
            assert_eq!(
                set.measurements.len(),
                1,
                "frame {k}: {:?}",
                set.measurements
            );
            model.residual(&DVector::from_vec(set.measurements[0].clone()), &truth)
        })
        .collect();
    (0..model.dim())
        .map(|i| {
            let mean = residuals.iter().map(|r| r[i]).sum::<f64>() / frames as f64;
            let var = residuals.iter().map(|r| (r[i] - mean).powi(2)).sum::<f64>() / frames as f64;
            var.sqrt()
        })
        .collect()
}

fn assert_within_ten_percent(kind: &str, measured: &[f64], expected: &[f64]) {
    println!("{kind}: noise std {measured:?}, descriptor {expected:?}");
    for (m, e) in measured.iter().zip(expected) {
        assert!((m / e - 1.0).abs() < 0.1, "{kind}: std {m} vs {e}");
    }
}

const FRAMES: u64 = 2000;

#[test]
fn camera_noise_matches_its_descriptor() {
    let camera = "[[sensors]]\nsensor = \"cam\"\ndetection_probability = 1.0\nclutter_rate = 0.0\n\
        rate_hz = 25.0\nmodel = { kind = \"camera\", projection = [[800.0, 0.0, 320.0, -400.0], \
        [0.0, 800.0, 240.0, -300.0], [0.0, 0.0, 1.0, -2.0]], image_size = [640, 480], \
        noise_std = [3.0, 5.0] }\n";
    let std = residual_std([0.2, 0.1, 4.0], camera, FRAMES);
    assert_within_ten_percent("camera", &std, &[3.0, 5.0]);
}

#[test]
fn mic_pair_noise_matches_its_descriptor() {
    let mics = "[[sensors]]\nsensor = \"mics\"\ndetection_probability = 1.0\nclutter_rate = 0.0\n\
        rate_hz = 4.0\nmodel = { kind = \"mic_pair\", mics = [[0.0, 0.0, 1.5], [0.5, 0.0, 1.5]], \
        noise_std = 6.25e-5 }\n";
    let std = residual_std([1.0, 1.5, 1.7], mics, FRAMES);
    assert_within_ten_percent("mic_pair", &std, &[6.25e-5]);
}

#[test]
fn lidar_noise_matches_its_descriptor() {
    let lidar =
        "[[sensors]]\nsensor = \"lidar\"\ndetection_probability = 1.0\nclutter_rate = 0.0\n\
        rate_hz = 10.0\nmodel = { kind = \"lidar\", position = [0.0, 0.0, 0.0], \
        orientation = [1.0, 0.0, 0.0, 0.0], noise_std = [0.05, 0.01, 0.02], max_range = 30.0, \
        elevation_limits = [-0.5, 0.5] }\n";
    // Azimuth near ±π, so wrapping must keep the residuals small.
    let std = residual_std([-5.0, 0.01, 0.5], lidar, FRAMES);
    assert_within_ten_percent("lidar", &std, &[0.05, 0.01, 0.02]);
}

#[test]
fn bearing_range_noise_matches_its_descriptor() {
    let radar =
        "[[sensors]]\nsensor = \"radar\"\ndetection_probability = 1.0\nclutter_rate = 0.0\n\
        rate_hz = 1.0\nmodel = { kind = \"bearing_range\", position = [0.0, 0.0, 0.0], \
        noise_std = [0.02, 0.5], max_range = 100.0 }\n";
    let std = residual_std([30.0, 40.0, 0.0], radar, FRAMES);
    assert_within_ten_percent("bearing_range", &std, &[0.02, 0.5]);
}

#[test]
fn position_noise_matches_its_descriptor() {
    let position =
        "[[sensors]]\nsensor = \"gps\"\ndetection_probability = 1.0\nclutter_rate = 0.0\n\
        rate_hz = 1.0\nmodel = { kind = \"position\", noise_std = [0.1, 0.2, 0.3], \
        region = { min = [0.0, 0.0, 0.0], max = [10.0, 10.0, 10.0] } }\n";
    let std = residual_std([5.0, 5.0, 5.0], position, FRAMES);
    assert_within_ten_percent("position", &std, &[0.1, 0.2, 0.3]);
}

#[test]
fn wrapped_angles_stay_in_range() {
    let lidar =
        "[[sensors]]\nsensor = \"lidar\"\ndetection_probability = 1.0\nclutter_rate = 2.0\n\
        rate_hz = 10.0\nmodel = { kind = \"lidar\", position = [0.0, 0.0, 0.0], \
        orientation = [1.0, 0.0, 0.0, 0.0], noise_std = [0.05, 0.05, 0.01], max_range = 30.0, \
        elevation_limits = [-0.5, 0.5] }\n";
    let simulation =
        Simulation::with_start(scenario(&[[-5.0, 0.001, 0.0]], lidar), SEED, 0.0).unwrap();
    let mut crossed = [false, false];
    for k in 0..500 {
        for z in simulation.measurement_set(0, k).unwrap().measurements {
            let azimuth = z[1];
            assert!(
                (-std::f64::consts::PI..std::f64::consts::PI).contains(&azimuth),
                "{z:?}"
            );
            crossed[usize::from(azimuth > 0.0)] = true;
        }
    }
    assert_eq!(
        crossed,
        [true, true],
        "noise should carry the azimuth across ±π"
    );
}
