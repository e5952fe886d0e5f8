//! The server's tracker: builds the labelled GM-PHD tracker from the configuration and turns
//! protocol sets into filter measurements and confirmed tracks into protocol tracks.

use gmphd::birth::{BirthTiming, GridBirth, GridBirthConfig, MixtureBirth};
use gmphd::measurement::{Measurement, MeasurementModel};
use gmphd::tracks::TrackManagerConfig;
use gmphd::{
    AdaptiveBirthConfig, ConstantVelocity, FilterConfig as GmFilterConfig, GmPhdFilter,
    LabelledTracker, MotionModel, PruneMergeCap, RandomWalk, Survival, SurvivalRegion,
    TrackerConfig, UnscentedParams,
};
use nalgebra::{DMatrix, DVector};
use protocol::{MeasurementSet, Track};

use crate::config::{BirthKind, MotionKind, ServerConfig};

pub use gmphd::TrackerState;

/// The labelled tracker of one site.
#[derive(Debug)]
pub struct Tracker {
    inner: LabelledTracker,
}

fn motion_model(config: &ServerConfig) -> anyhow::Result<Box<dyn MotionModel>> {
    let f = &config.filter;
    Ok(match f.motion {
        MotionKind::RandomWalk => Box::new(RandomWalk::new(3, f.position_noise_std, 0.0)?),
        MotionKind::ConstantVelocity => Box::new(ConstantVelocity::new(3, f.accel_noise_std)?),
    })
}

fn birth_model(
    config: &ServerConfig,
    state_dim: usize,
) -> anyhow::Result<Box<dyn gmphd::BirthModel>> {
    let f = &config.filter;
    Ok(match f.birth {
        BirthKind::Mixture => {
            let mut variances = vec![f.birth_position_std.powi(2); 3];
            variances.resize(state_dim, f.birth_velocity_std.powi(2));
            let cov = DMatrix::from_diagonal(&DVector::from_vec(variances));
            let weight = f.birth_rate / f.birth_means.len() as f64;
            let components = f
                .birth_means
                .iter()
                .map(|m| {
                    let mut mean = DVector::zeros(state_dim);
                    mean.rows_mut(0, 3).copy_from_slice(m);
                    (weight, mean, cov.clone())
                })
                .collect();
            Box::new(MixtureBirth::new(
                state_dim,
                components,
                BirthTiming::PerSecond,
            )?)
        }
        BirthKind::Grid => Box::new(GridBirth::new(&GridBirthConfig {
            region_min: config.site.volume_min.to_vec(),
            region_max: config.site.volume_max.to_vec(),
            cells: config.filter.birth_grid.to_vec(),
            state_dim,
            velocity_std: f.birth_velocity_std,
            extra_std: 0.0,
            total_rate: f.birth_rate,
            timing: BirthTiming::PerSecond,
        })?),
    })
}

impl Tracker {
    /// The tracker the configuration describes.
    pub fn new(config: &ServerConfig) -> anyhow::Result<Self> {
        let motion = motion_model(config)?;
        let birth = birth_model(config, motion.state_dim())?;
        let f = &config.filter;
        let reducer = PruneMergeCap::new(f.prune_threshold, f.merge_threshold, f.max_components)?;
        let filter = GmPhdFilter::new(
            motion,
            birth,
            Box::new(reducer),
            GmFilterConfig {
                survival: Survival::PerSecond(f.survival_probability),
                unscented: UnscentedParams::default(),
            },
            0.0,
        )?
        .with_birth_interval(f.birth_interval_s)?
        .with_survival_region(SurvivalRegion::new(
            config
                .site
                .volume_min
                .iter()
                .map(|v| v - f.survival_margin_m)
                .collect(),
            config
                .site
                .volume_max
                .iter()
                .map(|v| v + f.survival_margin_m)
                .collect(),
        )?)?;
        let filter = match f.activity_model() {
            Some(model) => filter.with_activity(model)?,
            None => filter,
        };
        let filter = match f.occlusion() {
            Some(occlusion) => filter.with_occlusion(occlusion?),
            None => filter,
        };
        let filter = match f.echoes() {
            Some(echoes) => filter.with_echoes(echoes)?,
            None => filter,
        };
        let filter = if f.label_existence {
            filter.with_label_existence()
        } else {
            filter
        };
        let filter = if f.adaptive_birth {
            filter.with_adaptive_birth(AdaptiveBirthConfig {
                rate: f.adaptive_birth_rate,
                velocity_std: f.adaptive_birth_velocity_std,
                // Lighter births would be pruned at the next reduction anyway.
                min_weight: f.prune_threshold,
                ..AdaptiveBirthConfig::default()
            })?
        } else {
            filter
        };
        let t = &config.tracks;
        let tracker_config = TrackerConfig {
            extraction_threshold: f.extraction_threshold,
            merge_threshold: f.merge_threshold,
            tracks: TrackManagerConfig {
                confirm_threshold: t.confirm_threshold,
                confirm_window: t.confirm_window,
                confirm_hits: t.confirm_hits,
                confirm_at_once_threshold: t.confirm_at_once_threshold,
                delete_threshold: t.delete_threshold,
                delete_after_sets: t.delete_after_sets,
                max_coast_s: t.max_coast_s,
            },
            ..TrackerConfig::default()
        };
        Ok(Self {
            inner: LabelledTracker::new(filter, tracker_config)?,
        })
    }

    /// Predicts to `stamp`, updates with `set` under `model`, and returns the confirmed tracks.
    pub fn process(
        &mut self,
        stamp: f64,
        model: &dyn MeasurementModel,
        set: &MeasurementSet,
    ) -> anyhow::Result<Vec<Track>> {
        let measurements = to_measurements(set);
        self.inner.step(stamp, model, &measurements)?;
        Ok(self.tracks())
    }

    /// The confirmed tracks, in the protocol's form, ordered by id.
    pub fn tracks(&self) -> Vec<Track> {
        let motion = self.inner.filter().motion();
        self.inner
            .confirmed_tracks()
            .map(|track| {
                let position = motion.position(&track.mean);
                let pos_dims = motion.position_dims();
                let mut position_covariance = [[0.0; 3]; 3];
                for (r, row) in position_covariance.iter_mut().enumerate().take(pos_dims) {
                    for (c, value) in row.iter_mut().enumerate().take(pos_dims) {
                        *value = track.cov[(r, c)];
                    }
                }
                Track {
                    id: track.label.0,
                    position: [position.x, position.y, position.z],
                    velocity: motion.velocity(&track.mean).map(|v| [v.x, v.y, v.z]),
                    position_covariance,
                    weight: track.weight,
                    first_seen: track.first_seen,
                }
            })
            .collect()
    }

    /// The PHD's expected number of objects.
    pub fn expected_count(&self) -> f64 {
        self.inner.filter().expected_count()
    }

    /// Number of Gaussian components.
    pub fn component_count(&self) -> usize {
        self.inner.filter().intensity().len()
    }

    /// The state to checkpoint.
    pub fn state(&self) -> TrackerState {
        self.inner.state()
    }

    /// Resumes from a checkpoint.
    pub fn restore(&mut self, state: TrackerState) -> anyhow::Result<()> {
        Ok(self.inner.restore(state)?)
    }
}

/// The filter's measurements of a (validated) set; per-measurement covariances when given.
fn to_measurements(set: &MeasurementSet) -> Vec<Measurement> {
    set.measurements
        .iter()
        .enumerate()
        .map(|(i, z)| {
            let z = DVector::from_column_slice(z);
            match set.covariances.as_ref().and_then(|c| c.get(i)) {
                Some(rows) => {
                    let n = rows.len();
                    let cov = DMatrix::from_fn(n, n, |r, c| rows[r][c]);
                    Measurement::with_cov(z, cov)
                }
                None => Measurement::new(z),
            }
        })
        .collect()
}
