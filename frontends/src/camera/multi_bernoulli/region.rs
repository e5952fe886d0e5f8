//! The image region a hypothesised person covers (the paper's `T(x)`): a head (the outline of an
//! upright ellipsoid) over a body that narrows from the shoulders to the feet, projected through the
//! camera at the person's floor position and height, rasterised into one span per row of the shrunk
//! image.
//!
//! A vertical body's width is measured across the line of sight (`CameraGeometry::across_sight`), so
//! the region's size follows the person's distance and its axis follows the camera's perspective.
//! Rows cut by the region's top or bottom edge count with the share of the row they cover, so the
//! likelihood varies smoothly with the head's height rather than in whole rows.

use super::config::PersonShape;
use super::geometry::CameraGeometry;
use super::outline::ImageEllipse;

/// Columns `[left, right)` of row `row` of the shrunk image, counted with `weight` (the share of the
/// row's height the region covers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowSpan {
    /// Row of the shrunk image (may lie outside it).
    pub row: i32,
    /// Left edge, columns of the shrunk image (fractional).
    pub left: f32,
    /// Right edge.
    pub right: f32,
    /// Share of the row's height covered, in (0, 1].
    pub weight: f32,
}

impl RowSpan {
    /// The span's area in pixels of the shrunk image.
    pub fn area(&self) -> f32 {
        self.weight * (self.right - self.left).max(0.0)
    }
}

/// A person's region: the head's spans first, then the body's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Region {
    /// The spans, head first, each list in row order.
    pub spans: Vec<RowSpan>,
    /// How many of `spans` belong to the head.
    pub head_spans: usize,
    /// Row (shrunk image, fractional) of the shoulders.
    pub shoulder_row: f32,
}

impl Region {
    /// The head's spans.
    pub fn head(&self) -> &[RowSpan] {
        &self.spans[..self.head_spans]
    }

    /// Area of the whole region, inside the image or not.
    pub fn area(&self) -> f32 {
        self.spans.iter().map(RowSpan::area).sum()
    }

    /// Area of the part inside an image of `size` (shrunk) pixels.
    pub fn area_inside(&self, size: [usize; 2]) -> f32 {
        inside(&self.spans, size)
    }

    /// Area of the head and shoulders (rows above the shoulders) inside an image of `size` pixels.
    pub fn upper_area_inside(&self, size: [usize; 2]) -> f32 {
        let upper: Vec<RowSpan> = self
            .spans
            .iter()
            .filter(|s| (s.row as f32) < self.shoulder_row)
            .copied()
            .collect();
        inside(&upper, size)
    }
}

/// Area of `spans` clipped to an image of `size` pixels.
pub fn inside(spans: &[RowSpan], size: [usize; 2]) -> f32 {
    let (width, height) = (size[0] as f32, size[1] as i32);
    spans
        .iter()
        .filter(|s| (0..height).contains(&s.row))
        .map(|s| s.weight * (s.right.min(width) - s.left.max(0.0)).max(0.0))
        .sum()
}

/// One key point of the body's outline: row and column of its axis, half-width, in shrunk pixels.
#[derive(Debug, Clone, Copy)]
struct Slice {
    row: f64,
    col: f64,
    half_width: f64,
}

/// Projects a person and rasterises it.
#[derive(Debug, Clone)]
pub struct PersonProjector {
    geometry: CameraGeometry,
    shape: PersonShape,
    floor_z: f64,
    /// Full-resolution pixels per shrunk pixel.
    scale: f64,
}

impl PersonProjector {
    /// A projector for `geometry`, people of `shape` standing on the floor at `floor_z`, into an image
    /// shrunk by `scale`.
    pub fn new(geometry: CameraGeometry, shape: PersonShape, floor_z: f64, scale: u32) -> Self {
        Self {
            geometry,
            shape,
            floor_z,
            scale: f64::from(scale),
        }
    }

    /// The camera.
    pub fn geometry(&self) -> &CameraGeometry {
        &self.geometry
    }

    /// The person model.
    pub fn shape(&self) -> &PersonShape {
        &self.shape
    }

    /// Height of the floor.
    pub fn floor_z(&self) -> f64 {
        self.floor_z
    }

    /// Full-resolution pixels per shrunk pixel.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The full-resolution pixel of the head top of a person of `height` standing at `(x, y)`.
    pub fn head_top(&self, x: f64, y: f64, height: f64) -> Option<[f64; 2]> {
        self.geometry.project([x, y, self.floor_z + height])
    }

    /// The axis point at height `z` (above the floor) of a person at `(x, y)` and its half-width for a
    /// body `half_width` metres wide there, in shrunk pixels.
    fn slice(&self, x: f64, y: f64, z: f64, half_width: f64) -> Option<Slice> {
        let z = self.floor_z + z;
        let centre = self.geometry.project([x, y, z])?;
        let [ax, ay] = self.geometry.across_sight(x, y)?;
        let a = self
            .geometry
            .project([x + half_width * ax, y + half_width * ay, z])?;
        let b = self
            .geometry
            .project([x - half_width * ax, y - half_width * ay, z])?;
        Some(Slice {
            row: centre[1] / self.scale,
            col: centre[0] / self.scale,
            half_width: 0.5 * (a[0] - b[0]).hypot(a[1] - b[1]) / self.scale,
        })
    }

    /// Writes into `region` the region of a person of `height` standing at `(x, y)`; false (and an
    /// empty region) when part of the person is behind the camera or the image's rows do not run from
    /// head to feet.
    pub fn rasterise(&self, x: f64, y: f64, height: f64, region: &mut Region) -> bool {
        region.spans.clear();
        region.head_spans = 0;
        let s = &self.shape;
        let slices = [
            (height, s.head_half_width),
            (height * (1.0 - s.head_share), s.neck_half_width),
            (height * s.shoulder_share, s.shoulder_half_width),
            (height * s.hip_share, s.hip_half_width),
            (0.0, s.foot_half_width),
        ]
        .map(|(z, w)| self.slice(x, y, z, w));
        let Some([top, chin, shoulder, hip, foot]) = collect(slices) else {
            return false;
        };
        let ordered = [top, chin, shoulder, hip, foot]
            .windows(2)
            .all(|w| w[0].row < w[1].row);
        let Some(head_bottom) = ordered
            .then(|| self.head_spans(x, y, height, &mut region.spans))
            .flatten()
        else {
            region.spans.clear();
            return false;
        };
        region.head_spans = region.spans.len();
        let body = [chin, shoulder, hip, foot];
        // The body starts where the head's outline ends (below the chin when seen from above), so that
        // no pixel is counted twice.
        rows(
            chin.row.max(head_bottom),
            foot.row,
            &mut region.spans,
            |r| {
                let k = body.windows(2).position(|w| r <= w[1].row).unwrap_or(2);
                let (a, b) = (body[k], body[k + 1]);
                let t = ((r - a.row) / (b.row - a.row)).clamp(0.0, 1.0);
                (
                    a.col + t * (b.col - a.col),
                    a.half_width + t * (b.half_width - a.half_width),
                )
            },
        );
        region.shoulder_row = shoulder.row as f32;
        true
    }

    /// Appends the spans of the head, the outline of an upright ellipsoid (the person model's head
    /// breadth and height, its top at the person's height) as the camera sees it: from an elevated
    /// camera it reaches above the head top's own projection. Returns the outline's bottom row.
    fn head_spans(&self, x: f64, y: f64, height: f64, spans: &mut Vec<RowSpan>) -> Option<f64> {
        let s = &self.shape;
        let half_height = 0.5 * s.head_share * height;
        let centre = [x, y, self.floor_z + height - half_height];
        let conic = self
            .geometry
            .ellipsoid_outline(centre, s.head_half_width, half_height)?;
        let ellipse = ImageEllipse::new(conic)?;
        let (top, bottom) = ellipse.rows()?;
        let scale = self.scale;
        rows(top / scale, bottom / scale, spans, |r| {
            match ellipse.columns(r * scale) {
                Some((left, right)) => (0.5 * (left + right) / scale, 0.5 * (right - left) / scale),
                None => (0.0, 0.0),
            }
        });
        Some(bottom / scale)
    }
}

fn collect(slices: [Option<Slice>; 5]) -> Option<[Slice; 5]> {
    let mut out = [Slice {
        row: 0.0,
        col: 0.0,
        half_width: 0.0,
    }; 5];
    for (o, s) in out.iter_mut().zip(slices) {
        *o = s?;
    }
    Some(out)
}

/// Appends the spans of the rows from `from` to `to` (fractional rows), the axis column and half-width
/// of each taken from `outline` at the middle of the part of the row covered.
fn rows(from: f64, to: f64, spans: &mut Vec<RowSpan>, outline: impl Fn(f64) -> (f64, f64)) {
    let first = from.floor() as i64;
    let last = to.ceil() as i64;
    for row in first..last {
        let (a, b) = ((row as f64).max(from), ((row + 1) as f64).min(to));
        if b <= a {
            continue;
        }
        let (col, half_width) = outline(0.5 * (a + b));
        if half_width <= 0.0 {
            continue;
        }
        spans.push(RowSpan {
            row: row as i32,
            left: (col - half_width) as f32,
            right: (col + half_width) as f32,
            weight: (b - a) as f32,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::geometry::tests::level_camera;
    use super::*;

    #[test]
    fn a_person_three_metres_away_covers_the_expected_rows_and_width() {
        let projector = PersonProjector::new(level_camera(), PersonShape::default(), 0.0, 1);
        let mut region = Region::default();
        assert!(projector.rasterise(3.0, 0.0, 1.7, &mut region));
        // Head top at z 1.7: 0.8 m below the camera at 3 m: row 240 + 500 · 0.8 / 3. Seen from above,
        // the head's outline reaches a little beyond that projection (a sliver of the row above).
        let top = region.spans[0];
        assert!(
            (top.row as f64 - (240.0 + 500.0 * 0.8 / 3.0)).abs() <= 2.0,
            "{top:?}"
        );
        let feet = region.spans.last().unwrap();
        assert!(
            (feet.row as f64 - (240.0 + 500.0 * 2.5 / 3.0)).abs() <= 1.0,
            "{feet:?}"
        );
        // The shoulders are 0.4 m wide: 67 px at 3 m.
        let widest = region
            .spans
            .iter()
            .map(|s| s.right - s.left)
            .fold(0.0, f32::max);
        assert!((widest - 66.7).abs() < 1.5, "{widest}");
        assert!(region.head_spans > 0 && region.head().iter().all(|s| s.right - s.left < 30.0));
        let shrunk = PersonProjector::new(level_camera(), PersonShape::default(), 0.0, 2);
        let mut half = Region::default();
        assert!(shrunk.rasterise(3.0, 0.0, 1.7, &mut half));
        assert!((half.area() * 4.0 - region.area()).abs() < 0.02 * region.area());
    }

    #[test]
    fn a_person_behind_the_camera_has_no_region() {
        let projector = PersonProjector::new(level_camera(), PersonShape::default(), 0.0, 2);
        let mut region = Region::default();
        assert!(!projector.rasterise(-2.0, 0.0, 1.7, &mut region));
        assert!(region.spans.is_empty());
    }
}
