//! A point in the sensor frame as a LIDAR measurement `[range, azimuth, elevation]` (the protocol's convention).

use std::f64::consts::PI;

/// Converts a sensor-frame point to `[range, azimuth, elevation]`: range = ‖p‖, azimuth = atan2(y, x) in
/// [−π, π), elevation = atan2(z, √(x² + y²)) in [−π/2, π/2]. The origin maps to `[0, 0, 0]`.
pub fn point_to_measurement(point: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = point;
    let horizontal = x.hypot(y);
    let mut azimuth = y.atan2(x);
    // atan2 returns +π for points on the negative x axis; the protocol's azimuth interval is half-open at +π.
    if azimuth >= PI {
        azimuth -= 2.0 * PI;
    }
    [horizontal.hypot(z), azimuth, z.atan2(horizontal)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_4;

    fn assert_close(actual: [f64; 3], expected: [f64; 3]) {
        for (a, e) in actual.iter().zip(expected) {
            assert!((a - e).abs() < 1e-12, "{actual:?} != {expected:?}");
        }
    }

    #[test]
    fn follows_the_protocol_convention() {
        assert_close(
            point_to_measurement([3.0, 0.0, 4.0]),
            [5.0, 0.0, 0.927_295_218_001_612_2],
        );
        assert_close(
            point_to_measurement([1.0, 1.0, 0.0]),
            [2f64.sqrt(), FRAC_PI_4, 0.0],
        );
        assert_close(
            point_to_measurement([0.0, -2.0, -2.0]),
            [8f64.sqrt(), -PI / 2.0, -FRAC_PI_4],
        );
        assert_close(point_to_measurement([0.0, 0.0, 0.0]), [0.0, 0.0, 0.0]);
    }

    #[test]
    fn azimuth_stays_in_the_half_open_interval() {
        assert_eq!(point_to_measurement([-1.0, 0.0, 0.0])[1], -PI);
        assert_eq!(point_to_measurement([-1.0, -0.0, 0.0])[1], -PI);
        assert!(point_to_measurement([-1.0, 1e-9, 0.0])[1] < PI);
    }
}
