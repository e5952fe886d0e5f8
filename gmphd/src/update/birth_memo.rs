//! The unscented projections of the static births, kept from one birth to the next.
//!
//! A static birth model adds the same components at every birth (the same means and
//! covariances; only their weights, scaled by the time owed, and their labels change), and
//! the unscented transform of a component through a sensor depends only on its mean and
//! covariance, on what the sensor measures and on the filter's motion model and unscented
//! parameters (fixed for a filter). So the projection of a birth through a sensor, once
//! computed, serves every later birth of that component seen by that sensor: it is recalled
//! instead of recomputed when the component's mean and covariance are, bit for bit, those
//! it was computed from, for a sensor of the same
//! [`projection_key`](crate::UpdateHints::projection_key) (the built-in models' key is the
//! model's type and the whole model, serialized, so a changed parameter is a different key). The update's
//! output is the same bit for bit; only the work goes — and at the sets that receive the
//! births it is most of the work (the dense scenario's grid of 128 wide components, each
//! projected through 2n + 1 sigma points, more than doubles the cost of those sets).

use std::ops::Range;

use nalgebra::{DefaultAllocator, Dim, OMatrix, OVector, U1};

use super::dims::{Dims, Storage};
use super::unscented::UnscentedMoments;
use crate::gaussian::Gaussian;

/// Most sensors remembered; the least recently used is forgotten first.
const MAX_SENSORS: usize = 32;

/// The remembered projections of a filter's static births, per sensor.
#[derive(Debug, Default)]
pub(crate) struct BirthProjections {
    /// Most recently used last.
    sensors: Vec<SensorBirths>,
}

impl BirthProjections {
    /// The projections remembered for sensors of projection key `key` (none yet, the first
    /// time).
    pub(crate) fn for_sensor(&mut self, key: Vec<u8>) -> &mut SensorBirths {
        match self.sensors.iter().position(|s| s.key == key) {
            Some(i) => {
                let sensor = self.sensors.remove(i);
                self.sensors.push(sensor);
            }
            None => {
                if self.sensors.len() == MAX_SENSORS {
                    self.sensors.remove(0);
                }
                self.sensors.push(SensorBirths {
                    key,
                    births: Vec::new(),
                });
            }
        }
        self.sensors.last_mut().expect("pushed above")
    }
}

/// The projections of the static births through one sensor, by the birth's position in
/// the block of static births.
#[derive(Debug)]
pub(crate) struct SensorBirths {
    key: Vec<u8>,
    births: Vec<Option<Remembered>>,
}

/// One birth's projection and the component it was computed from.
#[derive(Debug)]
struct Remembered {
    mean: Vec<f64>,
    cov: Vec<f64>,
    z_mean: Vec<f64>,
    z_cov: Vec<f64>,
    cross_cov: Vec<f64>,
}

impl Remembered {
    /// Whether `component` has, bit for bit, the mean and covariance projected.
    fn is_of(&self, component: &Gaussian) -> bool {
        // Differing bits OR-ed together, without an early exit: the loop vectorises (the
        // components compared are almost always equal).
        let same = |a: &[f64], b: &[f64]| {
            a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .fold(0, |differ, (x, y)| differ | (x.to_bits() ^ y.to_bits()))
                    == 0
        };
        same(&self.mean, component.mean.as_slice()) && same(&self.cov, component.cov.as_slice())
    }
}

/// The static births of one update: where they are in the predicted mixture, and what is
/// remembered of them for the update's sensor.
pub(crate) struct StaticBirths<'a> {
    /// Indices of the static births in the predicted mixture.
    pub(crate) range: Range<usize>,
    pub(crate) memo: &'a mut SensorBirths,
}

impl StaticBirths<'_> {
    /// The projection of predicted component `index`, `component`, if it is a static birth
    /// whose projection is remembered.
    pub(super) fn recall<D: Dims>(
        &self,
        dims: D,
        index: usize,
        component: &Gaussian,
    ) -> Option<UnscentedMoments<D>>
    where
        DefaultAllocator: Storage<D>,
    {
        if !self.range.contains(&index) {
            return None;
        }
        let remembered = self.memo.births.get(index - self.range.start)?.as_ref()?;
        if !remembered.is_of(component) {
            return None;
        }
        let (n, m) = (dims.state(component), dims.measurement());
        let sizes_match = remembered.z_mean.len() == m.value()
            && remembered.cross_cov.len() == n.value() * m.value();
        sizes_match.then(|| UnscentedMoments {
            mean: OVector::<f64, D::M>::from_column_slice_generic(m, U1, &remembered.z_mean),
            cov: OMatrix::<f64, D::M, D::M>::from_column_slice_generic(m, m, &remembered.z_cov),
            cross_cov: OMatrix::<f64, D::N, D::M>::from_column_slice_generic(
                n,
                m,
                &remembered.cross_cov,
            ),
        })
    }

    /// Remembers `moments` as the projection of predicted component `index`, `component`,
    /// if it is a static birth and that is not remembered already.
    pub(super) fn remember<D: Dims>(
        &mut self,
        index: usize,
        component: &Gaussian,
        moments: &UnscentedMoments<D>,
    ) where
        DefaultAllocator: Storage<D>,
    {
        if !self.range.contains(&index) {
            return;
        }
        let position = index - self.range.start;
        let births = &mut self.memo.births;
        if births.len() <= position {
            births.resize_with(position + 1, || None);
        }
        if births[position]
            .as_ref()
            .is_some_and(|r| r.is_of(component))
        {
            return;
        }
        births[position] = Some(Remembered {
            mean: component.mean.as_slice().to_vec(),
            cov: component.cov.as_slice().to_vec(),
            z_mean: moments.mean.as_slice().to_vec(),
            z_cov: moments.cov.as_slice().to_vec(),
            cross_cov: moments.cross_cov.as_slice().to_vec(),
        });
    }
}

#[cfg(test)]
impl BirthProjections {
    /// How many births' projections are remembered, over all sensors.
    pub(crate) fn remembered(&self) -> usize {
        let count = |s: &SensorBirths| s.births.iter().flatten().count();
        self.sensors.iter().map(count).sum()
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Matrix3x4, Vector3};

    use crate::birth::{BirthTiming, GridBirth, GridBirthConfig};
    use crate::{
        ConstantVelocity, Detection, FilterConfig, GmPhdFilter, Lidar, Measurement,
        MeasurementModel, PinholeCamera, PruneMergeCap, Survival, UnscentedParams,
    };

    /// A camera at `eye`, 15 m up, looking straight down (image x along world x, image y
    /// along −y); at the floor it sees about 33 × 25 m.
    fn camera(eye: [f64; 2]) -> PinholeCamera {
        let eye = Vector3::new(eye[0], eye[1], 15.0);
        let rotation = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
        let mut extrinsics = Matrix3x4::zeros();
        extrinsics.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
        extrinsics.set_column(3, &(-rotation * eye));
        let intrinsics = Matrix3::new(250.0, 0.0, 320.0, 0.0, 250.0, 240.0, 0.0, 0.0, 1.0);
        let detection = Detection::new(0.9, 5.0).unwrap();
        PinholeCamera::new(
            intrinsics * extrinsics,
            [640.0, 480.0],
            [2.0, 2.0],
            detection,
        )
        .unwrap()
    }

    fn filter() -> GmPhdFilter {
        let birth = GridBirth::new(&GridBirthConfig {
            region_min: vec![0.0, 0.0, 0.0],
            region_max: vec![20.0, 20.0, 4.0],
            cells: vec![4, 4, 1],
            state_dim: 6,
            velocity_std: 0.5,
            extra_std: 0.0,
            total_rate: 2.0,
            timing: BirthTiming::PerSecond,
        })
        .unwrap();
        GmPhdFilter::new(
            Box::new(ConstantVelocity::new(3, 1.0).unwrap()),
            Box::new(birth),
            Box::new(PruneMergeCap::new(1e-5, 4.0, 200).unwrap()),
            FilterConfig {
                survival: Survival::PerSecond(0.99),
                unscented: UnscentedParams::default(),
            },
            0.0,
        )
        .unwrap()
    }

    /// Two people standing on the floor, seen by `sensor`, and a clutter return.
    fn detections(sensor: &dyn MeasurementModel) -> Vec<Measurement> {
        let mut set: Vec<Measurement> = [[4.0, 6.0, 1.0], [13.0, 12.0, 1.5]]
            .iter()
            .map(|p| Measurement::new(sensor.measure(&Vector3::from(*p))))
            .collect();
        let clutter = sensor.measure(&Vector3::new(17.0, 3.0, 0.5));
        set.push(Measurement::new(clutter.map(|z| z * 1.01)));
        set
    }

    /// A filter that has projected the births through its sensors before recalls their
    /// projections; a new one restored from the same checkpoint computes them afresh, and
    /// both end with the same intensity, bit for bit.
    #[test]
    fn recalled_projections_give_the_same_posterior() {
        let lidar = Lidar::new(
            [-2.0, 10.0, 2.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.05, 0.005, 0.005],
            60.0,
            [-0.6, 0.6],
            Detection::new(0.9, 5.0).unwrap(),
        )
        .unwrap();
        let sensors: Vec<Box<dyn MeasurementModel>> = vec![
            Box::new(camera([10.0, 10.0])),
            Box::new(camera([6.0, 14.0])),
            Box::new(lidar),
        ];
        let mut warm = filter();
        for k in 1..=6 {
            let sensor = sensors[k % sensors.len()].as_ref();
            warm.predict_to(0.05 * k as f64).unwrap();
            warm.update(sensor, &detections(sensor)).unwrap();
            warm.reduce();
        }
        assert_eq!(warm.birth_projections().remembered(), 3 * 16);
        let checkpoint = warm.state();
        for sensor in &sensors {
            let mut fresh = filter();
            fresh.restore(checkpoint.clone()).unwrap();
            for f in [&mut fresh, &mut warm] {
                f.predict_to(0.4).unwrap();
                f.update(sensor.as_ref(), &detections(sensor.as_ref()))
                    .unwrap();
            }
            assert_eq!(fresh.intensity(), warm.intensity());
            assert!(fresh.intensity().iter().any(|c| c.mean.len() == 6));
            warm.restore(checkpoint.clone()).unwrap();
        }
        // A sensor of the same kind elsewhere is another sensor.
        let moved = camera([10.0, 11.0]);
        warm.predict_to(0.4).unwrap();
        warm.update(&moved, &detections(&moved)).unwrap();
        assert_eq!(warm.birth_projections().remembered(), 4 * 16);
    }
}
