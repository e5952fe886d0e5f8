//! Configuration of the camera front end, with documented defaults.
//!
//! Every field has a default, so a configuration file only needs the values it changes, e.g. in TOML:
//!
//! ```toml
//! front_end = "multi_bernoulli"   # or "blobs"
//! [background]
//! model = "kde"            # or "running_stats"
//! kde = { samples = 20, bandwidth_i = 10.0 }
//! [blobs]
//! min_area = 400
//! anchor = "top_centre"    # or "centroid", "bottom_centre"
//! [mot_det]
//! min_score = 0.3
//! [multi_bernoulli]
//! downscale = 2
//! person = { max_height = 2.1 }
//! ```

use serde::Deserialize;

use super::detections::PointAnchor;
use super::error::{CameraError, CameraResult};
use super::multi_bernoulli::MultiBernoulliConfig;

/// How frames become a camera's published points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrontEndKind {
    /// The multi-Bernoulli filter on the background-subtracted image (`multi_bernoulli`): people
    /// tracked on the image itself, their head tops published with covariances. The default.
    #[default]
    MultiBernoulli,
    /// Background subtraction, blobs joined into bodies and one head point per peak of a body's
    /// top outline (`CameraPipeline`), then a point tracker.
    Blobs,
}

/// Everything the camera front end needs to know.
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraConfig {
    /// Which front end turns frames into points; default `multi_bernoulli`.
    pub front_end: FrontEndKind,
    /// The multi-Bernoulli image tracker (front end `multi_bernoulli`).
    pub multi_bernoulli: MultiBernoulliConfig,
    /// Background subtraction.
    pub background: BackgroundConfig,
    /// Mask clean-up and blob extraction.
    pub blobs: BlobConfig,
    /// Reading precomputed MOT Challenge detections instead of subtracting a background.
    pub mot_det: MotDetConfig,
    /// Telling shadows from objects.
    pub shadows: ShadowConfig,
}

/// Shadow suppression: a foreground pixel of the background's chromaticity at a share of its
/// brightness is a shadow.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShadowConfig {
    /// Whether shadows are suppressed; default false: on the simulator's rendered room it also took
    /// hair and trousers of the floor's colour for shadow, splitting bodies into pieces that gave
    /// false heads (0.32 against 0.13 per frame on `cam1`), while the top outline already keeps
    /// two people joined by a shadow apart.
    pub enabled: bool,
    /// Largest difference in chromaticity r and in g from the background, in r units (0..1), of a
    /// shadow pixel; default 0.03.
    pub max_chromaticity_difference: f32,
    /// Smallest share of the background's brightness a shadow leaves; default 0.4.
    pub min_brightness_ratio: f32,
    /// Largest share of the background's brightness a shadow leaves (above it the pixel is either
    /// background or an object of the background's colour); default 0.95.
    pub max_brightness_ratio: f32,
}

impl Default for ShadowConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            max_chromaticity_difference: 0.03,
            min_brightness_ratio: 0.4,
            max_brightness_ratio: 0.95,
        }
    }
}

/// Which per-pixel background model to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BackgroundModelKind {
    /// Kernel density over the last N background samples (Hoseinnezhad, Vo, Vu, eq. 10). The default:
    /// it is the model of the paper, it represents backgrounds that take several values (flicker, swaying
    /// leaves, a monitor) which a single Gaussian cannot, and at N = 16 samples with table look-up kernels
    /// and early exit it costs a few milliseconds per 320x240 frame.
    #[default]
    Kde,
    /// One running Gaussian (mean and variance) per pixel and rgI component: constant cost and memory
    /// per pixel whatever the history length, for large frames or slow hardware; unimodal backgrounds only.
    RunningStats,
}

/// Background subtraction settings.
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BackgroundConfig {
    /// The model used; default `kde`.
    pub model: BackgroundModelKind,
    /// Settings of the kernel-density model.
    pub kde: KdeConfig,
    /// Settings of the running-statistics model.
    pub running_stats: RunningStatsConfig,
}

/// Kernel-density background model settings.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct KdeConfig {
    /// N, the number of background samples kept per pixel (1..=255); default 16. The first N frames
    /// are all learned as background, so the scene should be empty of movers then (a mover present
    /// then leaves a "ghost" where it stood, foreground until those samples are replaced, which the
    /// selective update never does while the ghost is foreground). Memory: 3 N bytes per pixel.
    pub samples: usize,
    /// K0, the number of frames between two selective updates once learned (>= 1); default 5. With N
    /// samples, the model remembers about N * K0 frames of background.
    pub update_interval: u32,
    /// Gaussian kernel bandwidth for chromaticity r (in r units, 0..1); default 0.03.
    pub bandwidth_r: f32,
    /// Gaussian kernel bandwidth for chromaticity g; default 0.03.
    pub bandwidth_g: f32,
    /// Gaussian kernel bandwidth for intensity I, in grey levels; default 8.
    pub bandwidth_i: f32,
    /// A pixel is foreground when its normalised background likelihood `y` (eq. 10, in [0, 1]) is below
    /// this; default 0.05.
    pub threshold: f32,
}

impl Default for KdeConfig {
    fn default() -> Self {
        Self {
            samples: 16,
            update_interval: 5,
            bandwidth_r: 0.03,
            bandwidth_g: 0.03,
            bandwidth_i: 8.0,
            threshold: 0.05,
        }
    }
}

/// Running-statistics background model settings.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RunningStatsConfig {
    /// Frames averaged (all pixels) before detection starts (>= 1); default 16.
    pub learning_frames: u32,
    /// Weight of a new background observation in the running mean and variance (0 < a <= 1);
    /// default 0.02 (a memory of about 50 frames).
    pub learning_rate: f32,
    /// A pixel is foreground when its squared Mahalanobis distance over r, g, I exceeds the square of
    /// this; default 4.
    pub threshold_sigmas: f32,
    /// Floor on the standard deviation of r, so a noise-free learning phase does not make every change
    /// foreground; default 0.01.
    pub min_std_r: f32,
    /// Floor on the standard deviation of g; default 0.01.
    pub min_std_g: f32,
    /// Floor on the standard deviation of I, in grey levels; default 3.
    pub min_std_i: f32,
}

impl Default for RunningStatsConfig {
    fn default() -> Self {
        Self {
            learning_frames: 16,
            learning_rate: 0.02,
            threshold_sigmas: 4.0,
            min_std_r: 0.01,
            min_std_g: 0.01,
            min_std_i: 3.0,
        }
    }
}

/// Mask clean-up and blob extraction settings.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BlobConfig {
    /// Radius k of the square structuring element ((2k+1) x (2k+1)) of the opening (removes specks)
    /// and closing (fills holes) applied to the foreground mask; 0 disables both; default 1 (3x3).
    pub cleanup_radius: u8,
    /// Blobs with fewer pixels are dropped as noise; default 200 (a person is thousands of pixels at
    /// 320x240).
    pub min_area: u32,
    /// Which point of a blob is its measurement; default top-centre (the head).
    pub anchor: PointAnchor,
    /// The x of a head is the centre of the columns around its peak whose top lies within this many
    /// rows of the peak's (that of a bottom-centre point the mean column of the pixels this close to
    /// the bottom edge), which is steadier than the single extreme row; >= 1, default 4.
    pub anchor_band_rows: u32,
    /// Connected regions with fewer pixels are specks, not pieces of a body; default 40.
    pub min_piece_area: u32,
    /// Pieces sharing at least half the narrower one's columns are one body when at most this many
    /// rows apart (a person split where the clothes match the background); default 30.
    pub join_gap_rows: u32,
    /// Pieces sharing at least half the shorter one's rows are one body when at most this many
    /// columns apart; default 3.
    pub join_gap_cols: u32,
    /// A peak of a body's top outline is a head when it rises at least this many rows above the
    /// lowest point between it and any higher peak (or above the body's bottom); >= 1, default 12.
    pub head_prominence_rows: u32,
}

impl Default for BlobConfig {
    fn default() -> Self {
        Self {
            cleanup_radius: 1,
            min_area: 200,
            anchor: PointAnchor::TopCentre,
            anchor_band_rows: 4,
            min_piece_area: 40,
            join_gap_rows: 30,
            join_gap_cols: 3,
            head_prominence_rows: 12,
        }
    }
}

/// Settings for reading MOT Challenge `det.txt` files.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotDetConfig {
    /// Detections scoring below this are dropped; default 0.5. Detectors differ in score range (the
    /// DPM detections of MOT16/17 have negative scores), so set it per detector.
    pub min_score: f64,
    /// Which point of a box is the measurement; default top-centre.
    pub anchor: PointAnchor,
}

impl Default for MotDetConfig {
    fn default() -> Self {
        Self {
            min_score: 0.5,
            anchor: PointAnchor::TopCentre,
        }
    }
}

/// A configuration error naming the field (shared with the image tracker's configuration).
pub(super) fn invalid(field: &'static str, problem: String) -> CameraError {
    CameraError::InvalidConfig { field, problem }
}

/// Refuses a value that is not finite and > 0.
pub(super) fn require_positive(field: &'static str, value: impl Into<f64>) -> CameraResult<()> {
    let value: f64 = value.into();
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be finite and > 0, got {value}"),
        ))
    }
}

impl CameraConfig {
    /// Checks every value's range; the pipeline refuses a configuration that fails this.
    pub fn validate(&self) -> CameraResult<()> {
        let kde = &self.background.kde;
        if !(1..=255).contains(&kde.samples) {
            return Err(invalid(
                "background.kde.samples",
                format!("must be in 1..=255, got {}", kde.samples),
            ));
        }
        if kde.update_interval == 0 {
            return Err(invalid(
                "background.kde.update_interval",
                "must be >= 1".into(),
            ));
        }
        require_positive("background.kde.bandwidth_r", kde.bandwidth_r)?;
        require_positive("background.kde.bandwidth_g", kde.bandwidth_g)?;
        require_positive("background.kde.bandwidth_i", kde.bandwidth_i)?;
        if !(kde.threshold > 0.0 && kde.threshold < 1.0) {
            return Err(invalid(
                "background.kde.threshold",
                format!("must be in (0, 1), got {}", kde.threshold),
            ));
        }
        let running = &self.background.running_stats;
        if running.learning_frames == 0 {
            return Err(invalid(
                "background.running_stats.learning_frames",
                "must be >= 1".into(),
            ));
        }
        if !(running.learning_rate > 0.0 && running.learning_rate <= 1.0) {
            return Err(invalid(
                "background.running_stats.learning_rate",
                format!("must be in (0, 1], got {}", running.learning_rate),
            ));
        }
        require_positive(
            "background.running_stats.threshold_sigmas",
            running.threshold_sigmas,
        )?;
        require_positive("background.running_stats.min_std_r", running.min_std_r)?;
        require_positive("background.running_stats.min_std_g", running.min_std_g)?;
        require_positive("background.running_stats.min_std_i", running.min_std_i)?;
        if self.blobs.anchor_band_rows == 0 {
            return Err(invalid("blobs.anchor_band_rows", "must be >= 1".into()));
        }
        if self.blobs.head_prominence_rows == 0 {
            return Err(invalid("blobs.head_prominence_rows", "must be >= 1".into()));
        }
        if self.blobs.min_area == 0 {
            return Err(invalid("blobs.min_area", "must be >= 1".into()));
        }
        let shadows = &self.shadows;
        require_positive(
            "shadows.max_chromaticity_difference",
            shadows.max_chromaticity_difference,
        )?;
        let ratios = (shadows.min_brightness_ratio, shadows.max_brightness_ratio);
        if !(ratios.0 > 0.0 && ratios.0 < ratios.1 && ratios.1 <= 1.0) {
            return Err(invalid(
                "shadows.min_brightness_ratio",
                format!(
                    "need 0 < min_brightness_ratio < max_brightness_ratio <= 1, got {} and {}",
                    ratios.0, ratios.1
                ),
            ));
        }
        self.multi_bernoulli.validate()?;
        if self.mot_det.min_score.is_nan() {
            return Err(invalid("mot_det.min_score", "must be a number".into()));
        }
        Ok(())
    }
}
