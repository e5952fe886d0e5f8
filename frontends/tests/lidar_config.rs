//! LIDAR pipeline configuration: documented defaults, every ground method from TOML, and rejected mistakes.

use frontends::lidar::{
    ClusteringConfig, Estimate, GroundRemoval, HeightThreshold, LidarConfig, LidarConfigError,
    LidarPipeline, ObjectConfig, RansacPlaneParams, SegmentationMethod,
};

fn parse(text: &str) -> Result<LidarConfig, toml::de::Error> {
    toml::from_str(text)
}

#[test]
fn an_empty_table_gives_the_documented_defaults() {
    let config = parse("").unwrap();
    assert_eq!(config, LidarConfig::default());
    assert_eq!(
        config.ground,
        GroundRemoval::Ransac(RansacPlaneParams {
            iterations: 400,
            distance_threshold: 0.15,
            max_tilt_deg: 15.0,
            min_inliers: 100,
            seed: 0,
        })
    );
    assert_eq!(
        config.clustering,
        ClusteringConfig {
            tolerance: 0.5,
            min_points: 10,
            max_points: 20_000,
        }
    );
    assert!(LidarPipeline::new(config).is_ok());
}

#[test]
fn each_ground_method_is_read_with_partial_overrides() {
    let ransac = parse("[ground]\nmethod = \"ransac\"\niterations = 250\nseed = 9\n").unwrap();
    assert_eq!(
        ransac.ground,
        GroundRemoval::Ransac(RansacPlaneParams {
            iterations: 250,
            seed: 9,
            ..RansacPlaneParams::default()
        })
    );
    let height = parse("[ground]\nmethod = \"height\"\nmax_ground_z = -1.65\n").unwrap();
    assert_eq!(
        height.ground,
        GroundRemoval::Height(HeightThreshold {
            max_ground_z: -1.65
        })
    );
    let default_height = parse("[ground]\nmethod = \"height\"\n").unwrap();
    assert_eq!(
        default_height.ground,
        GroundRemoval::Height(HeightThreshold { max_ground_z: -1.5 })
    );
    let none = parse("[ground]\nmethod = \"none\"\n[clustering]\ntolerance = 0.3\n").unwrap();
    assert_eq!(none.ground, GroundRemoval::None);
    assert_eq!(none.clustering.tolerance, 0.3);
    assert_eq!(none.clustering.min_points, 10);
}

#[test]
fn misspelt_keys_and_unknown_methods_are_rejected() {
    let typo = parse("[clustering]\ntolerence = 0.4\n")
        .unwrap_err()
        .to_string();
    assert!(typo.contains("tolerence"), "{typo}");
    let method = parse("[ground]\nmethod = \"magic\"\n")
        .unwrap_err()
        .to_string();
    assert!(method.contains("magic"), "{method}");
    let wrong_field = parse("[ground]\nmethod = \"height\"\niterations = 5\n")
        .unwrap_err()
        .to_string();
    assert!(wrong_field.contains("iterations"), "{wrong_field}");
}

#[test]
fn unusable_values_are_rejected_by_the_pipeline() {
    let negative = parse("[clustering]\ntolerance = -1.0\n").unwrap();
    assert_eq!(
        LidarPipeline::new(negative).unwrap_err(),
        LidarConfigError::NotPositive {
            name: "clustering.tolerance",
            value: -1.0
        }
    );
    let inverted = parse("[clustering]\nmin_points = 50\nmax_points = 20\n").unwrap();
    let message = LidarPipeline::new(inverted).unwrap_err().to_string();
    assert_eq!(message, "max_points (20) is below min_points (50)");
    let no_iterations = parse("[ground]\nmethod = \"ransac\"\niterations = 0\n").unwrap();
    assert!(LidarPipeline::new(no_iterations).is_err());
}

#[test]
fn range_image_and_object_tables_are_read() {
    let config = parse(
        "segmentation = \"euclidean\"\n[range_image]\nbeams_deg = [-1.0, 1.0]\nmax_range_jump = 0.4\n\
         [objects]\nestimate = \"centroid\"\nhead_height = 1.7\nmax_top_height = 2.5\n",
    )
    .unwrap();
    assert_eq!(config.segmentation, SegmentationMethod::Euclidean);
    assert_eq!(config.range_image.beams_deg, vec![-1.0, 1.0]);
    assert_eq!(config.range_image.max_range_jump, 0.4);
    assert_eq!(config.range_image.min_points, 4);
    assert_eq!(config.objects.estimate, Estimate::Centroid);
    assert_eq!(config.objects.head_height, Some(1.7));
    assert_eq!(config.objects.max_top_height, 2.5);
    assert_eq!(config.objects.max_width, ObjectConfig::default().max_width);
    let jump = parse("[range_image]\nmax_range_jump = 0.0\n").unwrap();
    assert_eq!(
        LidarPipeline::new(jump).unwrap_err(),
        LidarConfigError::NotPositive {
            name: "range_image.max_range_jump",
            value: 0.0
        }
    );
    let typo = parse("[objects]\nbody_radus = 0.2\n")
        .unwrap_err()
        .to_string();
    assert!(typo.contains("body_radus"), "{typo}");
}
