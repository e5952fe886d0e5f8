//! Ground removal: which points of a scan belong to the ground and must not be clustered into objects.

use super::error::LidarConfigError;
use super::ransac_plane::{fit_ground_plane, Plane, RansacPlaneParams};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// How the ground is told apart from objects. In a configuration file the variant is chosen by `method`:
///
/// ```toml
/// [ground]
/// method = "ransac"          # or "height", or "none"
/// iterations = 400           # RANSAC fields; "height" takes max_ground_z instead
/// distance_threshold = 0.15
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum GroundRemoval {
    /// Keep every point (e.g. a sensor that never sees the ground, or a cloud already filtered).
    None,
    /// Every point below a height in the sensor frame is ground; right for flat ground and a level sensor.
    Height(HeightThreshold),
    /// The dominant near-horizontal plane found by RANSAC is ground; tolerates a tilted sensor or slope.
    Ransac(RansacPlaneParams),
}

impl Default for GroundRemoval {
    /// RANSAC with its defaults: it needs no knowledge of the mounting height.
    fn default() -> Self {
        Self::Ransac(RansacPlaneParams::default())
    }
}

/// Parameters of [`GroundRemoval::Height`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeightThreshold {
    /// Points with `z` below this (metres, sensor frame) are ground. Default −1.5: ground about 1.7 m below the
    /// sensor (KITTI's Velodyne is mounted 1.73 m up) plus a 0.2 m margin for noise and small slopes.
    pub max_ground_z: f64,
}

impl Default for HeightThreshold {
    fn default() -> Self {
        Self { max_ground_z: -1.5 }
    }
}

impl GroundRemoval {
    /// Checks that the parameters can be used.
    ///
    /// # Errors
    /// [`LidarConfigError`] naming the bad parameter.
    pub fn validate(&self) -> Result<(), LidarConfigError> {
        match self {
            Self::None => Ok(()),
            Self::Height(height) if !height.max_ground_z.is_finite() => {
                Err(LidarConfigError::NotFinite {
                    name: "ground.max_ground_z",
                    value: height.max_ground_z,
                })
            }
            Self::Height(_) => Ok(()),
            Self::Ransac(ransac) => {
                if ransac.iterations == 0 {
                    return Err(LidarConfigError::TooSmall {
                        name: "ground.iterations",
                        value: 0,
                        minimum: 1,
                    });
                }
                if !(ransac.distance_threshold.is_finite() && ransac.distance_threshold > 0.0) {
                    return Err(LidarConfigError::NotPositive {
                        name: "ground.distance_threshold",
                        value: ransac.distance_threshold,
                    });
                }
                if !(ransac.max_tilt_deg > 0.0 && ransac.max_tilt_deg <= 90.0) {
                    return Err(LidarConfigError::TiltOutOfRange(ransac.max_tilt_deg));
                }
                if ransac.min_inliers < 3 {
                    return Err(LidarConfigError::TooSmall {
                        name: "ground.min_inliers",
                        value: ransac.min_inliers,
                        minimum: 3,
                    });
                }
                Ok(())
            }
        }
    }

    /// Marks each point `true` if it is ground. Points are in the sensor frame (metres).
    pub fn ground_mask(&self, points: &[[f64; 3]]) -> Vec<bool> {
        self.classify(points).0
    }

    /// The ground mask and the ground plane: RANSAC's fit, the horizontal plane at `max_ground_z` for the
    /// height threshold (so heights above it are measured from the threshold), none for `none` or when RANSAC
    /// finds no plane.
    pub fn classify(&self, points: &[[f64; 3]]) -> (Vec<bool>, Option<Plane>) {
        match self {
            Self::None => (vec![false; points.len()], None),
            Self::Height(height) => (
                points.iter().map(|p| p[2] < height.max_ground_z).collect(),
                Some(Plane {
                    normal: Vector3::z(),
                    offset: -height.max_ground_z,
                }),
            ),
            Self::Ransac(ransac) => match fit_ground_plane(points, ransac) {
                Some(fit) => (
                    points
                        .iter()
                        .map(|p| fit.plane.signed_distance(p).abs() <= ransac.distance_threshold)
                        .collect(),
                    Some(fit.plane),
                ),
                None => (vec![false; points.len()], None),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_threshold_marks_points_below_it() {
        let ground = GroundRemoval::Height(HeightThreshold { max_ground_z: -1.0 });
        let mask = ground.ground_mask(&[[1.0, 0.0, -1.2], [1.0, 0.0, -0.8], [5.0, 5.0, -1.0]]);
        assert_eq!(mask, vec![true, false, false]);
        assert_eq!(
            GroundRemoval::None.ground_mask(&[[0.0, 0.0, -9.0]]),
            vec![false]
        );
    }

    #[test]
    fn invalid_parameters_are_named() {
        let bad_height = GroundRemoval::Height(HeightThreshold {
            max_ground_z: f64::NAN,
        });
        assert!(bad_height
            .validate()
            .unwrap_err()
            .to_string()
            .contains("max_ground_z"));
        let tilt = GroundRemoval::Ransac(RansacPlaneParams {
            max_tilt_deg: 120.0,
            ..RansacPlaneParams::default()
        });
        assert_eq!(
            tilt.validate(),
            Err(LidarConfigError::TiltOutOfRange(120.0))
        );
        let threshold = GroundRemoval::Ransac(RansacPlaneParams {
            distance_threshold: 0.0,
            ..RansacPlaneParams::default()
        });
        assert!(threshold
            .validate()
            .unwrap_err()
            .to_string()
            .contains("distance_threshold"));
        assert_eq!(GroundRemoval::default().validate(), Ok(()));
    }
}
