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

/// Covariance (rows) of a measurement `[range, azimuth, elevation]` whose point is uncertain by `centre_std`
/// metres in every direction, on top of the sensor's own `noise_std` (range in metres, angles in radians).
///
/// An isotropic spread σ² I of the point maps through the Jacobian J of the spherical coordinates to
/// σ² J Jᵀ = σ² diag(1, 1/h², 1/r²), h the point's horizontal distance from the sensor's axis and r its range
/// (J's rows are orthogonal, so no cross terms); the sensor's noise adds on the diagonal. Near the axis the
/// azimuth carries no information: h is taken as at least `centre_std` there, so the azimuth's standard
/// deviation stays at most about a radian and the matrix finite.
pub fn measurement_covariance(
    [range, _, elevation]: [f64; 3],
    centre_std: f64,
    noise_std: [f64; 3],
) -> [[f64; 3]; 3] {
    let spread = centre_std * centre_std;
    let horizontal = (range * elevation.cos()).abs().max(centre_std);
    let range = range.max(centre_std);
    let diagonal = [
        noise_std[0].powi(2) + spread,
        noise_std[1].powi(2) + spread / (horizontal * horizontal),
        noise_std[2].powi(2) + spread / (range * range),
    ];
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { diagonal[i] } else { 0.0 }))
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

    /// The covariance against a Monte Carlo-free check: the Jacobian of `point_to_measurement` by central
    /// differences, J σ² Jᵀ, plus the sensor noise.
    #[test]
    fn covariance_is_the_spread_through_the_jacobian() {
        let point = [0.7, -1.1, -0.9];
        let (std, noise) = (0.05, [0.02, 0.01, 0.005]);
        let h = 1e-6;
        let jacobian: Vec<[f64; 3]> = (0..3)
            .map(|axis| {
                let mut plus = point;
                let mut minus = point;
                plus[axis] += h;
                minus[axis] -= h;
                let (p, m) = (point_to_measurement(plus), point_to_measurement(minus));
                std::array::from_fn(|k| (p[k] - m[k]) / (2.0 * h))
            })
            .collect();
        let covariance = measurement_covariance(point_to_measurement(point), std, noise);
        for i in 0..3 {
            for j in 0..3 {
                let spread: f64 = (0..3).map(|a| jacobian[a][i] * jacobian[a][j]).sum::<f64>();
                let expected = std * std * spread + if i == j { noise[i] * noise[i] } else { 0.0 };
                assert!(
                    (covariance[i][j] - expected).abs() < 1e-8,
                    "({i}, {j}): {} != {expected}",
                    covariance[i][j]
                );
            }
        }
    }

    #[test]
    fn covariance_stays_finite_on_the_axis() {
        let covariance =
            measurement_covariance([1.0, 0.0, std::f64::consts::FRAC_PI_2], 0.05, [0.0; 3]);
        assert!(covariance.iter().flatten().all(|v| v.is_finite()));
        assert!(
            (covariance[1][1] - 1.0).abs() < 1e-9,
            "azimuth σ about a radian"
        );
    }

    #[test]
    fn azimuth_stays_in_the_half_open_interval() {
        assert_eq!(point_to_measurement([-1.0, 0.0, 0.0])[1], -PI);
        assert_eq!(point_to_measurement([-1.0, -0.0, 0.0])[1], -PI);
        assert!(point_to_measurement([-1.0, 1e-9, 0.0])[1] < PI);
    }
}
