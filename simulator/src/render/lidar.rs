//! Ray-cast scans of a scenario's LIDAR: one ray per (beam, azimuth step) from the sensor's pose,
//! the nearest hit of the floor, the room, the distractors (`lidar_scene.rs`) and the people
//! present at the scan's time, within the model's `max_range`; Gaussian range noise and random
//! dropouts. People occlude each other and the background as ray casting does.
//!
//! The whole scan is taken at one instant (no rolling shutter: at walking pace a 0.1 s rotation
//! moves a person 14 cm, which a tracker sees as a little more noise). Deterministic from
//! (scenario, sensor, seed, time): the noise comes from a stream keyed by all four. The cost is a
//! handful of closed-form intersections per ray and no allocation per ray.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use protocol::{LidarModel, SensorModel};
use rand::Rng;
use rand_distr::{Distribution, Normal};

use super::lidar_scene::{Body, LidarScene};
use crate::error::{invalid, ScenarioError};
use crate::scenario::Scenario;
use crate::seeding::StreamKey;

/// The elevations of a spinning LIDAR's beams (sensor frame, radians, ascending).
#[derive(Debug, Clone, PartialEq)]
pub struct BeamLayout {
    /// One elevation per beam, ascending.
    pub elevations: Vec<f64>,
}

impl BeamLayout {
    /// Velodyne VLP-16: 16 beams from −15° to +15°, 2° apart.
    pub fn vlp16() -> Self {
        Self::evenly_spaced(-15.0, 2.0, 16)
    }

    /// Velodyne HDL-32E: 32 beams from −30.67° to +10.67°, 4/3° apart.
    pub fn hdl32() -> Self {
        Self::evenly_spaced(-30.67, 4.0 / 3.0, 32)
    }

    /// `count` beams evenly covering the elevation interval `[low, high]` (radians), one in the
    /// middle of each of `count` equal slices (so none points exactly along the spin axis, where
    /// all azimuths meet). The default room's ceiling LIDAR sees from 0.2 rad to straight below
    /// (π/2); 40 beams put them 1.96° apart, the spacing of a VLP-16, which on a head 0.8 m below
    /// is one ring every 3–5 cm.
    pub fn covering(limits: [f64; 2], count: usize) -> Self {
        let step = (limits[1] - limits[0]) / count as f64;
        Self {
            elevations: (0..count)
                .map(|k| limits[0] + (k as f64 + 0.5) * step)
                .collect(),
        }
    }

    /// `count` beams from `lowest_deg` up, `step_deg` apart.
    fn evenly_spaced(lowest_deg: f64, step_deg: f64, count: usize) -> Self {
        Self {
            elevations: (0..count)
                .map(|k| (lowest_deg + k as f64 * step_deg).to_radians())
                .collect(),
        }
    }
}

/// Beams of [`ScanPattern::ceiling`].
const CEILING_BEAMS: usize = 40;

/// How a scan is taken: beams, azimuth resolution, point noise and dropouts.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanPattern {
    /// The beams.
    pub layout: BeamLayout,
    /// Azimuth step, radians; the columns sit at `−π + (c + ½) · step`. 0.2° is a VLP-16 at 10 Hz.
    pub azimuth_step: f64,
    /// Standard deviation of each return's range noise, m (a VLP-16 is specified at ±3 cm).
    pub range_noise_std: f64,
    /// Probability that a ray that hits something returns nothing (dark or specular surfaces).
    pub dropout_probability: f64,
}

impl ScanPattern {
    /// A pattern with 0.2° azimuth steps, 2 cm range noise and 1 % dropouts.
    pub fn new(layout: BeamLayout) -> Self {
        Self {
            layout,
            azimuth_step: 0.2f64.to_radians(),
            range_noise_std: 0.02,
            dropout_probability: 0.01,
        }
    }

    /// The pattern the default room's ceiling LIDAR is rendered with: 40 beams spread evenly over
    /// the model's elevation limits (its region of interest, so that no ray is wasted on what the
    /// descriptor says it cannot see), 0.2° azimuth steps. The raw-LIDAR test and `fusion-demo
    /// --raw` render with it, so their scans and figures are the same.
    pub fn ceiling(model: &LidarModel) -> Self {
        Self::new(BeamLayout::covering(model.elevation_limits, CEILING_BEAMS))
    }

    /// Number of azimuth columns in one rotation.
    pub fn columns(&self) -> usize {
        (std::f64::consts::TAU / self.azimuth_step).round() as usize
    }

    fn validate(&self) -> Result<(), ScenarioError> {
        if self.layout.elevations.is_empty() || self.layout.elevations.len() > usize::from(u16::MAX)
        {
            return Err(invalid("scan.layout", "needs 1 to 65535 beams"));
        }
        if !(self.azimuth_step > 1e-4 && self.azimuth_step <= std::f64::consts::PI) {
            return Err(invalid("scan.azimuth_step", "must lie in (1e-4, π] rad"));
        }
        if !(self.range_noise_std.is_finite() && self.range_noise_std >= 0.0) {
            return Err(invalid("scan.range_noise_std", "must be ≥ 0"));
        }
        if !(0.0..1.0).contains(&self.dropout_probability) {
            return Err(invalid("scan.dropout_probability", "must lie in [0, 1)"));
        }
        Ok(())
    }
}

/// One return: its cell in the range image and its point in the sensor frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidarReturn {
    /// Beam index into the layout (0 = lowest elevation).
    pub beam: u16,
    /// Azimuth column.
    pub column: u32,
    /// The point, sensor frame, m.
    pub point: [f32; 3],
}

/// One rendered scan: the returns in beam-major order (a sparse range image).
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedScan {
    /// Number of beams.
    pub beams: usize,
    /// Number of azimuth columns.
    pub columns: usize,
    /// Every return, beam by beam, each beam in column order.
    pub returns: Vec<LidarReturn>,
}

impl RenderedScan {
    /// The returns' points, in the same order.
    pub fn points(&self) -> Vec<[f32; 3]> {
        self.returns.iter().map(|r| r.point).collect()
    }
}

/// Renders the scan that `sensor` (a `lidar` sensor of the scenario) takes at scenario time `t`.
///
/// # Errors
/// [`ScenarioError`] when the sensor does not exist, is not a LIDAR, or `pattern` is unusable.
pub fn render_lidar_scan(
    scenario: &Scenario,
    sensor: &str,
    scene: &LidarScene,
    pattern: &ScanPattern,
    seed: u64,
    t: f64,
) -> Result<RenderedScan, ScenarioError> {
    let (_, spec) = scenario.sensor(sensor)?;
    let SensorModel::Lidar(model) = &spec.model else {
        return Err(invalid(sensor, "not a lidar sensor"));
    };
    pattern.validate()?;
    let bodies = bodies_at(scenario, seed, t, scene.floor_z.unwrap_or(0.0));
    let mut rng = StreamKey::new(seed, "lidar_scan")
        .with_text(sensor)
        .with(t.to_bits())
        .rng();
    let noise = Normal::new(0.0, pattern.range_noise_std)
        .map_err(|e| invalid("scan.range_noise_std", e.to_string()))?;
    let rotation = sensor_rotation(model)?;
    let origin = Vector3::from(model.position);
    let columns = pattern.columns();
    let column_directions: Vec<(f64, f64)> = (0..columns)
        .map(|c| (-std::f64::consts::PI + (c as f64 + 0.5) * pattern.azimuth_step).sin_cos())
        .collect();
    let mut returns = Vec::new();
    for (beam, elevation) in pattern.layout.elevations.iter().enumerate() {
        let (sin_el, cos_el) = elevation.sin_cos();
        for (column, (sin_az, cos_az)) in column_directions.iter().enumerate() {
            let local = Vector3::new(cos_el * cos_az, cos_el * sin_az, sin_el);
            let world = rotation * local;
            let hit = bodies
                .iter()
                .map(|body| body.hit(&origin, &world))
                .fold(scene.nearest_static(&origin, &world), f64::min);
            if hit > model.max_range || rng.gen::<f64>() < pattern.dropout_probability {
                continue;
            }
            let range = hit + noise.sample(&mut rng);
            let point = local * range;
            returns.push(LidarReturn {
                beam: beam as u16,
                column: column as u32,
                point: [point.x as f32, point.y as f32, point.z as f32],
            });
        }
    }
    Ok(RenderedScan {
        beams: pattern.layout.elevations.len(),
        columns,
        returns,
    })
}

/// The model's orientation as a rotation from the sensor frame into the world.
fn sensor_rotation(model: &LidarModel) -> Result<UnitQuaternion<f64>, ScenarioError> {
    let [w, x, y, z] = model.orientation;
    let quaternion = Quaternion::new(w, x, y, z);
    if quaternion.norm().is_nan() || quaternion.norm() <= 0.5 {
        return Err(invalid("orientation", "not a unit quaternion"));
    }
    Ok(UnitQuaternion::from_quaternion(quaternion))
}

/// The bodies of the targets present at `t`, each facing where it walks (from the truth 0.1 s
/// apart; a target standing still faces +x).
fn bodies_at(scenario: &Scenario, seed: u64, t: f64, floor_z: f64) -> Vec<Body> {
    const DT: f64 = 0.05;
    scenario
        .present_at(seed, t)
        .into_iter()
        .map(|(index, top)| {
            let before = scenario.position_of(index, seed, t - DT);
            let after = scenario.position_of(index, seed, t + DT);
            let (dx, dy) = (after[0] - before[0], after[1] - before[1]);
            let length = dx.hypot(dy);
            let heading = if length > 1e-6 {
                [dx / length, dy / length]
            } else {
                [1.0, 0.0]
            };
            Body::new(top, heading, floor_z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_have_the_documented_beams() {
        let vlp = BeamLayout::vlp16();
        assert_eq!(vlp.elevations.len(), 16);
        assert!((vlp.elevations[0].to_degrees() + 15.0).abs() < 1e-12);
        assert!((vlp.elevations[15].to_degrees() - 15.0).abs() < 1e-12);
        let hdl = BeamLayout::hdl32();
        assert!((hdl.elevations[31].to_degrees() - 10.663).abs() < 0.01);
        let ceiling = BeamLayout::covering([0.2, std::f64::consts::FRAC_PI_2], 40);
        let spacing = (ceiling.elevations[1] - ceiling.elevations[0]).to_degrees();
        println!("ceiling layout: 40 beams {spacing:.3}° apart");
        assert!((spacing - 1.963).abs() < 0.01);
        assert!(*ceiling.elevations.last().unwrap() < std::f64::consts::FRAC_PI_2);
    }
}
