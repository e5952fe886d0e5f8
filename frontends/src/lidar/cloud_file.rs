//! Reading a point-cloud file of either supported format, chosen by its extension.

use super::error::{CloudFileError, CloudFileProblem};
use super::kitti::read_kitti_bin;
use super::pcd::read_pcd;
use super::point_cloud::PointCloud;
use std::path::Path;

/// Reads a `.pcd` file (ASCII or binary PCD) or a `.bin` file (KITTI velodyne scan); the extension is matched
/// case-insensitively.
///
/// # Errors
/// [`CloudFileError`] naming the file: an unknown extension, or whatever the format's reader reports.
pub fn read_point_cloud(path: impl AsRef<Path>) -> Result<PointCloud, CloudFileError> {
    let path = path.as_ref();
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match extension.as_str() {
        "pcd" => read_pcd(path),
        "bin" => read_kitti_bin(path),
        _ => Err(CloudFileError::new(
            path,
            CloudFileProblem::UnknownExtension { extension },
        )),
    }
}
