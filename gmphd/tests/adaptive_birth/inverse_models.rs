//! The inverse sensor models: each invertible measurement maps back to its point, with the
//! covariance that maps back to the sensor noise; cameras and microphone pairs stay `None`.

use std::f64::consts::FRAC_PI_2;

use gmphd::{
    BearingRange, Detection, HeightPrior, Lidar, MeasurementModel, MicPair, PinholeCamera,
    PositionSensor,
};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix3x4, Vector3};

/// ∂h/∂p by central differences (angular residuals wrapped), dim × 3.
fn forward_jacobian(sensor: &dyn MeasurementModel, p: &Vector3<f64>) -> DMatrix<f64> {
    let step = 1e-6;
    let mut jacobian = DMatrix::zeros(sensor.dim(), 3);
    for axis in 0..3 {
        let mut offset = Vector3::zeros();
        offset[axis] = step;
        let difference = sensor.residual(
            &sensor.measure(&(p + offset)),
            &sensor.measure(&(p - offset)),
        );
        jacobian.set_column(axis, &(difference / (2.0 * step)));
    }
    jacobian
}

/// invert(measure(p)) = p on the measured coordinates, and the inverted covariance maps
/// back to the sensor noise: J_h P J_hᵀ = R. Returns the inverted point and covariance.
fn assert_round_trip(
    sensor: &dyn MeasurementModel,
    p: Vector3<f64>,
    measured_dims: usize,
) -> (Vector3<f64>, Matrix3<f64>) {
    let (point, cov) = sensor
        .invert(&sensor.measure(&p))
        .expect("invertible measurement");
    for axis in 0..measured_dims {
        assert!(
            (point[axis] - p[axis]).abs() < 1e-9,
            "axis {axis}: {point} vs {p}"
        );
    }
    let jacobian = forward_jacobian(sensor, &p);
    let back = &jacobian * DMatrix::from_column_slice(3, 3, cov.as_slice()) * jacobian.transpose();
    let noise = sensor.noise_cov();
    assert!(
        (&back - &noise).amax() <= 1e-5 * noise.amax(),
        "J P Jᵀ = {back} vs R = {noise}"
    );
    (point, cov)
}

fn detection() -> Detection {
    Detection::new(0.9, 1.0).unwrap()
}

#[test]
fn position_sensor_inverts_back_to_the_point() {
    let sensor =
        PositionSensor::new(&[0.1, 0.2, 0.3], &[-10.0; 3], &[10.0; 3], detection()).unwrap();
    assert_round_trip(&sensor, Vector3::new(1.0, -2.0, 3.0), 3);

    let planar = PositionSensor::new(&[0.1, 0.2], &[-10.0; 2], &[10.0; 2], detection())
        .unwrap()
        .with_height_prior(HeightPrior::new(1.7, 0.5).unwrap());
    let (point, cov) = assert_round_trip(&planar, Vector3::new(4.0, 5.0, 0.0), 2);
    assert_eq!(
        point.z, 1.7,
        "a 2-D sensor's point takes the prior's height"
    );
    assert_eq!(cov[(2, 2)], 0.25);
}

#[test]
fn lidar_inverts_back_to_the_point_through_its_pose() {
    let q = nalgebra::Quaternion::new(0.9, 0.1, -0.3, 0.2).normalize();
    let lidar = Lidar::new(
        [1.0, 2.0, 3.0],
        [q.w, q.i, q.j, q.k],
        [0.05, 0.01, 0.02],
        50.0,
        [-FRAC_PI_2, FRAC_PI_2],
        detection(),
    )
    .unwrap();
    for p in [
        Vector3::new(10.0, 4.0, 1.0),
        Vector3::new(-3.0, -7.0, 5.5),
        Vector3::new(1.5, 2.2, -4.0),
    ] {
        let (point, _) = assert_round_trip(&lidar, p, 3);
        assert!((point - p).norm() < 1e-9);
    }
    // A measurement's own covariance replaces the default noise: 4 R gives 4 P.
    let z = lidar.measure(&Vector3::new(10.0, 4.0, 1.0));
    let (_, default_cov) = lidar.invert(&z).unwrap();
    let (_, own_cov) = lidar
        .invert_with_noise(&z, &(lidar.noise_cov() * 4.0))
        .unwrap();
    assert!((own_cov - default_cov * 4.0).amax() < 1e-12);
    // Degenerate or malformed measurements are not inverted.
    assert!(lidar
        .invert(&DVector::from_vec(vec![0.0, 0.1, 0.1]))
        .is_none());
    assert!(lidar
        .invert(&DVector::from_vec(vec![-1.0, 0.1, 0.1]))
        .is_none());
    assert!(lidar.invert(&DVector::from_vec(vec![1.0, 0.1])).is_none());
    assert!(lidar
        .invert(&DVector::from_vec(vec![1.0, f64::NAN, 0.1]))
        .is_none());
}

#[test]
fn bearing_range_inverts_in_the_horizontal_plane() {
    let sensor = BearingRange::new([10.0, -5.0, 2.0], [0.02, 1.5], 500.0, detection()).unwrap();
    let (point, cov) = assert_round_trip(&sensor, Vector3::new(100.0, 50.0, 7.0), 2);
    assert_eq!(point.z, 2.0, "by default the sensor's own height");
    assert_eq!(cov[(2, 2)], gmphd::measurement::DEFAULT_HEIGHT_STD.powi(2));
    // Across the ±π bearing wrap too.
    assert_round_trip(&sensor, Vector3::new(-100.0, -5.1, 0.0), 2);
    let lifted = sensor.with_height_prior(HeightPrior::new(30.0, 3.0).unwrap());
    let (point, _) = lifted.invert(&DVector::from_vec(vec![0.0, 10.0])).unwrap();
    assert!((point - Vector3::new(20.0, -5.0, 30.0)).norm() < 1e-12);
    assert!(lifted.invert(&DVector::from_vec(vec![0.3, 0.0])).is_none());
}

#[test]
fn cameras_and_microphone_pairs_are_not_invertible() {
    let projection = Matrix3x4::new(
        500.0, 0.0, 320.0, 0.0, 0.0, 500.0, 240.0, 0.0, 0.0, 0.0, 1.0, 0.0,
    );
    let camera = PinholeCamera::new(projection, [640.0, 480.0], [3.0, 3.0], detection()).unwrap();
    let p = Vector3::new(0.2, 0.1, 3.0);
    assert!(camera.invert(&camera.measure(&p)).is_none());
    let pair = MicPair::new([0.0; 3], [0.5, 0.0, 0.0], 343.0, 6e-5, detection()).unwrap();
    assert!(pair.invert(&pair.measure(&p)).is_none());
}
