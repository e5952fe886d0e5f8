//! The camera pipeline: RGB frame -> rgI -> background subtraction -> shadow suppression -> mask
//! clean-up -> bodies -> their head points.

use image::{GrayImage, RgbImage};

use super::background::{new_background_model, BackgroundModel};
use super::blobs::{Blob, BlobDetector};
use super::chromaticity::RgiImage;
use super::config::CameraConfig;
use super::detections::FrameDetections;
use super::error::{CameraError, CameraResult};
use super::frames::FrameDirectory;
use super::shadows::suppress_shadows;

/// Turns a sequence of frames of one fixed-size camera into point measurements. The background model
/// is built on the first frame, whose size every later frame must have.
pub struct CameraPipeline {
    config: CameraConfig,
    background: Option<Box<dyn BackgroundModel>>,
    detector: BlobDetector,
    rgi: RgiImage,
    mask: GrayImage,
    /// The shadow pixels of the last frame: not objects, yet not learned as background either.
    shadows: GrayImage,
    blobs: Vec<Blob>,
}

impl CameraPipeline {
    /// A pipeline with the given configuration, refused if `config.validate()` fails.
    pub fn new(config: CameraConfig) -> CameraResult<Self> {
        config.validate()?;
        let detector = BlobDetector::new(config.blobs.clone());
        Ok(Self {
            config,
            background: None,
            detector,
            rgi: RgiImage::default(),
            mask: GrayImage::new(0, 0),
            shadows: GrayImage::new(0, 0),
            blobs: Vec::new(),
        })
    }

    /// Its configuration.
    pub fn config(&self) -> &CameraConfig {
        &self.config
    }

    /// True until the background model has learned its first frames (and before the first frame).
    pub fn is_learning(&self) -> bool {
        self.background.as_ref().is_none_or(|b| b.is_learning())
    }

    /// The cleaned foreground mask of the last processed frame (255 = foreground); empty before
    /// the first detection.
    pub fn foreground_mask(&self) -> &GrayImage {
        &self.mask
    }

    /// The blobs found in the last processed frame.
    pub fn blobs(&self) -> &[Blob] {
        &self.blobs
    }

    /// Processes one frame. Returns `None` while the background is still being learned (those frames
    /// carry no measurements, which is not the same as "nothing seen"), then one point per blob.
    /// `frame_name` only labels errors (a file name, say).
    pub fn process_frame(
        &mut self,
        image: &RgbImage,
        frame_index: usize,
        stamp: f64,
        frame_name: &str,
    ) -> CameraResult<Option<FrameDetections>> {
        let (width, height) = image.dimensions();
        if width == 0 || height == 0 {
            return Err(CameraError::EmptyFrame {
                frame: frame_name.to_string(),
                width,
                height,
            });
        }
        if self.background.is_none() {
            self.background = Some(new_background_model(&self.config.background, width, height));
            self.mask = GrayImage::new(width, height);
            self.shadows = GrayImage::new(width, height);
        }
        if self.mask.dimensions() != (width, height) {
            return Err(CameraError::FrameSizeMismatch {
                frame: frame_name.to_string(),
                expected_width: self.mask.width(),
                expected_height: self.mask.height(),
                found_width: width,
                found_height: height,
            });
        }
        self.rgi.fill_from(image);
        let background = self
            .background
            .as_mut()
            .expect("the background model was built above");
        if background.is_learning() {
            background.update(&self.rgi, &self.mask);
            self.blobs.clear();
            return Ok(None);
        }
        background.classify(&self.rgi, &mut self.mask);
        suppress_shadows(
            &self.config.shadows,
            background.as_ref(),
            &self.rgi,
            &mut self.mask,
            &mut self.shadows,
        );
        self.blobs = self.detector.detect(&mut self.mask);
        // A shadow is not learned as background either: where it falls is not what the empty
        // scene shows. The shadow buffer becomes the mask of what is not learned.
        for (s, &m) in self.shadows.iter_mut().zip(self.mask.iter()) {
            *s = (*s).max(m);
        }
        background.update(&self.rgi, &self.shadows);
        Ok(Some(FrameDetections {
            frame_index,
            stamp,
            points: self
                .blobs
                .iter()
                .flat_map(|blob| blob.points.iter().copied())
                .collect(),
        }))
    }

    /// Processes every frame of a directory in order and returns the detections of the frames after
    /// the learning phase (the first frames, which only train the background, yield none).
    pub fn process_directory(
        &mut self,
        frames: &FrameDirectory,
    ) -> CameraResult<Vec<FrameDetections>> {
        let mut out = Vec::with_capacity(frames.len());
        for frame in frames.iter() {
            let frame = frame?;
            let name = frame.path.display().to_string();
            if let Some(detections) =
                self.process_frame(&frame.image, frame.index, frame.stamp, &name)?
            {
                out.push(detections);
            }
        }
        Ok(out)
    }
}
