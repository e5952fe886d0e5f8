//! The in-memory point cloud every LIDAR reader produces and the pipeline consumes.

/// One LIDAR scan: Cartesian points in the sensor frame, in metres, with an optional return intensity each.
///
/// Coordinates are `f32` because both on-disk formats (KITTI `.bin`, PCD from a sensor driver) store them so, and
/// a scan in the sensor frame spans at most a few hundred metres, where `f32` keeps sub-millimetre resolution.
/// Points may be non-finite (organised PCD clouds mark "no return" with NaN); the pipeline skips those.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PointCloud {
    /// Point coordinates `[x, y, z]` in the sensor frame (metres).
    pub points: Vec<[f32; 3]>,
    /// Return intensity per point, when the source has one. If present it holds exactly one value per point;
    /// the readers guarantee this and the writers refuse a cloud that breaks it.
    pub intensity: Option<Vec<f32>>,
}

impl PointCloud {
    /// A cloud of bare points with no intensity channel.
    pub fn from_points(points: Vec<[f32; 3]>) -> Self {
        Self {
            points,
            intensity: None,
        }
    }

    /// Number of points in the cloud.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the cloud holds no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Whether the intensity channel, if any, has one value per point (the invariant the writers check).
    pub fn intensity_matches_points(&self) -> bool {
        self.intensity
            .as_ref()
            .is_none_or(|values| values.len() == self.points.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intensity_length_invariant_is_checked() {
        let mut cloud = PointCloud::from_points(vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        assert_eq!(cloud.len(), 2);
        assert!(!cloud.is_empty());
        assert!(cloud.intensity_matches_points());
        cloud.intensity = Some(vec![0.5]);
        assert!(!cloud.intensity_matches_points());
        cloud.intensity = Some(vec![0.5, 0.25]);
        assert!(cloud.intensity_matches_points());
    }
}
