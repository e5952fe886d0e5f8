//! Euclidean clustering: points closer than a tolerance to some point of a cluster belong to that cluster
//! (the connected components of the "within tolerance" graph), found by region growing over a k-d tree.

use super::error::LidarConfigError;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use serde::{Deserialize, Serialize};

/// Parameters of Euclidean clustering.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClusteringConfig {
    /// Largest gap (metres) between neighbouring points of one object. Default 0.5 m: bridges the vertical gap
    /// between adjacent beams of a 32-beam sensor (≈1.3°) on an object up to about 20 m away, yet keeps apart
    /// objects more than half a metre from each other.
    pub tolerance: f64,
    /// Smaller clusters are dropped as noise. Default 10 points.
    pub min_points: usize,
    /// Larger clusters are dropped as structure (walls, buildings, vegetation) rather than trackable objects.
    /// Default 20 000 points.
    pub max_points: usize,
}

impl Default for ClusteringConfig {
    fn default() -> Self {
        Self {
            tolerance: 0.5,
            min_points: 10,
            max_points: 20_000,
        }
    }
}

impl ClusteringConfig {
    /// Checks that the parameters can be used.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the bad parameter.
    pub fn validate(&self) -> Result<(), LidarConfigError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(LidarConfigError::NotPositive {
                name: "clustering.tolerance",
                value: self.tolerance,
            });
        }
        check_point_range("clustering.min_points", self.min_points, self.max_points)
    }
}

/// One cluster: the indices of its points and their centroid.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCluster {
    /// Indices of the member points, into the slice that was clustered (the pipeline maps them back to the
    /// original cloud), in the order region growing reached them.
    pub indices: Vec<usize>,
    /// Mean of the member points (metres, sensor frame).
    pub centroid: [f64; 3],
}

/// Groups finite points into Euclidean clusters and keeps those with `min_points..=max_points` members. Clusters
/// come out in the order of their lowest point index, so the result depends only on the input.
///
/// A fixed tolerance has one known blind spot: a horizontal surface just below the sensor (a car roof seen from
/// a sensor 1.8 m up) is met by the beams at grazing incidence, its rings lie metres apart, and a ring can be
/// split off as a cluster of its own, i.e. a second measurement of the same object. Range-image segmentation
/// (Lee et al.), where adjacency is by beam index rather than distance, does not have this problem.
pub fn euclidean_clusters(points: &[[f64; 3]], config: &ClusteringConfig) -> Vec<PointCluster> {
    if points.is_empty() {
        return Vec::new();
    }
    let tree: ImmutableKdTree<f64, 3> = ImmutableKdTree::new_from_slice(points);
    let radius_squared = config.tolerance * config.tolerance;
    let mut assigned = vec![false; points.len()];
    let mut clusters = Vec::new();
    for seed in 0..points.len() {
        if assigned[seed] {
            continue;
        }
        assigned[seed] = true;
        let mut members = vec![seed];
        // Region growing: every member's neighbourhood is searched once; `members` doubles as the work queue.
        let mut next = 0;
        while let Some(&current) = members.get(next) {
            next += 1;
            for neighbour in
                tree.within_unsorted::<SquaredEuclidean>(&points[current], radius_squared)
            {
                let index = neighbour.item as usize;
                if !assigned[index] {
                    assigned[index] = true;
                    members.push(index);
                }
            }
        }
        // Oversized clusters are grown to the end anyway, so that their points cannot seed other clusters.
        if (config.min_points..=config.max_points).contains(&members.len()) {
            let centroid = centroid(points, &members);
            clusters.push(PointCluster {
                indices: members,
                centroid,
            });
        }
    }
    clusters
}

/// Mean of the indexed points.
/// Checks an object's size limits in points: at least one, and `max` not below `min` (`min_name` is the
/// setting's name in errors).
pub(crate) fn check_point_range(
    min_name: &'static str,
    min: usize,
    max: usize,
) -> Result<(), LidarConfigError> {
    if min == 0 {
        return Err(LidarConfigError::TooSmall {
            name: min_name,
            value: 0,
            minimum: 1,
        });
    }
    if max < min {
        return Err(LidarConfigError::ClusterSizeRange { min, max });
    }
    Ok(())
}

fn centroid(points: &[[f64; 3]], indices: &[usize]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for &index in indices {
        for (axis, total) in sum.iter_mut().enumerate() {
            *total += points[index][axis];
        }
    }
    sum.map(|total| total / indices.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line of `count` points spaced `step` apart along x, starting at `start`.
    fn line(start: [f64; 3], count: usize, step: f64) -> Vec<[f64; 3]> {
        (0..count)
            .map(|k| [start[0] + k as f64 * step, start[1], start[2]])
            .collect()
    }

    #[test]
    fn separates_groups_farther_apart_than_the_tolerance() {
        let mut points = line([0.0, 0.0, 0.0], 20, 0.1);
        points.extend(line([5.0, 0.0, 0.0], 15, 0.3));
        points.extend(line([0.0, 3.0, 0.0], 3, 0.1)); // too small
        let config = ClusteringConfig {
            tolerance: 0.35,
            min_points: 5,
            max_points: 100,
        };
        let clusters = euclidean_clusters(&points, &config);
        assert_eq!(clusters.len(), 2);
        let mut first: Vec<usize> = clusters[0].indices.clone();
        first.sort_unstable();
        assert_eq!(first, (0..20).collect::<Vec<_>>());
        assert_eq!(clusters[1].indices.len(), 15);
        assert!((clusters[0].centroid[0] - 0.95).abs() < 1e-12);
        assert!((clusters[1].centroid[0] - (5.0 + 7.0 * 0.3)).abs() < 1e-12);
    }

    #[test]
    fn chains_connect_through_intermediate_points_and_oversized_clusters_are_dropped() {
        // End points 3 m apart but linked by 0.2 m steps: one cluster, dropped because it exceeds max_points.
        let points = line([0.0, 0.0, 0.0], 16, 0.2);
        let small_max = ClusteringConfig {
            tolerance: 0.25,
            min_points: 1,
            max_points: 15,
        };
        assert!(euclidean_clusters(&points, &small_max).is_empty());
        let clusters = euclidean_clusters(
            &points,
            &ClusteringConfig {
                max_points: 16,
                ..small_max
            },
        );
        assert_eq!(clusters.len(), 1);
        assert_eq!(clusters[0].indices.len(), 16);
    }

    #[test]
    fn duplicate_points_and_empty_input() {
        let points = vec![[1.0, 1.0, 1.0]; 50];
        let clusters = euclidean_clusters(&points, &ClusteringConfig::default());
        assert_eq!(clusters.len(), 1);
        assert_eq!(clusters[0].centroid, [1.0, 1.0, 1.0]);
        assert!(euclidean_clusters(&[], &ClusteringConfig::default()).is_empty());
    }

    #[test]
    fn invalid_parameters_are_named() {
        let zero = ClusteringConfig {
            tolerance: 0.0,
            ..ClusteringConfig::default()
        };
        assert!(zero
            .validate()
            .unwrap_err()
            .to_string()
            .contains("tolerance"));
        let inverted = ClusteringConfig {
            min_points: 10,
            max_points: 5,
            ..ClusteringConfig::default()
        };
        assert_eq!(
            inverted.validate(),
            Err(LidarConfigError::ClusterSizeRange { min: 10, max: 5 })
        );
    }
}
