//! Simulated measurement sets of one sensor.
//!
//! Frame `k` of sensor `s` draws every random number from one ChaCha8 stream seeded by the
//! hash of `(seed, "measurements", s, k)`, so a process simulating only that sensor, or
//! only that frame, produces the same set bit for bit as a process simulating everything.

use gmphd::MeasurementModel;
use nalgebra::{DMatrix, DVector, Vector3};
use protocol::MeasurementSet;
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Poisson, StandardNormal};

use crate::error::{invalid, ScenarioError};
use crate::scenario::Scenario;
use crate::seeding::StreamKey;
use crate::sensor_spec::SensorSpec;
use crate::truth::truth_objects;

/// One sensor of a scenario, ready to produce measurement sets.
#[derive(Debug)]
pub struct SimulatedSensor {
    spec: SensorSpec,
    model: Box<dyn MeasurementModel>,
    /// Lower Cholesky factor `L` of the noise covariance `R = L Lᵀ`: `L n` with standard
    /// normal `n` has covariance `R`.
    noise_factor: DMatrix<f64>,
}

impl SimulatedSensor {
    /// Builds sensor `index` of `scenario` (its measurement model and noise factor).
    pub fn new(scenario: &Scenario, index: usize) -> Result<Self, ScenarioError> {
        let key = format!("sensors[{index}]");
        let spec = scenario
            .sensors
            .get(index)
            .ok_or_else(|| invalid(&key, "no such sensor"))?
            .clone();
        let model = sensor_models::measurement_model(&spec.descriptor(&scenario.site)).map_err(
            |source| ScenarioError::SensorModel {
                key: format!("{key}.model"),
                source,
            },
        )?;
        let noise_factor = model
            .noise_cov()
            .cholesky()
            .ok_or_else(|| invalid(format!("{key}.model.noise_std"), "noise is not positive"))?
            .l();
        // `sample_clutter` only fails for the wrong number of uniforms or ones outside
        // [0, 1]; probing once here lets frame generation rely on that.
        let probe = vec![0.5; model.dim()];
        model
            .sample_clutter(&probe)
            .map_err(|e| invalid(format!("{key}.model"), e.to_string()))?;
        Ok(Self {
            spec,
            model,
            noise_factor,
        })
    }

    /// The scenario entry this sensor was built from.
    pub fn spec(&self) -> &SensorSpec {
        &self.spec
    }

    /// The measurement model the frames are drawn from.
    pub fn model(&self) -> &dyn MeasurementModel {
        self.model.as_ref()
    }

    /// Frame `k` of a run of `scenario` with `seed` that started at Unix time `start`:
    /// `seq = k`, `stamp = start + (phase_s + k / rate_hz)` (the scenario time is computed
    /// first, exactly as the truth is evaluated), no per-measurement covariances.
    ///
    /// Each target present at the frame's time is detected with the model's `p_D(x)` (zero
    /// outside the field of view); a detection is `h(x) + L n` with angular components
    /// wrapped to [−π, π). Then `Poisson(clutter_rate)` clutter points are drawn uniformly
    /// over the measurement region, and the set is shuffled so its order says nothing.
    pub fn measurement_set(
        &self,
        scenario: &Scenario,
        seed: u64,
        start: f64,
        k: u64,
    ) -> MeasurementSet {
        let t = self.spec.frame_time(k);
        let mut rng = StreamKey::new(seed, "measurements")
            .with_text(self.spec.sensor.as_str())
            .with(k)
            .rng();
        let mut measurements = Vec::new();
        for object in truth_objects(scenario, seed, t) {
            let x = Vector3::from(object.position);
            // One uniform per present target whatever its p_D, so visibility of one target
            // does not shift the random numbers of the next.
            let u: f64 = rng.gen();
            if u < self.model.detection_probability(&x) {
                measurements.push(self.noisy_measurement(&x, &mut rng));
            }
        }
        for _ in 0..self.clutter_count(&mut rng) {
            let u: Vec<f64> = (0..self.model.dim()).map(|_| rng.gen()).collect();
            // Cannot fail: `u` has `dim()` values in [0, 1), checked in `new`.
            if let Ok(z) = self.model.sample_clutter(&u) {
                measurements.push(z.iter().copied().collect());
            }
        }
        measurements.shuffle(&mut rng);
        MeasurementSet::new(self.spec.sensor.clone(), k, start + t, measurements)
    }

    /// `h(x) + L n`, angular components wrapped.
    fn noisy_measurement(&self, x: &Vector3<f64>, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let dim = self.model.dim();
        let n = DVector::from_iterator(dim, (0..dim).map(|_| StandardNormal.sample(rng)));
        let z = self.model.measure(x) + &self.noise_factor * n;
        // The residual against zero is z itself with its angles wrapped to [−π, π).
        self.model
            .residual(&z, &DVector::zeros(dim))
            .iter()
            .copied()
            .collect()
    }

    /// A draw of the number of clutter points in one set.
    fn clutter_count(&self, rng: &mut ChaCha8Rng) -> u64 {
        let rate = self.spec.clutter_rate;
        if rate <= 0.0 {
            return 0;
        }
        // Validation keeps the rate finite and positive here, so `Poisson::new` succeeds.
        Poisson::new(rate).map_or(0, |poisson| poisson.sample(rng) as u64)
    }
}
