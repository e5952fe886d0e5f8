//! Measurement simulation and scoring shared by the integration tests.
//!
//! Every test binary compiles this module and uses only part of it.
#![allow(dead_code)]

pub mod bare_filter;
pub mod vo_demo;
pub mod vo_nonlinear;

use gmphd::metrics::{ospa, MetricParams};
use gmphd::{
    Detection, Gaussian, GaussianMixture, Label, LabelledTracker, Measurement, MeasurementModel,
    MicPair,
};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};

/// Pham's four microphone pairs (thesis 5.6.2) in a 3 × 3 m room: 0.5 m spacing, one pair in the
/// middle of each wall, alternately at 1.2 m and 2.0 m, TDOA noise of one sample at 16 kHz.
pub fn pham_microphone_pairs(detection: Detection) -> Vec<MicPair> {
    [
        ([1.25, 0.0, 1.2], [1.75, 0.0, 1.2]),
        ([3.0, 1.25, 2.0], [3.0, 1.75, 2.0]),
        ([1.75, 3.0, 1.2], [1.25, 3.0, 1.2]),
        ([0.0, 1.75, 2.0], [0.0, 1.25, 2.0]),
    ]
    .into_iter()
    .map(|(m1, m2)| {
        MicPair::new(m1, m2, MicPair::DEFAULT_SPEED_OF_SOUND, 6.25e-5, detection).unwrap()
    })
    .collect()
}

/// One unit-covariance component per `(label, weight)`, at x = label on the x axis of a
/// 2-D state, so that labels are also positions.
pub fn mixture_of(weights: &[(u64, f64)]) -> GaussianMixture {
    GaussianMixture::from_components(
        weights
            .iter()
            .map(|&(label, w)| {
                Gaussian::new(
                    w,
                    DVector::from_vec(vec![label as f64, 0.0]),
                    DMatrix::identity(2, 2),
                    Label(label),
                )
            })
            .collect(),
    )
}

/// One measurement set: each object detected with the sensor's p_D at its
/// position, measured with Gaussian noise, plus Poisson clutter over the region.
pub fn simulate_set(
    sensor: &dyn MeasurementModel,
    positions: &[Vector3<f64>],
    rng: &mut ChaCha8Rng,
) -> Vec<Measurement> {
    let noise_root = sensor.noise_cov().cholesky().unwrap().unpack();
    let mut set = Vec::new();
    for p in positions {
        if rng.gen::<f64>() < sensor.detection_probability(p) {
            let white = DVector::from_fn(sensor.dim(), |_, _| rng.sample::<f64, _>(StandardNormal));
            set.push(Measurement::new(sensor.measure(p) + &noise_root * white));
        }
    }
    let rate = sensor.clutter_rate();
    let clutter = if rate > 0.0 {
        Poisson::new(rate).unwrap().sample(rng) as usize
    } else {
        0
    };
    for _ in 0..clutter {
        let u: Vec<f64> = (0..sensor.dim()).map(|_| rng.gen::<f64>()).collect();
        set.push(Measurement::new(sensor.sample_clutter(&u).unwrap()));
    }
    set
}

/// Positions (the motion model's `position_dims` leading state entries) of the
/// tracker's confirmed tracks: the estimate set the system reports.
pub fn confirmed_positions(tracker: &LabelledTracker) -> Vec<DVector<f64>> {
    let dims = tracker.filter().motion().position_dims();
    tracker
        .confirmed_tracks()
        .map(|track| track.mean.rows(0, dims).into_owned())
        .collect()
}

/// Vo & Ma's extraction (2006, Table III): every component of weight > 0.5 gives
/// round(weight) copies of its position (the first `dims` state entries).
pub fn vo_ma_positions(intensity: &GaussianMixture, dims: usize) -> Vec<DVector<f64>> {
    intensity
        .iter()
        .filter(|c| c.weight > 0.5)
        .flat_map(|c| {
            std::iter::repeat_n(c.mean.rows(0, dims).into_owned(), c.weight.round() as usize)
        })
        .collect()
}

/// OSPA and cardinality figures accumulated over the scored steps of many runs.
#[derive(Debug, Clone)]
pub struct Scores {
    params: MetricParams,
    steps: usize,
    ospa_sum: f64,
    /// Steps in which both sets were non-empty, and the localisation part summed over them.
    paired_steps: usize,
    localisation_sum: f64,
    right_count_steps: usize,
    /// Steps with the right, non-zero count, and their OSPA summed.
    right_nonempty_steps: usize,
    ospa_when_right_sum: f64,
    estimated_total: usize,
    true_total: usize,
}

impl Scores {
    /// Empty scores for OSPA with cut-off `cutoff` and order `order`.
    pub fn new(cutoff: f64, order: f64) -> Self {
        Self {
            params: MetricParams::new(cutoff, order).unwrap(),
            steps: 0,
            ospa_sum: 0.0,
            paired_steps: 0,
            localisation_sum: 0.0,
            right_count_steps: 0,
            right_nonempty_steps: 0,
            ospa_when_right_sum: 0.0,
            estimated_total: 0,
            true_total: 0,
        }
    }

    /// Scores one step's estimates against its truth.
    pub fn record(&mut self, truth: &[DVector<f64>], estimates: &[DVector<f64>]) {
        let score = ospa(truth, estimates, self.params).unwrap();
        self.steps += 1;
        self.ospa_sum += score.distance;
        if !truth.is_empty() && !estimates.is_empty() {
            self.paired_steps += 1;
            self.localisation_sum += score.localisation;
        }
        if truth.len() == estimates.len() {
            self.right_count_steps += 1;
            if !truth.is_empty() {
                self.right_nonempty_steps += 1;
                self.ospa_when_right_sum += score.distance;
            }
        }
        self.estimated_total += estimates.len();
        self.true_total += truth.len();
    }

    /// Number of scored steps.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Mean OSPA distance over all scored steps.
    pub fn mean_ospa(&self) -> f64 {
        self.ospa_sum / self.steps.max(1) as f64
    }

    /// Mean localisation part of OSPA over the steps where both sets were non-empty
    /// (elsewhere there is nothing to localise).
    pub fn mean_localisation(&self) -> f64 {
        self.localisation_sum / self.paired_steps.max(1) as f64
    }

    /// Fraction of scored steps with exactly as many estimates as true objects.
    pub fn cardinality_rate(&self) -> f64 {
        self.right_count_steps as f64 / self.steps.max(1) as f64
    }

    /// Mean OSPA over the steps where the count was right and not zero (an empty
    /// estimate of an empty scene scores a trivial 0).
    pub fn mean_ospa_when_count_right(&self) -> f64 {
        self.ospa_when_right_sum / self.right_nonempty_steps.max(1) as f64
    }

    /// Mean number of estimates per scored step.
    pub fn mean_estimated_count(&self) -> f64 {
        self.estimated_total as f64 / self.steps.max(1) as f64
    }

    /// Mean number of true objects per scored step.
    pub fn mean_true_count(&self) -> f64 {
        self.true_total as f64 / self.steps.max(1) as f64
    }

    /// One line with every figure, distances in `unit`.
    pub fn summary(&self, unit: &str) -> String {
        format!(
            "mean OSPA {:.4} {unit} (localisation part {:.4} {unit}), count right in {:.1}% of \
             {} steps (OSPA {:.4} {unit} where right and non-empty), mean count {:.2} estimated vs {:.2} true",
            self.mean_ospa(),
            self.mean_localisation(),
            100.0 * self.cardinality_rate(),
            self.steps,
            self.mean_ospa_when_count_right(),
            self.mean_estimated_count(),
            self.mean_true_count(),
        )
    }
}
