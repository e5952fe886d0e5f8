//! The exporters' `--score`: our bare `GmPhdFilter` run on exported sets and scored as the
//! Stone Soup scripts score theirs (`tools/stonesoup/`).

use std::time::Instant;

use gmphd::{GmPhdFilter, Measurement, MeasurementModel};
use nalgebra::DVector;

use super::{vo_ma_positions, Scores};

/// Runs a fresh `filter()` over each run's sets (predict, update, reduce per scan, at
/// t = 1, 2, … s), scores Vo & Ma's extraction against `truth` with OSPA (c = 100 m,
/// p = 1) and prints it with the wall-clock time per scan (median and mean, timed as the
/// Python side times Stone Soup) and the mean mixture size.
pub fn print_scores(
    truth: &[Vec<DVector<f64>>],
    runs: &[Vec<Vec<Measurement>>],
    sensor: &dyn MeasurementModel,
    filter: impl Fn() -> GmPhdFilter,
) {
    let mut scores = Scores::new(100.0, 1.0);
    let mut times = Vec::with_capacity(runs.iter().map(Vec::len).sum());
    let mut sizes = 0usize;
    for scans in runs {
        let mut filter = filter();
        for (index, (objects, measurements)) in truth.iter().zip(scans).enumerate() {
            let start = Instant::now();
            filter.predict_to((index + 1) as f64).unwrap();
            filter.update(sensor, measurements).unwrap();
            filter.reduce();
            times.push(start.elapsed().as_secs_f64());
            scores.record(objects, &vo_ma_positions(filter.intensity(), 2));
            sizes += filter.intensity().len();
        }
    }
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    times.sort_by(f64::total_cmp);
    println!(
        "our GmPhdFilter, Vo & Ma extraction: {}",
        scores.summary("m")
    );
    println!(
        "  median {:.1} µs per scan (mean {:.1}; predict + update + reduce) over {} scans, \
         mean {:.1} components",
        1e6 * times[times.len() / 2],
        1e6 * mean,
        times.len(),
        sizes as f64 / times.len() as f64
    );
}
