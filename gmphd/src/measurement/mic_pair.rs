//! Microphone pair: time difference of arrival (TDOA) of a sound source (Pham 5.4–5.5).

use nalgebra::{DMatrix, DVector, Vector3};

use super::{
    check_uniforms, diagonal_noise, finite_point, hints_of, positive, Detection, MeasurementModel,
    UpdateHints,
};
use serde::Serialize;

use crate::error::{invalid, FilterError};

/// tau = (|x − m2| − |x − m1|) / c + noise (Pham eq. 5.25), in seconds.
///
/// The measurement region is [−d/c, d/c] with d the microphone spacing; every
/// source is audible with the pair's detection probability (the direction is
/// what a pair measures, so there is no range limit).
///
/// [`MicPair::in_plane`] makes it Pham's planar model (§5.5, speakers and
/// microphones in one horizontal plane): the source is taken at a fixed height
/// and the state's own height is not used. Why: a horizontal pair's TDOA depends
/// on the source's height only through the square of its distance from the pair's
/// plane (the derivative vanishes in the plane), so pairs at one height do not
/// observe it; a 3-D state's height then stays where its birth put it, and through
/// the hyperboloid's curvature a wrong height moves the horizontal estimate (a
/// source taken 0.4 m below the pair while it is 0.1 m above is put 0.2 m closer
/// to the pair's axis at 0.5 m from it).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MicPair {
    m1: Vector3<f64>,
    m2: Vector3<f64>,
    speed_of_sound: f64,
    noise_cov: DMatrix<f64>,
    detection: Detection,
    /// The height the source is taken at (planar model), or `None` for the state's own.
    source_height: Option<f64>,
}

impl MicPair {
    /// Speed of sound in dry air at 20 °C, m/s (the protocol's default).
    pub const DEFAULT_SPEED_OF_SOUND: f64 = 343.0;

    /// Microphones `m1`, `m2` (world, metres), speed of sound (m/s), TDOA noise (s).
    pub fn new(
        m1: [f64; 3],
        m2: [f64; 3],
        speed_of_sound: f64,
        noise_std: f64,
        detection: Detection,
    ) -> Result<Self, FilterError> {
        let m1 = finite_point(m1, "microphone 1 position")?;
        let m2 = finite_point(m2, "microphone 2 position")?;
        if (m2 - m1).norm() <= 0.0 {
            return Err(invalid("microphone pair", "the two microphones coincide"));
        }
        Ok(Self {
            m1,
            m2,
            speed_of_sound: positive(speed_of_sound, "speed of sound")?,
            noise_cov: diagonal_noise(&[noise_std])?,
            detection,
            source_height: None,
        })
    }

    /// The planar model: sources are taken at height `z` (m, finite) whatever the
    /// state's height (see the type's documentation).
    pub fn in_plane(mut self, z: f64) -> Result<Self, FilterError> {
        if !z.is_finite() {
            return Err(invalid(
                "microphone pair",
                "the source height is not finite",
            ));
        }
        self.source_height = Some(z);
        Ok(self)
    }

    /// The height sources are taken at, for the planar model.
    pub fn source_height(&self) -> Option<f64> {
        self.source_height
    }

    /// Largest possible |tau|: spacing / speed of sound.
    pub fn max_delay(&self) -> f64 {
        (self.m2 - self.m1).norm() / self.speed_of_sound
    }
}

impl MeasurementModel for MicPair {
    fn dim(&self) -> usize {
        1
    }

    fn measure_into(&self, p: &Vector3<f64>, out: &mut [f64]) {
        let p = match self.source_height {
            Some(z) => Vector3::new(p.x, p.y, z),
            None => *p,
        };
        out[0] = ((p - self.m2).norm() - (p - self.m1).norm()) / self.speed_of_sound;
    }

    fn noise_cov(&self) -> DMatrix<f64> {
        self.noise_cov.clone()
    }

    fn detection_probability(&self, _p: &Vector3<f64>) -> f64 {
        self.detection.probability
    }

    /// A pair hears a talker only while the talker talks.
    fn detects_only_active(&self) -> bool {
        true
    }

    fn delay_entry(&self) -> Option<usize> {
        Some(0)
    }

    fn clutter_rate(&self) -> f64 {
        self.detection.clutter_rate
    }

    fn clutter_density(&self) -> f64 {
        1.0 / (2.0 * self.max_delay())
    }

    /// Indexed by the delay.
    fn update_hints(&self) -> UpdateHints {
        hints_of(self, 0)
    }

    fn sample_clutter(&self, u: &[f64]) -> Result<DVector<f64>, FilterError> {
        check_uniforms(u, 1)?;
        let max = self.max_delay();
        Ok(DVector::from_element(1, -max + u[0] * 2.0 * max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delay_sign_and_range() {
        let pair = MicPair::new(
            [0.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            343.0,
            6e-5,
            Detection::new(0.7, 1.0).unwrap(),
        )
        .unwrap();
        // A source on the axis beyond m2 is closer to m2: negative delay of -d/c.
        let tau = pair.measure(&Vector3::new(3.0, 0.0, 0.0))[0];
        assert!((tau + 0.5 / 343.0).abs() < 1e-15);
        // On the perpendicular bisector the delay vanishes.
        assert!(pair.measure(&Vector3::new(0.25, 2.0, 1.0))[0].abs() < 1e-15);
        assert!((pair.clutter_density() - 343.0).abs() < 1e-9);
        assert!(MicPair::new(
            [0.0; 3],
            [0.0; 3],
            343.0,
            1e-5,
            Detection::new(0.7, 1.0).unwrap()
        )
        .is_err());
    }

    #[test]
    fn the_planar_model_ignores_the_state_height() {
        let detection = Detection::new(0.7, 1.0).unwrap();
        let pair = MicPair::new([1.25, 0.0, 1.5], [1.75, 0.0, 1.5], 343.0, 6e-5, detection)
            .unwrap()
            .in_plane(1.5)
            .unwrap();
        let at = |z: f64| pair.measure(&Vector3::new(2.0, 0.5, z))[0];
        assert_eq!(at(0.3), at(1.5));
        let spatial =
            MicPair::new([1.25, 0.0, 1.5], [1.75, 0.0, 1.5], 343.0, 6e-5, detection).unwrap();
        assert!((spatial.measure(&Vector3::new(2.0, 0.5, 1.5))[0] - at(0.3)).abs() < 1e-15);
        assert!(spatial.measure(&Vector3::new(2.0, 0.5, 0.3))[0] != at(0.3));
        assert!(spatial.clone().in_plane(f64::NAN).is_err());
    }
}
