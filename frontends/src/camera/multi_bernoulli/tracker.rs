//! Frames in, people out: the frame is binned (`downscale` × `downscale` blocks), converted to rgI, scored against the kernel-density
//! background (the grey image of the paper, sec. 3.1) and handed to the multi-Bernoulli filter.
//!
//! The background learns only where it saw background and no estimated person stands, so a person who
//! stops, or whose clothes happen to match the background in places, is not learned into it.

use image::{GrayImage, RgbImage};

use super::config::MultiBernoulliConfig;
use super::estimate::PersonEstimate;
use super::filter::MultiBernoulliFilter;
use super::foreground::ForegroundMap;
use crate::camera::background::{new_background_model, BackgroundModel, FOREGROUND};
use crate::camera::chromaticity::RgiImage;
use crate::camera::config::BackgroundConfig;
use crate::camera::error::{CameraError, CameraResult};

/// One frame's result.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameEstimates {
    /// The frame's stamp.
    pub stamp: f64,
    /// Every estimated person (existence at least the reporting threshold).
    pub people: Vec<PersonEstimate>,
}

/// The camera's multi-Bernoulli image tracker.
pub struct ImageTracker {
    config: MultiBernoulliConfig,
    background_config: BackgroundConfig,
    background: Option<Box<dyn BackgroundModel>>,
    filter: MultiBernoulliFilter,
    full_size: [u32; 2],
    rgi: RgiImage,
    values: Vec<f32>,
    mask: GrayImage,
    map: ForegroundMap,
}

impl ImageTracker {
    /// A tracker for a camera of `projection` taking frames of `image_size` pixels.
    pub fn new(
        config: MultiBernoulliConfig,
        background_config: BackgroundConfig,
        projection: [[f64; 4]; 3],
        image_size: [u32; 2],
    ) -> CameraResult<Self> {
        let filter = MultiBernoulliFilter::new(config.clone(), projection, image_size)?;
        if image_size.iter().any(|&side| side < config.downscale) {
            return Err(CameraError::InvalidConfig {
                field: "multi_bernoulli.downscale",
                problem: format!(
                    "the {}x{} px image is smaller than one {}-pixel block",
                    image_size[0], image_size[1], config.downscale
                ),
            });
        }
        Ok(Self {
            config,
            background_config,
            background: None,
            filter,
            full_size: image_size,
            rgi: RgiImage::default(),
            values: Vec::new(),
            mask: GrayImage::new(0, 0),
            map: ForegroundMap::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MultiBernoulliConfig {
        &self.config
    }

    /// The filter.
    pub fn filter(&self) -> &MultiBernoulliFilter {
        &self.filter
    }

    /// The last frame's foreground map (shrunk image).
    pub fn foreground(&self) -> &ForegroundMap {
        &self.map
    }

    /// Processes one frame; `None` while the background is still learning. Frames must have the size
    /// given at construction. `frame_name` only labels errors.
    pub fn process_frame(
        &mut self,
        image: &RgbImage,
        stamp: f64,
        frame_name: &str,
    ) -> CameraResult<Option<FrameEstimates>> {
        let (width, height) = image.dimensions();
        if [width, height] != self.full_size {
            return Err(CameraError::FrameSizeMismatch {
                frame: frame_name.to_string(),
                expected_width: self.full_size[0],
                expected_height: self.full_size[1],
                found_width: width,
                found_height: height,
            });
        }
        let scale = self.config.downscale;
        let small = [width / scale, height / scale];
        self.rgi.fill_binned(image, scale);
        let background = self.background.get_or_insert_with(|| {
            new_background_model(&self.background_config, small[0], small[1])
        });
        if self.mask.dimensions() != (small[0], small[1]) {
            self.mask = GrayImage::new(small[0], small[1]);
        }
        if background.is_learning() {
            background.update(&self.rgi, &self.mask);
            return Ok(None);
        }
        background.foreground_values(
            &self.rgi,
            self.config.foreground_saturation,
            &mut self.values,
            &mut self.mask,
        );
        let [w, h] = small.map(|v| v as usize);
        self.map
            .fill(w, h, &self.values, self.config.foreground_threshold);
        let people = self.filter.step(stamp, &self.map);
        self.mark_people();
        let background = self.background.as_mut().expect("built above");
        background.update(&self.rgi, &self.mask);
        Ok(Some(FrameEstimates { stamp, people }))
    }

    /// Marks the estimated people's regions in the mask, so that the background does not learn them.
    fn mark_people(&mut self) {
        let (width, height) = self.mask.dimensions();
        for region in self.filter.estimate_regions() {
            for span in &region.spans {
                if span.row < 0 || span.row as u32 >= height {
                    continue;
                }
                let left = span.left.floor().max(0.0) as u32;
                let right = (span.right.ceil().max(0.0) as u32).min(width);
                for col in left..right {
                    self.mask
                        .put_pixel(col, span.row as u32, image::Luma([FOREGROUND]));
                }
            }
        }
    }
}
