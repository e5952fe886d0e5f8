//! Point-cloud file readers: exact round trips through PCD (ASCII and binary) and KITTI `.bin` files, PCL-style
//! files with extra fields, and clear errors for malformed files.

use frontends::lidar::{
    decode_pcd, read_kitti_bin, read_pcd, read_point_cloud, write_kitti_bin, write_pcd,
    PcdEncoding, PointCloud,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};

/// A seeded cloud with awkward values: negatives, tiny and huge magnitudes, signed zero.
fn sample_cloud(with_intensity: bool) -> PointCloud {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut points: Vec<[f32; 3]> = (0..500)
        .map(|_| {
            [
                rng.gen_range(-80.0..80.0),
                rng.gen_range(-80.0..80.0),
                rng.gen_range(-3.0..3.0),
            ]
        })
        .collect();
    points.extend([
        [0.1, -0.0, 1.0e-30],
        [f32::MAX, f32::MIN, f32::MIN_POSITIVE],
        [1.0 / 3.0, 2.0 / 3.0, -123_456.79],
    ]);
    let intensity =
        with_intensity.then(|| (0..points.len()).map(|_| rng.gen_range(0.0..1.0)).collect());
    PointCloud { points, intensity }
}

/// Bit patterns of a cloud, so that the comparison is exact (and would treat NaNs alike).
fn bits(cloud: &PointCloud) -> (Vec<[u32; 3]>, Option<Vec<u32>>) {
    let points = cloud
        .points
        .iter()
        .map(|p| [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()])
        .collect();
    let intensity = cloud
        .intensity
        .as_ref()
        .map(|values| values.iter().map(|v| v.to_bits()).collect());
    (points, intensity)
}

fn temp_file(dir: &tempfile::TempDir, name: &str, contents: &[u8]) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

/// Asserts that reading `path` fails with a message naming the file and containing `problem`.
fn assert_read_error(
    result: Result<PointCloud, frontends::lidar::CloudFileError>,
    path: &Path,
    problem: &str,
) {
    let message = result.expect_err("malformed file was accepted").to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(
        message.contains(name.as_ref()),
        "error does not name the file: {message}"
    );
    assert!(
        message.contains(problem),
        "error '{message}' does not say '{problem}'"
    );
}

#[test]
fn pcd_ascii_and_binary_round_trip_exactly() {
    let dir = tempfile::tempdir().unwrap();
    for with_intensity in [true, false] {
        let cloud = sample_cloud(with_intensity);
        for (encoding, name) in [
            (PcdEncoding::Ascii, "ascii.pcd"),
            (PcdEncoding::Binary, "binary.pcd"),
        ] {
            let path = dir.path().join(name);
            write_pcd(&path, &cloud, encoding).unwrap();
            let read = read_pcd(&path).unwrap();
            assert_eq!(
                bits(&read),
                bits(&cloud),
                "{name}, intensity {with_intensity}"
            );
        }
    }
}

#[test]
fn kitti_bin_round_trips_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = sample_cloud(true);
    let path = dir.path().join("000000.bin");
    write_kitti_bin(&path, &cloud).unwrap();
    assert_eq!(
        std::fs::metadata(&path).unwrap().len(),
        16 * cloud.len() as u64
    );
    assert_eq!(bits(&read_kitti_bin(&path).unwrap()), bits(&cloud));
}

#[test]
fn read_point_cloud_picks_the_format_by_extension() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = sample_cloud(true);
    let kitti = dir.path().join("scan.BIN");
    write_kitti_bin(&kitti, &cloud).unwrap();
    let pcd = dir.path().join("scan.pcd");
    write_pcd(&pcd, &cloud, PcdEncoding::Binary).unwrap();
    assert_eq!(bits(&read_point_cloud(&kitti).unwrap()), bits(&cloud));
    assert_eq!(bits(&read_point_cloud(&pcd).unwrap()), bits(&cloud));
    let ply = temp_file(&dir, "scan.ply", b"ply\n");
    assert_read_error(
        read_point_cloud(&ply),
        &ply,
        "unknown point-cloud extension 'ply'",
    );
}

#[test]
fn pcl_style_ascii_pcd_with_extra_fields_is_read() {
    let text = "# .PCD v0.7 - Point Cloud Data file format\n\
                VERSION .7\n\
                FIELDS x y z intensity ring normal\n\
                SIZE 4 4 8 4 2 4\n\
                TYPE F F F F U F\n\
                COUNT 1 1 1 1 1 3\n\
                WIDTH 2\n\
                HEIGHT 1\n\
                VIEWPOINT 0 0 0 1 0 0 0\n\
                POINTS 2\n\
                DATA ascii\n\
                1.5 -2 0.25 17 5 0 0 1\n\
                \n\
                nan nan nan 0 6 0 0 1\r\n";
    let cloud = decode_pcd(text.as_bytes()).unwrap();
    assert_eq!(cloud.points[0], [1.5, -2.0, 0.25]);
    assert!(cloud.points[1].iter().all(|v| v.is_nan()));
    assert_eq!(cloud.intensity, Some(vec![17.0, 0.0]));
}

#[test]
fn binary_pcd_with_padding_and_integer_fields_is_read() {
    // Record: x (F4), pad (1 byte), y (F8), z (I2), i (U1): 16 bytes, no intensity alias clash.
    let mut bytes =
        b"VERSION 0.7\nFIELDS x _ y z i\nSIZE 4 1 8 2 1\nTYPE F U F I U\nCOUNT 1 1 1 1 1\n\
                      WIDTH 1\nHEIGHT 2\nPOINTS 2\nDATA binary\n"
            .to_vec();
    for (x, y, z, i) in [(1.25f32, -3.5f64, -7i16, 200u8), (-0.5, 1.0e3, 32_000, 0)] {
        bytes.extend_from_slice(&x.to_le_bytes());
        bytes.push(0xAB);
        bytes.extend_from_slice(&y.to_le_bytes());
        bytes.extend_from_slice(&z.to_le_bytes());
        bytes.push(i);
    }
    let cloud = decode_pcd(&bytes).unwrap();
    assert_eq!(
        cloud.points,
        vec![[1.25, -3.5, -7.0], [-0.5, 1000.0, 32_000.0]]
    );
    assert_eq!(cloud.intensity, Some(vec![200.0, 0.0]));
}

#[test]
fn malformed_kitti_files_name_the_file_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let path = temp_file(&dir, "scan.bin", &[0u8; 1001]);
    assert_read_error(
        read_kitti_bin(&path),
        &path,
        "length 1001 bytes is not a multiple of 16",
    );
    let missing = dir.path().join("absent.bin");
    assert_read_error(read_kitti_bin(&missing), &missing, "No such file");
}

/// A valid ASCII header for three points, with `TYPE` on line 3 and `DATA` on line 9.
const HEADER: &str =
    "VERSION 0.7\nFIELDS x y z\nTYPE F F F\nSIZE 4 4 4\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n\
                      POINTS 3\nDATA ascii\n";

#[test]
fn malformed_pcd_headers_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let body = "1 2 3\n4 5 6\n7 8 9\n";
    let cases: [(String, &str); 11] = [
        (
            HEADER.replace("TYPE F F F", "TYPE F F Q") + body,
            "header line 3: unknown field type 'Q'",
        ),
        (
            HEADER.replace("SIZE 4 4 4", "SIZE 4 4") + body,
            "header line 4: SIZE has 2 values, expected 3",
        ),
        (
            HEADER.replace("SIZE 4 4 4", "SIZE 4 4 2") + body,
            "header line 4: field 'z' of type F cannot have size 2",
        ),
        (
            HEADER.replace("FIELDS x y z", "FIELDS x y w") + body,
            "no 'z' field",
        ),
        (
            HEADER.replace("POINTS 3", "POINTS 4") + body,
            "header line 8: POINTS 4 differs from WIDTH 3 × HEIGHT 1",
        ),
        (
            HEADER.replace("WIDTH 3", "WIDTH three") + body,
            "header line 6: WIDTH value 'three' is not a non-negative integer",
        ),
        (
            HEADER.replace("COUNT 1 1 1", "COUNT 1 1 2") + body,
            "header line 5: field 'z' has COUNT 2, expected 1",
        ),
        (
            HEADER.replace("HEIGHT 1", "HEIGHT 1\nHEIGHT 1") + body,
            "header line 8: HEIGHT appears a second time",
        ),
        (
            HEADER.replace("DATA ascii", "DATA binary_compressed") + body,
            "DATA encoding 'binary_compressed' is not supported",
        ),
        (
            HEADER.replace("VERSION 0.7", "PLY"),
            "header line 1: unknown keyword 'PLY'",
        ),
        (HEADER[..40].to_owned(), "without a DATA line"),
    ];
    for (index, (contents, problem)) in cases.iter().enumerate() {
        let path = temp_file(&dir, &format!("cloud{index}.pcd"), contents.as_bytes());
        assert_read_error(read_pcd(&path), &path, problem);
    }
}

#[test]
fn malformed_pcd_data_names_the_file_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            format!("{HEADER}1 2 3\n4 5 6\n"),
            "ascii data has 2 points but POINTS says 3",
        ),
        (
            format!("{HEADER}1 2 3\n4 5 6\n7 8 9\n1 1 1\n"),
            "ascii data has 4 points but POINTS says 3",
        ),
        (
            format!("{HEADER}1 2 3\n4 abc 6\n7 8 9\n"),
            "data line 11: field 'y' value 'abc' is not a number of type F32",
        ),
        (
            format!("{HEADER}1 2 3\n4 5\n7 8 9\n"),
            "data line 11: 2 values, expected 3",
        ),
    ];
    for (index, (contents, problem)) in cases.iter().enumerate() {
        let path = temp_file(&dir, &format!("data{index}.pcd"), contents.as_bytes());
        assert_read_error(read_pcd(&path), &path, problem);
    }
    let integer = HEADER
        .replace("TYPE F F F", "TYPE F F I")
        .replace("SIZE 4 4 4", "SIZE 4 4 1");
    let path = temp_file(
        &dir,
        "int.pcd",
        format!("{integer}1 2 3\n4 5 300\n7 8 9\n").as_bytes(),
    );
    assert_read_error(
        read_pcd(&path),
        &path,
        "field 'z' value '300' is not a number of type I8",
    );
}

#[test]
fn every_truncation_of_a_binary_file_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = PointCloud {
        points: vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
        intensity: Some(vec![0.5, 0.25]),
    };
    let pcd_path = dir.path().join("full.pcd");
    write_pcd(&pcd_path, &cloud, PcdEncoding::Binary).unwrap();
    let pcd_bytes = std::fs::read(&pcd_path).unwrap();
    for cut in 0..pcd_bytes.len() {
        assert!(
            decode_pcd(&pcd_bytes[..cut]).is_err(),
            "PCD cut at byte {cut} was accepted"
        );
    }
    let path = temp_file(&dir, "short.pcd", &pcd_bytes[..pcd_bytes.len() - 5]);
    assert_read_error(
        read_pcd(&path),
        &path,
        "binary data is 27 bytes but POINTS 2 × 16 bytes per point needs 32",
    );
    let path = temp_file(
        &dir,
        "long.pcd",
        &[pcd_bytes.as_slice(), &[0u8; 3]].concat(),
    );
    assert_read_error(read_pcd(&path), &path, "binary data is 35 bytes");
}

#[test]
fn corrupted_files_never_panic() {
    // Seeded byte corruption of valid files: every outcome must be a value (Ok or a typed error), never a panic.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let cloud = sample_cloud(true);
    let originals = [
        frontends::lidar::encode_pcd(&cloud, PcdEncoding::Ascii).unwrap(),
        frontends::lidar::encode_pcd(&cloud, PcdEncoding::Binary).unwrap(),
    ];
    let mut rejected = 0;
    for round in 0..400 {
        let mut bytes = originals[round % 2].clone();
        // Corrupt the header region more often: that is where sizes and counts come from.
        let span = if round % 4 < 2 { 200 } else { bytes.len() };
        for _ in 0..rng.gen_range(1..4) {
            let at = rng.gen_range(0..span);
            bytes[at] = rng.gen();
        }
        if decode_pcd(&bytes).is_err() {
            rejected += 1;
        }
    }
    println!("corrupted PCD files rejected: {rejected} of 400");
    assert!(
        rejected > 100,
        "only {rejected} of 400 corrupted files were rejected"
    );
}
