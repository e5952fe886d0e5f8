//! Vo & Ma's linear GM-PHD demo (the public MATLAB demo of "The Gaussian mixture
//! probability hypothesis density filter", 2006), re-run over 50 seeded Monte-Carlo
//! runs and scored with OSPA (c = 100 m, p = 1) on positions.
//!
//! Truth: the 12 targets of the demo's `gen_truth.m` (its state [x; vx; y; vy]
//! reordered to our [x, y, vx, vy]), noiseless constant velocity, born at k = 1,
//! 20, 40, 60, 80; targets 1 and 3 exist up to k = 70. As in the demo, the state
//! recorded at a target's birth step has already been propagated once.
//! Filter: as the demo (p_S 0.99, p_D 0.98, 60 clutter returns per scan over
//! [−1000, 1000]², σ = 10 m, four birth components of weight 0.03 with
//! P = diag(10²), T = 1e-5, U = 4, J_max = 100), except that the process noise is
//! our continuous white-noise acceleration with σ_v = 5 m/s² rather than the demo's
//! discretised one (position variance dt³/3 instead of dt⁴/4 per unit σ_v²; with
//! the demo's exact discrete noise the figures below agree to 0.1 m).
//!
//! Acceptance bounds. Measured with these seeds: mean OSPA ≈ 20.8 m, the extracted
//! cardinality exactly right in ≈ 43 % of the steps, mean extracted cardinality
//! ≈ 7.5 for a true mean of ≈ 7.3. Exact per-step cardinality is not something
//! the PHD filter delivers in this scenario, and the numbers follow from the
//! model, not from an implementation defect (the update is checked against the
//! textbook formula in `update_reference.rs`):
//! * a clutter return within ≈ 38 m of a target (q(z) > κ with S ≈ 180 m²,
//!   κ = 60 / 4e6 m⁻²) gets weight > 0.5 of its own — ≈ 7 % per target and scan;
//! * a missed detection (2 %) leaves the target's weight at 0.02, and it takes two
//!   or three scans to climb back above 0.5.
//!
//! so each target is counted right in ≈ 0.93 · 0.94 of the scans, and all of ≈ 7.3
//! targets in ≈ 0.87^7.3 ≈ 0.4 of them. The test therefore asserts bounds a
//! correct GM-PHD meets with margin — mean OSPA ≤ 23 m, cardinality right in ≥ 35 %
//! of the steps, mean extracted cardinality within 0.5 of the truth — and prints
//! the measured values.

mod common;

use common::vo_demo::{filter, sensor, CLUTTER_RATE, DETECTION_PROBABILITY, NOISE_STD, STEPS};
use gmphd::{GaussianMixture, Measurement, MeasurementModel, PositionSensor};
use nalgebra::{DVector, Vector2};
use pathfinding::kuhn_munkres::kuhn_munkres_min;
use pathfinding::matrix::Matrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};

const RUNS: u64 = 50;
const OSPA_CUTOFF: f64 = 100.0;

/// True positions at steps 1..=STEPS (index 0 is step 1).
fn truth() -> Vec<Vec<Vector2<f64>>> {
    common::vo_demo::truth()
        .iter()
        .map(|step| step.iter().map(|p| Vector2::new(p[0], p[1])).collect())
        .collect()
}

/// One scan: each target detected with p_D, then Poisson clutter (the demo's order).
fn scan(truth: &[Vector2<f64>], sensor: &PositionSensor, rng: &mut ChaCha8Rng) -> Vec<Measurement> {
    let noise = Normal::new(0.0, NOISE_STD).unwrap();
    let mut set = Vec::new();
    for p in truth {
        if rng.gen::<f64>() < DETECTION_PROBABILITY {
            let z = DVector::from_vec(vec![p.x + noise.sample(rng), p.y + noise.sample(rng)]);
            set.push(Measurement::new(z));
        }
    }
    let clutter = Poisson::new(CLUTTER_RATE).unwrap().sample(rng) as usize;
    for _ in 0..clutter {
        let u = [rng.gen::<f64>(), rng.gen::<f64>()];
        set.push(Measurement::new(sensor.sample_clutter(&u).unwrap()));
    }
    set
}

/// The demo's state extraction: every component with weight > 0.5 gives
/// round(weight) copies of its mean position.
fn extract(intensity: &GaussianMixture) -> Vec<Vector2<f64>> {
    intensity
        .iter()
        .filter(|c| c.weight > 0.5)
        .flat_map(|c| {
            let copies = c.weight.round() as usize;
            std::iter::repeat_n(Vector2::new(c.mean[0], c.mean[1]), copies)
        })
        .collect()
}

/// OSPA distance (Schuhmacher, Vo & Vo 2008) with cut-off `c` and order p = 1.
fn ospa(truth: &[Vector2<f64>], estimates: &[Vector2<f64>], c: f64) -> f64 {
    let (small, large) = if truth.len() <= estimates.len() {
        (truth, estimates)
    } else {
        (estimates, truth)
    };
    if large.is_empty() {
        return 0.0;
    }
    if small.is_empty() {
        return c;
    }
    // Integer costs for the Hungarian algorithm, in micrometres.
    const SCALE: f64 = 1e6;
    let costs: Vec<i64> = small
        .iter()
        .flat_map(|a| {
            large
                .iter()
                .map(move |b| ((a - b).norm().min(c) * SCALE).round() as i64)
        })
        .collect();
    let matrix = Matrix::from_vec(small.len(), large.len(), costs).unwrap();
    let (total, _) = kuhn_munkres_min(&matrix);
    let unmatched = (large.len() - small.len()) as f64;
    (total as f64 / SCALE + c * unmatched) / large.len() as f64
}

#[test]
fn ospa_of_a_perfect_estimate_is_zero_and_a_miss_costs_the_cutoff() {
    let a = vec![Vector2::new(0.0, 0.0), Vector2::new(10.0, 0.0)];
    assert_eq!(ospa(&a, &a, OSPA_CUTOFF), 0.0);
    assert_eq!(ospa(&a, &[], OSPA_CUTOFF), OSPA_CUTOFF);
    let one = [Vector2::new(10.0, 3.0)];
    assert!((ospa(&a, &one, OSPA_CUTOFF) - (3.0 + 100.0) / 2.0).abs() < 1e-9);
}

#[test]
fn vo_ma_linear_demo_monte_carlo() {
    let truth = truth();
    assert_eq!(truth[0].len(), 3);
    assert_eq!(truth[69].len(), 10);
    assert_eq!(truth[70].len(), 8);
    assert_eq!(truth[99].len(), 10);
    let sensor = sensor();
    let mut ospa_sum = 0.0;
    let mut right_cardinality = 0usize;
    let (mut estimated_count, mut true_count) = (0usize, 0usize);
    for run in 0..RUNS {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + run);
        let mut filter = filter();
        for (k, objects) in truth.iter().enumerate() {
            let measurements = scan(objects, &sensor, &mut rng);
            filter.predict_to((k + 1) as f64).unwrap();
            filter.update(&sensor, &measurements).unwrap();
            filter.reduce();
            assert!(filter.intensity().len() <= 100);
            let estimates = extract(filter.intensity());
            ospa_sum += ospa(objects, &estimates, OSPA_CUTOFF);
            right_cardinality += usize::from(estimates.len() == objects.len());
            estimated_count += estimates.len();
            true_count += objects.len();
        }
    }
    let total_steps = (RUNS as usize * STEPS) as f64;
    let mean_ospa = ospa_sum / total_steps;
    let cardinality_rate = right_cardinality as f64 / total_steps;
    let mean_estimated = estimated_count as f64 / total_steps;
    let mean_true = true_count as f64 / total_steps;
    println!(
        "Vo & Ma demo, {RUNS} runs x {STEPS} steps: mean OSPA(c=100, p=1) = {mean_ospa:.2} m, \
         cardinality right in {:.1}% of steps, mean cardinality {mean_estimated:.2} \
         estimated vs {mean_true:.2} true",
        100.0 * cardinality_rate
    );
    assert!(mean_ospa <= 23.0, "mean OSPA {mean_ospa:.2} m");
    assert!(
        cardinality_rate >= 0.35,
        "cardinality right in {cardinality_rate:.3}"
    );
    assert!((mean_estimated - mean_true).abs() <= 0.5);
    // The sensor is used through the trait object as the fusion server does.
    assert_eq!((&sensor as &dyn MeasurementModel).dim(), 2);
}
