//! Correlation evidence pooled over frames, as far as a talker's TDOA may drift between them.
//!
//! Why: in a reverberant room one frame's correlation rarely has its highest peak at a talker's
//! direct path (on the rendered default room, T60 0.3 s, SNR 20 dB: 15 % of talking frames within
//! one sample). The reverberant peaks move from frame to frame (their errors are nearly
//! uncorrelated, lag-1 correlation 0.09), while the direct path stays where the talker is. Adding
//! each frame's correlation to a decaying sum of the earlier ones keeps what persists and lets the
//! rest average out. Before the sum is added to, it is widened by a running maximum over the lags
//! a talker may move through in one frame (the max-product step of a grid tracker, as in
//! track-before-detect: Ward, Lehmann & Williamson 2003 accumulate the steered response over
//! time in a particle filter for the same reason), so that a walking talker's peak is not
//! smeared out. Frames without speech add nothing: the sum only fades.

/// A decaying, drift-tolerant sum of correlations sampled on one lag grid.
#[derive(Debug, Clone)]
pub struct PooledCorrelation {
    /// Weight kept of the earlier frames' sum at each new frame, in [0, 1).
    memory: f64,
    /// Grid points a talker's peak may move from one frame to the next.
    drift_points: usize,
    /// The decaying sum (not normalised).
    sum: Vec<f64>,
    /// Scratch for the widened sum, then the pooled correlation handed out.
    pooled: Vec<f64>,
    /// Sum of the frames' weights in `sum`: dividing by it gives one frame's scale.
    weight: f64,
}

impl PooledCorrelation {
    /// An empty pool keeping `memory` (in [0, 1)) of the earlier frames at each frame, whose
    /// peaks may move `drift_points` grid points per frame.
    pub fn new(memory: f64, drift_points: usize) -> Self {
        Self {
            memory,
            drift_points,
            sum: Vec::new(),
            pooled: Vec::new(),
            weight: 0.0,
        }
    }

    /// Adds one frame's correlation and returns the pooled one, on one frame's scale (a
    /// weighted mean: a peak that is in every frame keeps its height, one that is in a single
    /// frame is divided by the frames' total weight).
    ///
    /// A correlation of another length than the previous one starts a new pool.
    pub fn add(&mut self, correlation: &[f64]) -> &[f64] {
        if self.sum.len() != correlation.len() {
            self.sum = vec![0.0; correlation.len()];
            self.weight = 0.0;
        }
        widen(&self.sum, self.drift_points, &mut self.pooled);
        for ((sum, widened), value) in self.sum.iter_mut().zip(&self.pooled).zip(correlation) {
            *sum = self.memory * widened + value;
        }
        self.weight = self.memory * self.weight + 1.0;
        let scale = 1.0 / self.weight;
        for (pooled, sum) in self.pooled.iter_mut().zip(&self.sum) {
            *pooled = sum * scale;
        }
        &self.pooled
    }

    /// Forgets every earlier frame (a new stream starts).
    pub fn clear(&mut self) {
        self.sum.clear();
        self.weight = 0.0;
    }

    /// A frame without speech: the earlier frames' evidence fades by one frame's memory.
    pub fn fade(&mut self) {
        for sum in &mut self.sum {
            *sum *= self.memory;
        }
        self.weight *= self.memory;
    }
}

/// `out[i]` = the largest of `values` within `reach` points of `i` (a running maximum).
fn widen(values: &[f64], reach: usize, out: &mut Vec<f64>) {
    out.clear();
    out.extend((0..values.len()).map(|i| {
        let last = (i + reach).min(values.len() - 1);
        values[i.saturating_sub(reach)..=last]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Index of the largest value.
    fn argmax(values: &[f64]) -> usize {
        (0..values.len())
            .max_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap()
    }

    #[test]
    fn without_memory_the_frame_is_returned_as_it_is() {
        let mut pool = PooledCorrelation::new(0.0, 3);
        let frame = [0.1, 0.5, -0.2, 0.3];
        pool.add(&[1.0, 1.0, 1.0, 1.0]);
        assert_eq!(pool.add(&frame), frame);
    }

    #[test]
    fn a_persistent_peak_outgrows_peaks_that_wander() {
        // Every frame: a true peak of 0.3 at index 40 and a stronger spurious one (0.5) at a
        // random place. Alone, a frame's highest point is the spurious peak; pooled, the true.
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let mut pool = PooledCorrelation::new(0.8, 1);
        let mut pooled_peak = 0;
        for _ in 0..20 {
            let mut frame = vec![0.0; 100];
            frame[40] = 0.3;
            frame[rng.gen_range(50..100)] = 0.5;
            assert_ne!(argmax(&frame), 40);
            pooled_peak = argmax(pool.add(&frame));
        }
        assert_eq!(pooled_peak, 40);
    }

    #[test]
    fn a_drifting_peak_is_followed_within_the_drift() {
        // A peak moving one point per frame, with a drift allowance of one point: the pooled
        // peak is where the frame's is, at full height.
        let mut pool = PooledCorrelation::new(0.8, 1);
        for step in 0..30 {
            let mut frame = vec![0.0; 100];
            frame[20 + step] = 1.0;
            let pooled = pool.add(&frame);
            assert_eq!(argmax(pooled), 20 + step);
            assert!((pooled[20 + step] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn silence_fades_the_pool_and_a_new_voice_takes_over() {
        let mut pool = PooledCorrelation::new(0.8, 0);
        let mut old = vec![0.0; 10];
        old[2] = 1.0;
        for _ in 0..10 {
            pool.add(&old);
        }
        for _ in 0..10 {
            pool.fade();
        }
        let mut new = vec![0.0; 10];
        new[7] = 1.0;
        let pooled = pool.add(&new);
        assert_eq!(argmax(pooled), 7);
        // Ten silent frames leave 0.8^10 of the old pool's weight: the old voice is at 0.38 of
        // the new one (a talker who paused 2.5 s is still heard where he was, faintly).
        assert!(pooled[2] < 0.4 * pooled[7], "{pooled:?}");
    }
}
