//! KITTI velodyne scans: a headerless `.bin` of little-endian float32 records `x, y, z, intensity`.

use super::error::{CloudFileError, CloudFileProblem};
use super::point_cloud::PointCloud;
use std::path::Path;

/// Bytes in one KITTI record: four little-endian float32 values.
const RECORD_BYTES: usize = 16;

/// Reads a KITTI velodyne `.bin` scan. The cloud always has an intensity channel.
///
/// # Errors
/// [`CloudFileError`] naming the file when it cannot be read or its length is not a multiple of 16 bytes.
pub fn read_kitti_bin(path: impl AsRef<Path>) -> Result<PointCloud, CloudFileError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| CloudFileError::new(path, e.into()))?;
    decode_kitti_bin(&bytes).map_err(|problem| CloudFileError::new(path, problem))
}

/// Decodes the bytes of a KITTI velodyne scan (see [`read_kitti_bin`]).
///
/// # Errors
/// [`CloudFileProblem::KittiLength`] when the length is not a multiple of 16 bytes.
pub fn decode_kitti_bin(bytes: &[u8]) -> Result<PointCloud, CloudFileProblem> {
    let records = bytes.chunks_exact(RECORD_BYTES);
    if !records.remainder().is_empty() {
        return Err(CloudFileProblem::KittiLength {
            length: bytes.len(),
        });
    }
    let mut points = Vec::with_capacity(records.len());
    let mut intensity = Vec::with_capacity(records.len());
    for record in records {
        let value = |k: usize| {
            let mut word = [0u8; 4];
            word.copy_from_slice(&record[4 * k..4 * k + 4]);
            f32::from_le_bytes(word)
        };
        points.push([value(0), value(1), value(2)]);
        intensity.push(value(3));
    }
    Ok(PointCloud {
        points,
        intensity: Some(intensity),
    })
}

/// Writes a cloud as a KITTI velodyne `.bin` scan. A cloud without intensity is written with intensity 0, since
/// the format has no way to say "absent".
///
/// # Errors
/// [`CloudFileError`] naming the file when it cannot be written or the intensity channel has the wrong length.
pub fn write_kitti_bin(path: impl AsRef<Path>, cloud: &PointCloud) -> Result<(), CloudFileError> {
    let path = path.as_ref();
    let bytes = encode_kitti_bin(cloud).map_err(|problem| CloudFileError::new(path, problem))?;
    std::fs::write(path, bytes).map_err(|e| CloudFileError::new(path, e.into()))
}

/// Encodes a cloud as the bytes of a KITTI velodyne scan (see [`write_kitti_bin`]).
///
/// # Errors
/// [`CloudFileProblem::IntensityLength`] when the intensity channel does not have one value per point.
pub fn encode_kitti_bin(cloud: &PointCloud) -> Result<Vec<u8>, CloudFileProblem> {
    if let Some(values) = &cloud.intensity {
        if values.len() != cloud.points.len() {
            return Err(CloudFileProblem::IntensityLength {
                points: cloud.points.len(),
                intensities: values.len(),
            });
        }
    }
    let mut bytes = Vec::with_capacity(cloud.points.len() * RECORD_BYTES);
    for (index, point) in cloud.points.iter().enumerate() {
        let intensity = cloud.intensity.as_ref().map_or(0.0, |values| values[index]);
        for value in [point[0], point[1], point[2], intensity] {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_then_decode_is_exact() {
        let cloud = PointCloud {
            points: vec![[1.5, -2.25, 0.125], [f32::MAX, f32::MIN_POSITIVE, -0.0]],
            intensity: Some(vec![0.75, 1.0e-7]),
        };
        let bytes = encode_kitti_bin(&cloud).unwrap();
        assert_eq!(bytes.len(), 32);
        assert_eq!(decode_kitti_bin(&bytes).unwrap(), cloud);
    }

    #[test]
    fn missing_intensity_is_written_as_zero() {
        let cloud = PointCloud::from_points(vec![[1.0, 2.0, 3.0]]);
        let decoded = decode_kitti_bin(&encode_kitti_bin(&cloud).unwrap()).unwrap();
        assert_eq!(decoded.points, cloud.points);
        assert_eq!(decoded.intensity, Some(vec![0.0]));
    }

    #[test]
    fn ragged_length_is_rejected() {
        let problem = decode_kitti_bin(&[0u8; 17]).unwrap_err();
        assert!(matches!(
            problem,
            CloudFileProblem::KittiLength { length: 17 }
        ));
    }
}
