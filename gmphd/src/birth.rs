//! Spontaneous birth intensities γ_k(x): where new objects appear.

use std::fmt::Debug;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::error::{invalid, FilterError};
use crate::gaussian::{Gaussian, LabelSource};
use crate::linalg::{check_finite_vector, check_spd};

/// A birth intensity: the Gaussian components added at each prediction.
pub trait BirthModel: Send + Sync + Debug {
    /// State size of the components this model produces.
    fn state_dim(&self) -> usize;

    /// Birth components for a prediction over `dt` seconds, each with a fresh label
    /// from `labels`. Components of zero weight are not produced.
    fn birth(&self, dt: f64, labels: &mut LabelSource) -> Vec<Gaussian>;
}

/// How configured birth weights relate to the prediction interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BirthTiming {
    /// The weights are expected births per prediction, whatever its length (the
    /// classic fixed-period filter, e.g. Vo & Ma's demo).
    PerStep,
    /// The weights are birth rates per second and are multiplied by `dt`, so that
    /// asynchronous sensors with irregular intervals see a consistent birth intensity.
    PerSecond,
}

impl BirthTiming {
    fn scale(self, dt: f64) -> f64 {
        match self {
            Self::PerStep => 1.0,
            Self::PerSecond => dt,
        }
    }
}

/// A fixed Gaussian-mixture birth intensity (Vo & Ma 2006, eq. 3.15 in Pham).
#[derive(Debug, Clone, PartialEq)]
pub struct MixtureBirth {
    state_dim: usize,
    /// (weight, mean, covariance) of each component; labels are assigned at birth.
    components: Vec<(f64, DVector<f64>, DMatrix<f64>)>,
    timing: BirthTiming,
}

impl MixtureBirth {
    /// Components as (weight, mean, covariance); an empty list means no births.
    pub fn new(
        state_dim: usize,
        components: Vec<(f64, DVector<f64>, DMatrix<f64>)>,
        timing: BirthTiming,
    ) -> Result<Self, FilterError> {
        for (weight, mean, cov) in &components {
            if !(*weight >= 0.0 && weight.is_finite()) {
                return Err(invalid(
                    "birth weight",
                    format!("{weight} is not a finite number >= 0"),
                ));
            }
            if mean.len() != state_dim {
                return Err(FilterError::DimensionMismatch {
                    what: "birth mean",
                    expected: state_dim,
                    found: mean.len(),
                });
            }
            check_finite_vector(mean, "birth mean")?;
            check_spd(cov, state_dim, "birth covariance")?;
        }
        Ok(Self {
            state_dim,
            components,
            timing,
        })
    }
}

impl BirthModel for MixtureBirth {
    fn state_dim(&self) -> usize {
        self.state_dim
    }

    fn birth(&self, dt: f64, labels: &mut LabelSource) -> Vec<Gaussian> {
        let scale = self.timing.scale(dt);
        self.components
            .iter()
            .filter(|(weight, _, _)| weight * scale > 0.0)
            .map(|(weight, mean, cov)| {
                Gaussian::new(weight * scale, mean.clone(), cov.clone(), labels.fresh())
            })
            .collect()
    }
}

/// Where and how densely a [`GridBirth`] places its components.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridBirthConfig {
    /// Lower corner of the birth box (2 or 3 world coordinates).
    pub region_min: Vec<f64>,
    /// Upper corner of the birth box.
    pub region_max: Vec<f64>,
    /// Number of cells along each axis (≥ 1).
    pub cells: Vec<usize>,
    /// State size: the positions, then as many velocities (if any), then extras.
    pub state_dim: usize,
    /// Standard deviation of the newborn velocity (zero mean), m/s.
    pub velocity_std: f64,
    /// Standard deviation of extra state components (zero mean), e.g. a turn rate.
    pub extra_std: f64,
    /// Total expected births over the whole box, split evenly among the cells.
    pub total_rate: f64,
    /// Whether `total_rate` is per prediction or per second.
    pub timing: BirthTiming,
}

/// Birth components at the centres of a regular grid over a box (Pham ch. 6–7:
/// "the birth intensity is the mixture of Gaussian components whose means are
/// centers of these parts"). Each component's position standard deviation is half
/// its cell's size, so neighbouring components overlap and cover the whole box.
#[derive(Debug, Clone, PartialEq)]
pub struct GridBirth {
    mixture: MixtureBirth,
}

impl GridBirth {
    /// Builds the grid; fails on an empty or inverted box, zero cells, a state too
    /// small for the positions, or a negative rate or spread.
    pub fn new(config: &GridBirthConfig) -> Result<Self, FilterError> {
        let (dims, velocity_dims) = config.validate()?;
        let cell_size: Vec<f64> = (0..dims)
            .map(|i| (config.region_max[i] - config.region_min[i]) / config.cells[i] as f64)
            .collect();
        let count: usize = config.cells.iter().product();
        let weight = config.total_rate / count as f64;
        let mut variances = DVector::zeros(config.state_dim);
        for i in 0..config.state_dim {
            variances[i] = if i < dims {
                (cell_size[i] / 2.0).powi(2)
            } else if i < dims + velocity_dims {
                config.velocity_std.powi(2)
            } else {
                config.extra_std.powi(2)
            };
        }
        // A zero spread (deterministic velocity) would make the covariance singular;
        // floor it far below any physical scale instead.
        let floor = variances.amax() * 1e-12;
        let cov = DMatrix::from_diagonal(&variances.map(|v| v.max(floor)));
        let mut components = Vec::with_capacity(count);
        for flat in 0..count {
            let mut mean = DVector::zeros(config.state_dim);
            let mut rest = flat;
            for i in 0..dims {
                let index = rest % config.cells[i];
                rest /= config.cells[i];
                mean[i] = config.region_min[i] + (index as f64 + 0.5) * cell_size[i];
            }
            components.push((weight, mean, cov.clone()));
        }
        Ok(Self {
            mixture: MixtureBirth::new(config.state_dim, components, config.timing)?,
        })
    }
}

impl GridBirthConfig {
    /// Checks the grid: 2 or 3 coordinates, min < max, at least one cell per axis, a state
    /// that holds the positions (and velocities), finite rates and spreads ≥ 0. Returns
    /// the number of position and of velocity entries.
    fn validate(&self) -> Result<(usize, usize), FilterError> {
        let dims = self.region_min.len();
        if dims != 2 && dims != 3 {
            return Err(invalid("grid birth region", "must have 2 or 3 coordinates"));
        }
        if self.region_max.len() != dims || self.cells.len() != dims {
            return Err(FilterError::DimensionMismatch {
                what: "grid birth region max / cells",
                expected: dims,
                found: self.region_max.len().min(self.cells.len()),
            });
        }
        let velocity_dims = if self.state_dim == dims {
            0
        } else if self.state_dim >= 2 * dims {
            dims
        } else {
            return Err(invalid(
                "grid birth state size",
                format!(
                    "{} cannot hold {dims} positions (and velocities)",
                    self.state_dim
                ),
            ));
        };
        let box_ok = self
            .region_min
            .iter()
            .zip(&self.region_max)
            .all(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo < hi);
        if !box_ok || self.cells.contains(&0) {
            return Err(invalid(
                "grid birth region",
                "needs min < max on every axis and at least one cell per axis",
            ));
        }
        for (value, name) in [
            (self.velocity_std, "grid birth velocity std"),
            (self.extra_std, "grid birth extra std"),
            (self.total_rate, "grid birth rate"),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(invalid(
                    name,
                    format!("{value} is not a finite number >= 0"),
                ));
            }
        }
        Ok((dims, velocity_dims))
    }
}

impl BirthModel for GridBirth {
    fn state_dim(&self) -> usize {
        self.mixture.state_dim()
    }

    fn birth(&self, dt: f64, labels: &mut LabelSource) -> Vec<Gaussian> {
        self.mixture.birth(dt, labels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixture_birth_scales_with_dt_and_labels_are_fresh() {
        let comp = (0.1, DVector::zeros(2), DMatrix::identity(2, 2));
        let birth = MixtureBirth::new(2, vec![comp.clone(), comp], BirthTiming::PerSecond).unwrap();
        let mut labels = LabelSource::default();
        let born = birth.birth(0.5, &mut labels);
        assert_eq!(born.len(), 2);
        assert!((born[0].weight - 0.05).abs() < 1e-15);
        assert_ne!(born[0].label, born[1].label);
        assert!(birth.birth(0.0, &mut labels).is_empty());
    }

    #[test]
    fn grid_birth_covers_the_box_evenly() {
        let config = GridBirthConfig {
            region_min: vec![0.0, 0.0],
            region_max: vec![3.0, 5.0],
            cells: vec![3, 5],
            state_dim: 5,
            velocity_std: 1.0,
            extra_std: 0.1,
            total_rate: 1.5,
            timing: BirthTiming::PerStep,
        };
        let grid = GridBirth::new(&config).unwrap();
        let born = grid.birth(1.0, &mut LabelSource::default());
        assert_eq!(born.len(), 15);
        assert!((born.iter().map(|g| g.weight).sum::<f64>() - 1.5).abs() < 1e-12);
        assert_eq!(born[0].mean.as_slice()[..2], [0.5, 0.5]);
        assert_eq!(born[14].mean.as_slice()[..2], [2.5, 4.5]);
        assert!((born[0].cov[(4, 4)] - 0.01).abs() < 1e-15);
        let bad = GridBirthConfig {
            state_dim: 3,
            ..config
        };
        assert!(GridBirth::new(&bad).is_err());
    }
}
