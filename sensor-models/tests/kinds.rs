//! One descriptor per kind: the model it yields measures, detects and clutters as the
//! contract (PROTOCOL.md) says.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use nalgebra::{DVector, Vector3};
use protocol::{
    BearingRangeModel, CameraModel, LidarModel, MicPairModel, PositionModel, Region,
    SensorDescriptor, SensorId, SensorKind, SensorModel, Site,
};
use sensor_models::{measurement_model, Error};

fn descriptor(model: SensorModel, p_d: f64, clutter: f64) -> SensorDescriptor {
    SensorDescriptor::new(
        Site::default(),
        SensorId::new("s1").unwrap(),
        model,
        p_d,
        clutter,
    )
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// The example camera of PROTOCOL.md: f = 800 px, principal point (320, 240), its centre
/// at world (−0.3, −0.225, 2) looking along +z.
fn example_camera() -> SensorModel {
    SensorModel::Camera(CameraModel {
        projection: [
            [800.0, 0.0, 320.0, -400.0],
            [0.0, 800.0, 240.0, -300.0],
            [0.0, 0.0, 1.0, -2.0],
        ],
        image_size: [640, 480],
        noise_std: [3.0, 3.0],
    })
}

#[test]
fn camera_projects_known_points_to_their_pixels() {
    let model = measurement_model(&descriptor(example_camera(), 0.95, 2.0)).unwrap();
    assert_eq!(model.dim(), 2);
    // On the optical axis, 3 m in front: the principal point.
    let z = model.measure(&Vector3::new(-0.3, -0.225, 5.0));
    assert!(close(z[0], 320.0, 1e-9) && close(z[1], 240.0, 1e-9), "{z}");
    // (800·0.2 + 320·4 − 400, 800·0.1 + 240·4 − 300) / (4 − 2) = (520, 370).
    let p = Vector3::new(0.2, 0.1, 4.0);
    let z = model.measure(&p);
    assert!(close(z[0], 520.0, 1e-9) && close(z[1], 370.0, 1e-9), "{z}");
    assert_eq!(model.detection_probability(&p), 0.95);
    // Behind the camera, and in front but outside the image: not detectable.
    assert_eq!(
        model.detection_probability(&Vector3::new(0.2, 0.1, 1.0)),
        0.0
    );
    assert_eq!(
        model.detection_probability(&Vector3::new(30.0, 0.1, 4.0)),
        0.0
    );
    assert_eq!(
        model.noise_cov(),
        nalgebra::DMatrix::from_diagonal_element(2, 2, 9.0)
    );
    assert_eq!(model.clutter_rate(), 2.0);
    assert!(close(model.clutter_density(), 1.0 / (640.0 * 480.0), 1e-18));
}

#[test]
fn mic_pair_tau_is_positive_nearer_the_second_microphone() {
    let model = measurement_model(&descriptor(
        SensorModel::MicPair(MicPairModel {
            mics: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
            speed_of_sound: 340.0,
            noise_std: 6.25e-5,
        }),
        0.7,
        1.0,
    ))
    .unwrap();
    assert_eq!(model.dim(), 1);
    // Beyond m2: tau = (‖x−m2‖ − ‖x−m1‖)/c = (2 − 3)/340 < 0.
    let tau = model.measure(&Vector3::new(3.0, 0.0, 0.0))[0];
    assert!(close(tau, -1.0 / 340.0, 1e-15), "tau {tau}");
    // Beyond m1: (4 − 3)/340 > 0.
    let tau = model.measure(&Vector3::new(-3.0, 0.0, 0.0))[0];
    assert!(close(tau, 1.0 / 340.0, 1e-15), "tau {tau}");
    // Equidistant: zero.
    assert!(close(
        model.measure(&Vector3::new(0.5, 2.0, 1.0))[0],
        0.0,
        1e-15
    ));
    assert_eq!(
        model.detection_probability(&Vector3::new(0.5, 2.0, 1.0)),
        0.7
    );
    assert!(close(model.noise_cov()[(0, 0)], 6.25e-5 * 6.25e-5, 1e-20));
    // Clutter spreads over [−d/c, d/c].
    assert!(close(model.clutter_density(), 340.0 / 2.0, 1e-9));
}

#[test]
fn mic_pair_speed_of_sound_defaults_to_343_in_json() {
    let json = r#"{"version": 1, "site": "default", "sensor": "mics1",
        "model": {"kind": "mic_pair", "mics": [[0,0,0],[1,0,0]], "noise_std": 1e-4},
        "detection_probability": 0.7, "clutter_rate": 1.0}"#;
    let descriptor: SensorDescriptor = serde_json::from_str(json).unwrap();
    let model = measurement_model(&descriptor).unwrap();
    let tau = model.measure(&Vector3::new(3.0, 0.0, 0.0))[0];
    assert!(close(tau, -1.0 / 343.0, 1e-15), "tau {tau}");
}

#[test]
fn lidar_measures_in_its_own_frame() {
    let lidar = |orientation| {
        SensorModel::Lidar(LidarModel {
            position: [1.0, 2.0, 3.0],
            orientation,
            noise_std: [0.05, 0.01, 0.01],
            max_range: 20.0,
            elevation_limits: [-FRAC_PI_4, FRAC_PI_4],
        })
    };
    let level = measurement_model(&descriptor(lidar([1.0, 0.0, 0.0, 0.0]), 0.9, 3.0)).unwrap();
    let z = level.measure(&Vector3::new(4.0, 6.0, 3.0));
    assert!(close(z[0], 5.0, 1e-12), "{z}");
    assert!(close(z[1], 4.0_f64.atan2(3.0), 1e-12), "{z}");
    assert!(close(z[2], 0.0, 1e-12), "{z}");
    assert_eq!(
        level.detection_probability(&Vector3::new(4.0, 6.0, 3.0)),
        0.9
    );
    // Out of range, and above the elevation limit: not detectable.
    assert_eq!(
        level.detection_probability(&Vector3::new(40.0, 2.0, 3.0)),
        0.0
    );
    assert_eq!(
        level.detection_probability(&Vector3::new(1.0, 3.0, 13.0)),
        0.0
    );

    // Turned 90° about z: the sensor's +x axis points along world +y.
    let half = FRAC_PI_4;
    let turned = lidar([half.cos(), 0.0, 0.0, half.sin()]);
    let turned = measurement_model(&descriptor(turned, 0.9, 3.0)).unwrap();
    let z = turned.measure(&Vector3::new(1.0, 4.0, 3.0));
    assert!(close(z[0], 2.0, 1e-12) && close(z[1], 0.0, 1e-12), "{z}");
    let z = turned.measure(&Vector3::new(0.0, 2.0, 3.0));
    assert!(close(z[1], FRAC_PI_2, 1e-12), "{z}");
}

#[test]
fn bearing_range_wraps_bearing_residuals() {
    let model = measurement_model(&descriptor(
        SensorModel::BearingRange(BearingRangeModel {
            position: [0.0, 0.0, 0.0],
            noise_std: [0.01, 0.5],
            max_range: 100.0,
        }),
        0.8,
        5.0,
    ))
    .unwrap();
    let z = model.measure(&Vector3::new(0.0, 2.0, 5.0));
    assert!(
        close(z[0], FRAC_PI_2, 1e-12) && close(z[1], 2.0, 1e-12),
        "{z}"
    );
    let r = model.residual(
        &DVector::from_vec(vec![PI - 0.1, 10.0]),
        &DVector::from_vec(vec![-PI + 0.1, 9.0]),
    );
    assert!(close(r[0], -0.2, 1e-12) && close(r[1], 1.0, 1e-12), "{r}");
    assert_eq!(
        model.detection_probability(&Vector3::new(0.0, 200.0, 0.0)),
        0.0
    );
}

#[test]
fn position_sensor_is_linear_inside_its_region() {
    let model = measurement_model(&descriptor(
        SensorModel::Position(PositionModel {
            noise_std: [0.1, 0.2, 0.3],
            region: Region {
                min: [0.0, 0.0, 0.0],
                max: [10.0, 20.0, 5.0],
            },
        }),
        0.99,
        4.0,
    ))
    .unwrap();
    let p = Vector3::new(1.0, 2.0, 3.0);
    assert_eq!(model.measure(&p).as_slice(), &[1.0, 2.0, 3.0]);
    assert_eq!(model.linear_position_dims(), Some(3));
    assert_eq!(model.detection_probability(&p), 0.99);
    assert_eq!(
        model.detection_probability(&Vector3::new(11.0, 2.0, 3.0)),
        0.0
    );
    assert!(close(model.clutter_density(), 1.0 / 1000.0, 1e-15));
}

#[test]
fn bad_descriptors_give_typed_errors_naming_the_sensor() {
    let err = measurement_model(&descriptor(example_camera(), 0.0, 2.0)).unwrap_err();
    assert!(matches!(err, Error::Detection { .. }), "{err:?}");
    assert!(err.to_string().contains("`s1`"), "{err}");

    let err = measurement_model(&descriptor(example_camera(), 0.9, -1.0)).unwrap_err();
    assert!(matches!(err, Error::Detection { .. }), "{err:?}");

    let mut future = descriptor(example_camera(), 0.9, 1.0);
    future.version = 2;
    let err = measurement_model(&future).unwrap_err();
    assert!(
        matches!(err, Error::UnsupportedVersion { version: 2, .. }),
        "{err:?}"
    );

    let singular = SensorModel::Camera(CameraModel {
        projection: [
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ],
        image_size: [640, 480],
        noise_std: [3.0, 3.0],
    });
    let err = measurement_model(&descriptor(singular, 0.9, 1.0)).unwrap_err();
    assert!(
        matches!(
            err,
            Error::Model {
                kind: SensorKind::Camera,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("camera"), "{err}");

    let deaf = SensorModel::MicPair(MicPairModel {
        mics: [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]],
        speed_of_sound: 343.0,
        noise_std: 1e-4,
    });
    let err = measurement_model(&descriptor(deaf, 0.9, 1.0)).unwrap_err();
    assert!(
        matches!(
            err,
            Error::Model {
                kind: SensorKind::MicPair,
                ..
            }
        ),
        "{err:?}"
    );

    let tilted = SensorModel::Lidar(LidarModel {
        position: [0.0; 3],
        orientation: [1.0, 0.1, 0.0, 0.0],
        noise_std: [0.05, 0.01, 0.01],
        max_range: 20.0,
        elevation_limits: [-0.5, 0.5],
    });
    let err = measurement_model(&descriptor(tilted, 0.9, 1.0)).unwrap_err();
    assert!(
        matches!(
            err,
            Error::Model {
                kind: SensorKind::Lidar,
                ..
            }
        ),
        "{err:?}"
    );
}
