//! The multi-Bernoulli filter on the background-subtracted image (Hoseinnezhad, Vo & Vu, sec. 4): one
//! recursion per frame of prediction, update by the image likelihood, resampling, pruning, merging and
//! estimation, then births for the next frame from what the estimates leave unexplained.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::bernoulli::{Bernoulli, Motion};
use super::birth::{newborns, BirthSettings};
use super::config::MultiBernoulliConfig;
use super::cover::Cover;
use super::estimate::{head_statistics, visible_share, PersonEstimate};
use super::foreground::ForegroundMap;
use super::geometry::CameraGeometry;
use super::likelihood::Likelihood;
use super::region::{PersonProjector, Region};
use crate::camera::error::CameraResult;

/// Interval assumed before the first frame, s.
const FIRST_INTERVAL_S: f64 = 0.04;
/// Adds to `estimate`'s covariance what a head outline that is `hidden` (a share) adds to its
/// uncertainty: where it lies on another person the foreground does not show where the head ends, so
/// its top may be anywhere over that share of the head's size (variance of a uniform spread over it).
fn widen_for_hidden_outline(
    estimate: &mut PersonEstimate,
    projector: &PersonProjector,
    hidden: f64,
) {
    let [x, y] = estimate.floor;
    let shape = projector.shape();
    let head_height = shape.head_share * estimate.height;
    let top = projector.head_top(x, y, estimate.height);
    let chin = projector.head_top(x, y, estimate.height - head_height);
    let (Some(top), Some(chin)) = (top, chin) else {
        return;
    };
    let height_px = (top[0] - chin[0]).hypot(top[1] - chin[1]);
    let width_px = height_px * 2.0 * shape.head_half_width / head_height;
    let spread = |size: f64| (hidden * size).powi(2) / 12.0;
    estimate.covariance[0][0] += spread(width_px);
    estimate.covariance[1][1] += spread(height_px);
}

/// Share of a person that must be in sight in a frame for the frame to count towards its confirmation.
const MIN_VISIBLE_TO_CONFIRM: f64 = 0.5;
/// Shortest interval a prediction covers, s (frames with equal stamps still move the particles a little).
const MIN_INTERVAL_S: f64 = 1e-3;

/// The filter's state: its Bernoulli components and the newborns waiting for the next frame.
pub struct MultiBernoulliFilter {
    config: MultiBernoulliConfig,
    projector: PersonProjector,
    components: Vec<Bernoulli>,
    newborn: Vec<Bernoulli>,
    rng: ChaCha8Rng,
    next_id: u64,
    last_stamp: Option<f64>,
    /// The regions of the last frame's estimates (at their means), for the background's update.
    estimate_regions: Vec<Region>,
}

impl MultiBernoulliFilter {
    /// A filter for the camera of `projection` with images of `image_size` (full-resolution) pixels.
    pub fn new(
        config: MultiBernoulliConfig,
        projection: [[f64; 4]; 3],
        image_size: [u32; 2],
    ) -> CameraResult<Self> {
        config.validate()?;
        let geometry = CameraGeometry::new(projection, image_size)?;
        let projector = PersonProjector::new(
            geometry,
            config.person.clone(),
            config.floor_z,
            config.downscale,
        );
        Ok(Self {
            rng: ChaCha8Rng::seed_from_u64(config.seed),
            config,
            projector,
            components: Vec::new(),
            newborn: Vec::new(),
            next_id: 1,
            last_stamp: None,
            estimate_regions: Vec::new(),
        })
    }

    /// The person projector (camera, person model, image scale).
    pub fn projector(&self) -> &PersonProjector {
        &self.projector
    }

    /// The regions (shrunk image) of the last frame's estimates.
    pub fn estimate_regions(&self) -> &[Region] {
        &self.estimate_regions
    }

    /// The components (for inspection).
    pub fn components(&self) -> &[Bernoulli] {
        &self.components
    }

    fn motion(&self) -> Motion {
        let c = &self.config;
        Motion {
            survival_per_second: c.survival_per_second,
            accel_noise: c.accel_noise,
            height_noise: c.height_noise,
            height_bounds: (c.person.min_height, c.person.max_height),
        }
    }

    /// One frame: the foreground `map` of the frame taken at `stamp`. Returns every estimate (existence
    /// at least `report_existence`), published or not.
    pub fn step(&mut self, stamp: f64, map: &ForegroundMap) -> Vec<PersonEstimate> {
        let dt = match self.last_stamp {
            Some(last) => (stamp - last).max(MIN_INTERVAL_S),
            None => FIRST_INTERVAL_S,
        };
        self.last_stamp = Some(stamp);
        self.components.append(&mut self.newborn);
        let motion = self.motion();
        for c in &mut self.components {
            c.predict(dt, &motion, &mut self.rng);
        }
        self.update(map);
        self.resample_and_prune();
        self.merge_duplicates();
        let estimates = self.estimates(map);
        self.drop_unconfirmed();
        let cover = Cover::from_regions(&self.estimate_regions);
        let settings = BirthSettings {
            existence: self.config.birth_existence,
            particles: self.config.birth_particles,
            velocity_std: self.config.birth_velocity_std,
            min_share: self.config.birth_min_share,
        };
        self.newborn = newborns(
            map,
            &cover,
            &self.projector,
            &settings,
            &mut self.rng,
            &mut self.next_id,
        );
        estimates
    }

    /// The regions, at their mean states, of the components that are estimates, with their indices.
    fn anchor_regions(&self) -> Vec<(usize, Region)> {
        let mut out = Vec::new();
        for (i, c) in self.components.iter().enumerate() {
            if c.existence < self.config.report_existence {
                continue;
            }
            let m = c.mean();
            let mut region = Region::default();
            if self.projector.rasterise(m[0], m[1], m[4], &mut region) {
                out.push((i, region));
            }
        }
        out
    }

    /// Updates each component on the pixels the other estimates leave free.
    fn update(&mut self, map: &ForegroundMap) {
        let anchors = self.anchor_regions();
        let likelihood = Likelihood {
            projector: &self.projector,
            map,
            pixels_per_observation: self.config.pixels_per_observation,
            head_weight: self.config.head_weight,
        };
        let mut region = Region::default();
        let mut logs = Vec::new();
        for (i, component) in self.components.iter_mut().enumerate() {
            let others = anchors.iter().filter(|(j, _)| *j != i).map(|(_, r)| r);
            let cover = Cover::from_regions(others);
            logs.clear();
            logs.extend(
                component
                    .particles
                    .iter()
                    .map(|p| likelihood.log_ratio(p, &cover, &mut region)),
            );
            component.update(&logs);
        }
    }

    fn resample_and_prune(&mut self) {
        let c = &self.config;
        self.components.retain(|b| b.existence >= c.prune_existence);
        for b in &mut self.components {
            let wanted = (b.existence * c.max_particles as f64).round() as usize;
            b.resample(
                wanted.clamp(c.min_particles, c.max_particles),
                &mut self.rng,
            );
            b.age = b.age.saturating_add(1);
        }
    }

    /// A component that has not been confirmed within `confirm_within_frames` of its birth goes: a
    /// person first seen must be seen, and a hypothesis that hides behind a confirmed person for good
    /// (which the image can neither confirm nor refute) is not one.
    fn drop_unconfirmed(&mut self) {
        let c = &self.config;
        self.components
            .retain(|b| b.reported_frames >= c.confirm_frames || b.age <= c.confirm_within_frames);
    }

    /// Two estimates closer on the floor than `merge_distance` are one person: the younger (or less
    /// certain) one goes.
    fn merge_duplicates(&mut self) {
        let report = self.config.report_existence;
        let means: Vec<_> = self.components.iter().map(Bernoulli::mean).collect();
        let mut gone = vec![false; self.components.len()];
        for i in 0..self.components.len() {
            for j in i + 1..self.components.len() {
                let (a, b) = (&self.components[i], &self.components[j]);
                if gone[i] || gone[j] || a.existence < report || b.existence < report {
                    continue;
                }
                let distance = (means[i][0] - means[j][0]).hypot(means[i][1] - means[j][1]);
                if distance >= self.config.merge_distance {
                    continue;
                }
                let keep_i = (a.reported_frames, a.existence) >= (b.reported_frames, b.existence);
                gone[if keep_i { j } else { i }] = true;
            }
        }
        let mut k = 0;
        self.components.retain(|_| {
            k += 1;
            !gone[k - 1]
        });
    }

    /// The estimates of this frame (their visibility and confirmation counts), and their regions for
    /// the births and the background.
    fn estimates(&mut self, map: &ForegroundMap) -> Vec<PersonEstimate> {
        let report = self.config.report_existence;
        let mut found: Vec<(usize, PersonEstimate, Region)> = Vec::new();
        for (i, c) in self.components.iter().enumerate() {
            if c.existence < report {
                continue;
            }
            let m = c.mean();
            let mut region = Region::default();
            if !self.projector.rasterise(m[0], m[1], m[4], &mut region) {
                continue;
            }
            let error = self.config.head_model_error;
            let Some((head, covariance)) = head_statistics(c, &self.projector, error) else {
                continue;
            };
            let estimate = PersonEstimate {
                id: c.id,
                existence: c.existence,
                reported_frames: c.reported_frames,
                head,
                covariance,
                floor: [m[0], m[1]],
                height: m[4],
                visible_head: 0.0,
                visible_body: 0.0,
                distance: self.projector.geometry().ground_distance(m[0], m[1]),
            };
            found.push((i, estimate, region));
        }
        for k in 0..found.len() {
            let distance = found[k].1.distance;
            let others = || found.iter().enumerate().filter(|(j, _)| *j != k);
            let nearer = Cover::from_regions(
                others()
                    .filter(|(_, (_, e, _))| e.distance < distance)
                    .map(|(_, (_, _, r))| r),
            );
            // The head's outline shows only against the background: where it lies on another person,
            // nearer or farther, the foreground says nothing of where it ends.
            let everyone = Cover::from_regions(others().map(|(_, (_, _, r))| r));
            let (_, estimate, region) = &mut found[k];
            estimate.visible_head = visible_share(region.head(), &nearer, map.size());
            estimate.visible_body = visible_share(&region.spans, &nearer, map.size());
            let outlined = visible_share(region.head(), &everyone, map.size());
            widen_for_hidden_outline(estimate, &self.projector, 1.0 - outlined);
        }
        self.count_confirmations(&mut found);
        self.estimate_regions = found.iter().map(|(_, _, r)| r.clone()).collect();
        found.into_iter().map(|(_, e, _)| e).collect()
    }

    /// Counts the frames in a row each component has been an estimate: a component not yet confirmed
    /// counts only frames in which it is mostly in sight.
    fn count_confirmations(&mut self, found: &mut [(usize, PersonEstimate, Region)]) {
        let confirm = self.config.confirm_frames;
        let mut counted = vec![false; self.components.len()];
        for (i, estimate, _) in found.iter_mut() {
            let c = &mut self.components[*i];
            counted[*i] = true;
            if c.reported_frames >= confirm || estimate.visible_body >= MIN_VISIBLE_TO_CONFIRM {
                c.reported_frames = c.reported_frames.saturating_add(1);
            } else {
                c.reported_frames = 0;
            }
            estimate.reported_frames = c.reported_frames;
        }
        for (c, counted) in self.components.iter_mut().zip(counted) {
            if !counted {
                c.reported_frames = 0;
            }
        }
    }
}

#[cfg(test)]
#[path = "filter_tests.rs"]
mod tests;
