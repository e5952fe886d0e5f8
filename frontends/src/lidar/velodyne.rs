//! Velodyne VLP-16 and VLP-32C data packets (the sensors' UDP port 2368 stream) to points, and scans cut at
//! each rotation.
//!
//! A data packet's payload is 1206 bytes: 12 firing blocks of 100 bytes — flag `FF EE`, azimuth (u16, 0.01°),
//! then 32 returns of (distance u16 in 2 mm units, reflectivity u8) — a 4-byte timestamp and two factory bytes
//! (return mode, product id: 0x22 VLP-16, 0x28 VLP-32C). All numbers are little-endian. On a VLP-16 a block
//! holds two firings of the 16 lasers; the second one's azimuth is taken halfway to the next block's. Laser
//! elevations are the manuals' tables; the VLP-32C's small per-laser azimuth offsets are not applied, nor are
//! the firings' microsecond time offsets (a person moves well under a millimetre in that time). A distance of
//! 0 is "no return" and gives no point. In dual-return mode both returns of each firing become points.
//!
//! Points are in the sensor frame of the rest of this module: x towards the Velodyne's azimuth 0, y to its
//! left, z up (the Velodyne's own azimuth turns clockwise seen from above; here azimuth is counter-clockwise,
//! as in `atan2(y, x)`).

use super::point_cloud::PointCloud;

/// Payload bytes of one data packet.
pub const PACKET_LEN: usize = 1206;
/// Firing blocks per packet.
const BLOCKS: usize = 12;
/// Bytes per block.
const BLOCK_LEN: usize = 100;
/// Returns per block.
const CHANNELS: usize = 32;
/// Metres per distance unit.
const DISTANCE_UNIT: f64 = 0.002;

/// VLP-16 laser elevations in degrees, by laser id (the manual's table: alternating below and above).
const VLP16_ELEVATIONS: [f64; 16] = [
    -15.0, 1.0, -13.0, 3.0, -11.0, 5.0, -9.0, 7.0, -7.0, 9.0, -5.0, 11.0, -3.0, 13.0, -1.0, 15.0,
];
/// VLP-32C laser elevations in degrees, by laser id (the manual's table).
const VLP32C_ELEVATIONS: [f64; 32] = [
    -25.0, -1.0, -1.667, -15.639, -11.31, 0.0, -0.667, -8.843, -7.254, 0.333, -0.333, -6.148,
    -5.333, 1.333, 0.667, -4.0, -4.667, 1.667, 1.0, -3.667, -3.333, 3.333, 2.333, -2.667, -3.0,
    7.0, 4.667, -2.333, -2.0, 15.0, 10.333, -1.333,
];

/// The sensor a packet comes from, by its product id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VelodyneModel {
    /// VLP-16 (Puck), product id 0x22.
    Vlp16,
    /// VLP-32C, product id 0x28.
    Vlp32c,
}

impl VelodyneModel {
    /// The elevation table, degrees by laser id.
    pub fn elevations(self) -> &'static [f64] {
        match self {
            VelodyneModel::Vlp16 => &VLP16_ELEVATIONS,
            VelodyneModel::Vlp32c => &VLP32C_ELEVATIONS,
        }
    }

    /// The model of a product id byte.
    fn from_product_id(id: u8) -> Option<Self> {
        match id {
            0x22 => Some(VelodyneModel::Vlp16),
            0x28 => Some(VelodyneModel::Vlp32c),
            _ => None,
        }
    }
}

/// Why a datagram is not a packet this decoder reads.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum VelodyneError {
    /// Not 1206 bytes (a position packet is 512, for instance).
    #[error("{0} bytes, not a 1206-byte data packet")]
    WrongSize(usize),
    /// A block does not start with `FF EE`.
    #[error("block {block} has flag {flag:#06x}, not 0xeeff")]
    BadFlag {
        /// Block index, 0–11.
        block: usize,
        /// The flag read (little-endian).
        flag: u16,
    },
    /// An azimuth of 360° or more.
    #[error("block {block} has azimuth {azimuth} (0.01°), beyond 35999")]
    BadAzimuth {
        /// Block index, 0–11.
        block: usize,
        /// The azimuth read.
        azimuth: u16,
    },
    /// A product id other than VLP-16 (0x22) or VLP-32C (0x28).
    #[error("product id {0:#04x} is neither a VLP-16 (0x22) nor a VLP-32C (0x28)")]
    UnknownProduct(u8),
}

/// One firing block: its azimuth and the points of its returns.
#[derive(Debug, Clone, PartialEq)]
pub struct FiringBlock {
    /// The block's azimuth in the Velodyne's convention, degrees in [0, 360).
    pub azimuth_deg: f64,
    /// The block's points in the sensor frame (metres).
    pub points: Vec<[f32; 3]>,
}

/// Decodes one data packet's payload into its 12 blocks; never panics on any input.
pub fn decode_velodyne_packet(
    payload: &[u8],
) -> Result<(VelodyneModel, Vec<FiringBlock>), VelodyneError> {
    if payload.len() != PACKET_LEN {
        return Err(VelodyneError::WrongSize(payload.len()));
    }
    let model = VelodyneModel::from_product_id(payload[1205])
        .ok_or(VelodyneError::UnknownProduct(payload[1205]))?;
    let u16_at = |i: usize| u16::from_le_bytes([payload[i], payload[i + 1]]);
    let mut azimuths = [0.0f64; BLOCKS];
    for (block, azimuth_deg) in azimuths.iter_mut().enumerate() {
        let base = block * BLOCK_LEN;
        let flag = u16_at(base);
        if flag != 0xEEFF {
            return Err(VelodyneError::BadFlag { block, flag });
        }
        let azimuth = u16_at(base + 2);
        if azimuth >= 36_000 {
            return Err(VelodyneError::BadAzimuth { block, azimuth });
        }
        *azimuth_deg = f64::from(azimuth) / 100.0;
    }
    let elevations = model.elevations();
    let blocks = (0..BLOCKS)
        .map(|block| {
            // The angle turned per block, for the VLP-16's second firing; the last block uses the one before.
            let step = if block + 1 < BLOCKS {
                (azimuths[block + 1] - azimuths[block]).rem_euclid(360.0)
            } else {
                (azimuths[block] - azimuths[block - 1]).rem_euclid(360.0)
            };
            let base = block * BLOCK_LEN + 4;
            let points = (0..CHANNELS)
                .filter_map(|channel| {
                    let at = base + 3 * channel;
                    let distance = f64::from(u16_at(at)) * DISTANCE_UNIT;
                    let laser = channel % elevations.len();
                    let second_firing = channel >= elevations.len();
                    let azimuth = azimuths[block] + if second_firing { step / 2.0 } else { 0.0 };
                    (distance > 0.0).then(|| to_point(distance, azimuth, elevations[laser]))
                })
                .collect();
            FiringBlock {
                azimuth_deg: azimuths[block],
                points,
            }
        })
        .collect();
    Ok((model, blocks))
}

/// A return at `distance` metres, Velodyne azimuth and elevation in degrees, as a point of the sensor frame.
pub fn to_point(distance: f64, azimuth_deg: f64, elevation_deg: f64) -> [f32; 3] {
    let (azimuth, elevation) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
    let horizontal = distance * elevation.cos();
    [
        (horizontal * azimuth.cos()) as f32,
        (-horizontal * azimuth.sin()) as f32,
        (distance * elevation.sin()) as f32,
    ]
}

/// Gathers firing blocks into one scan per rotation.
///
/// A rotation ends at the first block whose azimuth is below its predecessor's (the wrap through 0°), so a
/// scan is handed out when the block that starts the next one arrives. The first rotation is kept only when
/// its first block lies within [`FIRST_SCAN_START_DEG`] of 0° (the sensor's stream began with it); otherwise
/// it is a partial rotation and is dropped.
#[derive(Debug, Clone, Default)]
pub struct RotationAssembler {
    points: Vec<[f32; 3]>,
    last_azimuth: Option<f64>,
    /// Whether the points gathered so far are a whole rotation's.
    whole: bool,
}

/// How far past 0° the stream's first block may lie for its first rotation to count as whole.
pub const FIRST_SCAN_START_DEG: f64 = 1.0;

impl RotationAssembler {
    /// An assembler waiting for its first block.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one block; returns the finished scan when this block starts a new rotation (`None` for a first,
    /// partial rotation).
    pub fn push(&mut self, block: &FiringBlock) -> Option<PointCloud> {
        let finished = match self.last_azimuth {
            None => {
                self.whole = block.azimuth_deg <= FIRST_SCAN_START_DEG;
                None
            }
            Some(last) if block.azimuth_deg < last => {
                let points = std::mem::take(&mut self.points);
                let whole = std::mem::replace(&mut self.whole, true);
                whole.then(|| PointCloud::from_points(points))
            }
            Some(_) => None,
        };
        self.last_azimuth = Some(block.azimuth_deg);
        self.points.extend_from_slice(&block.points);
        finished
    }

    /// Whether no block has arrived yet since the last scan was handed out.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A VLP-16 packet whose block b has azimuth `first + b * step` (0.01°) and every return at `distance`
    /// units.
    fn packet(first: u16, step: u16, distance: u16) -> Vec<u8> {
        let mut bytes = vec![0u8; PACKET_LEN];
        for block in 0..BLOCKS {
            let base = block * BLOCK_LEN;
            bytes[base..base + 2].copy_from_slice(&[0xFF, 0xEE]);
            let azimuth = (first + block as u16 * step) % 36_000;
            bytes[base + 2..base + 4].copy_from_slice(&azimuth.to_le_bytes());
            for channel in 0..CHANNELS {
                let at = base + 4 + 3 * channel;
                bytes[at..at + 2].copy_from_slice(&distance.to_le_bytes());
                bytes[at + 2] = 100;
            }
        }
        bytes[1204] = 0x37;
        bytes[1205] = 0x22;
        bytes
    }

    #[test]
    fn a_vlp16_packet_gives_32_points_per_block_at_the_table_elevations() {
        let (model, blocks) = decode_velodyne_packet(&packet(9000, 20, 5000)).unwrap();
        assert_eq!(model, VelodyneModel::Vlp16);
        assert_eq!(blocks.len(), 12);
        assert_eq!(blocks[0].points.len(), 32);
        assert!((blocks[1].azimuth_deg - 90.2).abs() < 1e-9);
        // Laser 0 at −15°, azimuth 90° (the Velodyne's right): 10 m away, to the sensor's right and below.
        let [x, y, z] = blocks[0].points[0];
        assert!(x.abs() < 1e-3 && (y + 10.0 * 15f32.to_radians().cos()).abs() < 1e-3);
        assert!((z + 10.0 * 15f32.to_radians().sin()).abs() < 1e-3);
        // The second firing is halfway to the next block.
        let [x2, y2, _] = blocks[0].points[16];
        let azimuth = f64::from(-y2).atan2(f64::from(x2)).to_degrees();
        assert!((azimuth - 90.1).abs() < 1e-3, "{azimuth}");
    }

    #[test]
    fn malformed_packets_are_errors() {
        assert_eq!(
            decode_velodyne_packet(&[0; 512]),
            Err(VelodyneError::WrongSize(512))
        );
        let mut bad = packet(0, 20, 100);
        bad[300] = 0x00;
        assert!(matches!(
            decode_velodyne_packet(&bad),
            Err(VelodyneError::BadFlag { block: 3, .. })
        ));
        let mut bad = packet(0, 20, 100);
        bad[1205] = 0x99;
        assert!(decode_velodyne_packet(&bad).is_err());
        let mut bad = packet(0, 20, 100);
        bad[2..4].copy_from_slice(&40_000u16.to_le_bytes());
        assert!(decode_velodyne_packet(&bad).is_err());
    }

    #[test]
    fn rotations_are_cut_at_the_wrap_and_a_partial_first_one_is_dropped() {
        let mut assembler = RotationAssembler::new();
        let mut scans = Vec::new();
        // Start at 180°: the first rotation is partial.
        for packet_index in 0..180u32 {
            let first = ((18_000 + packet_index * 480) % 36_000) as u16;
            let (_, blocks) = decode_velodyne_packet(&packet(first, 40, 1000)).unwrap();
            for block in &blocks {
                scans.extend(assembler.push(block));
            }
        }
        // 180 packets × 4.8° from 180° reach 1044°: wraps at 360° (the partial first rotation) and 720°.
        assert_eq!(scans.len(), 1);
        assert_eq!(scans[0].len(), 75 * 12 * 32);
    }
}
