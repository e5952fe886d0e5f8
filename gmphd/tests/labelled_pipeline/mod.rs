//! The labelled filtering cycle the experiments run, built from the public API:
//! `GmPhdFilter` predict / update / reduce, then extraction, Pham ch. 4 label
//! association with inherited label sets, label write-back, and the track
//! manager — one cycle per measurement set.

use gmphd::extract::{StateExtractor, WeightThresholdExtractor};
use gmphd::labels::{
    apply_relabelling, associate_labels, inherited_label_sets, CurrentEstimate, PreviousEstimate,
};
use gmphd::tracks::{TrackManager, TrackManagerConfig};
use gmphd::{GmPhdFilter, Label, LabelSource, Measurement, MeasurementModel};
use nalgebra::{DMatrix, DVector};

/// Squared Mahalanobis distance within which a pre-reduction component counts as
/// an ancestor of an estimate: the reducer's merge threshold U.
const MERGE_THRESHOLD: f64 = 4.0;

/// A labelled position estimate.
pub type LabelledPoint = (Label, DVector<f64>);

/// Filter plus label continuity plus track management.
pub struct LabelledPipeline {
    filter: GmPhdFilter,
    extractor: WeightThresholdExtractor,
    tracks: TrackManager,
    /// Last cycle's estimates (label, mean, covariance) and their time.
    previous: Vec<(Label, DVector<f64>, DMatrix<f64>)>,
    previous_time: f64,
}

impl LabelledPipeline {
    /// A pipeline around `filter` (whose clock starts the first cycle).
    pub fn new(filter: GmPhdFilter) -> Self {
        Self {
            previous_time: filter.time(),
            filter,
            extractor: WeightThresholdExtractor::default(),
            tracks: TrackManager::new(TrackManagerConfig::default()).unwrap(),
            previous: Vec::new(),
        }
    }

    /// One measurement set taken at `t`; returns this cycle's labelled estimates
    /// (positions).
    pub fn step(
        &mut self,
        t: f64,
        sensor: &dyn MeasurementModel,
        measurements: &[Measurement],
    ) -> Vec<LabelledPoint> {
        self.filter.predict_to(t).unwrap();
        self.filter.update(sensor, measurements).unwrap();
        let before_reduction = self.filter.intensity().clone();
        self.filter.reduce();

        let mut mixture = self.filter.intensity().clone();
        let estimates = self.extractor.extract(&mixture).unwrap();
        let inherited =
            inherited_label_sets(&before_reduction, &estimates, MERGE_THRESHOLD).unwrap();
        let motion = self.filter.motion();
        let dims = motion.position_dims();
        let position = move |x: &DVector<f64>| x.rows(0, dims).into_owned();
        let dt = t - self.previous_time;
        let previous: Vec<PreviousEstimate> = self
            .previous
            .iter()
            .map(|(label, mean, cov)| PreviousEstimate {
                label: *label,
                predicted: position(&motion.predict(mean, cov, dt).unwrap().0),
            })
            .collect();
        let current: Vec<CurrentEstimate> = estimates
            .iter()
            .zip(inherited)
            .map(|(estimate, inherited)| CurrentEstimate {
                mean: position(&estimate.mean),
                weight: estimate.weight,
                inherited,
            })
            .collect();
        // Fresh labels continue after the filter's, which it then skips.
        let mut source = LabelSource::starting_at(self.filter.next_label());
        let relabelling = associate_labels(&previous, &current, &mut source).unwrap();
        apply_relabelling(&mut mixture, &estimates, &relabelling, &mut source).unwrap();
        self.filter.set_intensity(mixture).unwrap();
        self.tracks.update(t, self.filter.intensity()).unwrap();

        self.previous = estimates
            .iter()
            .zip(&relabelling.labels)
            .map(|(estimate, &label)| (label, estimate.mean.clone(), estimate.cov.clone()))
            .collect();
        self.previous_time = t;
        self.previous
            .iter()
            .map(|(label, mean, _)| (*label, position(mean)))
            .collect()
    }

    /// The track manager's confirmed tracks (positions).
    pub fn confirmed_tracks(&self) -> Vec<LabelledPoint> {
        let dims = self.filter.motion().position_dims();
        self.tracks
            .confirmed_tracks()
            .map(|track| (track.label, track.mean.rows(0, dims).into_owned()))
            .collect()
    }
}
