//! Picking the strongest local maxima of a sampled correlation, refined to sub-grid precision.

/// A local maximum of a sampled function, refined by a parabola through it and its two neighbours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefinedPeak {
    /// Fractional index of the vertex, within half a grid step of the sampled maximum.
    pub position: f64,
    /// Height of the parabola's vertex.
    pub value: f64,
}

/// Finds the local maxima of `values` at interior indices (`1..len-1`) whose refined height is at least
/// `threshold`, keeps the `max_peaks` highest, and writes them to `peaks` strongest first.
///
/// A plateau counts once. `peaks` is cleared first and reused, so a caller that keeps it across frames stops
/// allocating once it has grown to the largest number of local maxima seen.
pub fn strongest_peaks(
    values: &[f64],
    threshold: f64,
    max_peaks: usize,
    peaks: &mut Vec<RefinedPeak>,
) {
    peaks.clear();
    for i in 1..values.len().saturating_sub(1) {
        let (left, centre, right) = (values[i - 1], values[i], values[i + 1]);
        if !(centre > left && centre >= right) {
            continue;
        }
        let peak = refine_parabolic(i, left, centre, right);
        if peak.value >= threshold {
            peaks.push(peak);
        }
    }
    peaks.sort_by(|a, b| b.value.total_cmp(&a.value));
    peaks.truncate(max_peaks);
}

/// Vertex of the parabola through `(i-1, left)`, `(i, centre)`, `(i+1, right)`, for a sampled maximum at `i`.
fn refine_parabolic(i: usize, left: f64, centre: f64, right: f64) -> RefinedPeak {
    let curvature = left - 2.0 * centre + right;
    // A flat or convex triple (only possible on plateaus) has no better estimate than the sample itself.
    if curvature >= 0.0 {
        return RefinedPeak {
            position: i as f64,
            value: centre,
        };
    }
    let offset = (0.5 * (left - right) / curvature).clamp(-0.5, 0.5);
    RefinedPeak {
        position: i as f64 + offset,
        value: centre - 0.25 * (left - right) * offset,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refines_a_sampled_parabola_exactly() {
        // y = 1 - (x - 2.3)^2 sampled at integers.
        let values: Vec<f64> = (0..5).map(|x| 1.0 - (x as f64 - 2.3).powi(2)).collect();
        let mut peaks = Vec::new();
        strongest_peaks(&values, 0.0, 3, &mut peaks);
        assert_eq!(peaks.len(), 1);
        assert!((peaks[0].position - 2.3).abs() < 1e-12);
        assert!((peaks[0].value - 1.0).abs() < 1e-12);
    }

    #[test]
    fn keeps_the_strongest_above_threshold_in_order() {
        let values = [0.0, 0.5, 0.0, 0.9, 0.0, 0.2, 0.0, 0.7, 0.0];
        let mut peaks = Vec::new();
        strongest_peaks(&values, 0.3, 2, &mut peaks);
        let positions: Vec<f64> = peaks.iter().map(|p| p.position).collect();
        assert_eq!(positions, vec![3.0, 7.0]);
        strongest_peaks(&values, 0.3, 10, &mut peaks);
        assert_eq!(peaks.len(), 3, "0.2 is below the threshold");
    }

    #[test]
    fn ignores_edges_and_counts_plateaus_once() {
        let values = [1.0, 0.5, 0.6, 0.6, 0.1, 2.0];
        let mut peaks = Vec::new();
        strongest_peaks(&values, 0.0, 5, &mut peaks);
        assert_eq!(peaks.len(), 1);
        assert_eq!(
            peaks[0].position, 2.5,
            "vertex of the parabola through the plateau"
        );
    }
}
