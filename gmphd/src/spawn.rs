//! Spawning: objects that appear next to existing ones (Vo & Ma 2006, eq. 21–22).

use nalgebra::{DMatrix, DVector};

use crate::error::{invalid, FilterError};
use crate::gaussian::{Gaussian, LabelSource};
use crate::linalg::{check_finite_vector, check_spd, symmetrize};

/// One spawn component: a child at F_β x + d_β with extra spread Q_β, expected
/// w_β children per parent per prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct SpawnComponent {
    /// Expected number of children per parent (w_β ≥ 0).
    pub weight: f64,
    /// Transition from parent to child state (F_β).
    pub transition: DMatrix<f64>,
    /// Offset of the child state (d_β).
    pub offset: DVector<f64>,
    /// Added covariance (Q_β).
    pub noise: DMatrix<f64>,
}

/// Vo & Ma's spawn intensity β(x | ζ) = Σ w_β N(x; F_β ζ + d_β, Q_β).
///
/// Spawning is a per-prediction event: F_β, d_β and Q_β describe one nominal
/// period and are not rescaled by the time step.
#[derive(Debug, Clone, PartialEq)]
pub struct SpawnModel {
    state_dim: usize,
    components: Vec<SpawnComponent>,
}

impl SpawnModel {
    /// Checks every component's sizes, weight and covariance.
    pub fn new(state_dim: usize, components: Vec<SpawnComponent>) -> Result<Self, FilterError> {
        for c in &components {
            if !(c.weight >= 0.0 && c.weight.is_finite()) {
                return Err(invalid("spawn weight", format!("{} is not >= 0", c.weight)));
            }
            if c.transition.nrows() != state_dim || c.transition.ncols() != state_dim {
                return Err(FilterError::DimensionMismatch {
                    what: "spawn transition",
                    expected: state_dim,
                    found: c.transition.nrows(),
                });
            }
            if !c.transition.iter().all(|x| x.is_finite()) {
                return Err(FilterError::NonFinite {
                    what: "spawn transition",
                });
            }
            if c.offset.len() != state_dim {
                return Err(FilterError::DimensionMismatch {
                    what: "spawn offset",
                    expected: state_dim,
                    found: c.offset.len(),
                });
            }
            check_finite_vector(&c.offset, "spawn offset")?;
            check_spd(&c.noise, state_dim, "spawn covariance")?;
        }
        Ok(Self {
            state_dim,
            components,
        })
    }

    /// State size of parents and children.
    pub fn state_dim(&self) -> usize {
        self.state_dim
    }

    /// The children of one posterior component, each with a fresh label.
    pub fn spawn(&self, parent: &Gaussian, labels: &mut LabelSource) -> Vec<Gaussian> {
        self.components
            .iter()
            .filter(|c| c.weight * parent.weight > 0.0)
            .map(|c| {
                let mean = &c.transition * &parent.mean + &c.offset;
                let cov = &c.transition * &parent.cov * c.transition.transpose() + &c.noise;
                Gaussian::new(
                    c.weight * parent.weight,
                    mean,
                    symmetrize(&cov),
                    labels.fresh(),
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gaussian::Label;

    #[test]
    fn children_follow_the_spawn_transition() {
        let spawn = SpawnModel::new(
            2,
            vec![SpawnComponent {
                weight: 0.05,
                transition: DMatrix::identity(2, 2),
                offset: DVector::from_vec(vec![1.0, 0.0]),
                noise: DMatrix::identity(2, 2) * 4.0,
            }],
        )
        .unwrap();
        let parent = Gaussian::new(
            0.8,
            DVector::from_vec(vec![10.0, 20.0]),
            DMatrix::identity(2, 2),
            Label(3),
        );
        let mut labels = LabelSource::starting_at(7);
        let kids = spawn.spawn(&parent, &mut labels);
        assert_eq!(kids.len(), 1);
        assert!((kids[0].weight - 0.04).abs() < 1e-15);
        assert_eq!(kids[0].mean.as_slice(), &[11.0, 20.0]);
        assert_eq!(kids[0].cov[(0, 0)], 5.0);
        assert_eq!(kids[0].label, Label(7));
        assert!(SpawnModel::new(3, spawn.components.clone()).is_err());
    }
}
