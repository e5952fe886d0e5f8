//! Segmentation of the range image: neighbouring cells (the next return along the ring, either way, and
//! the return in the same column on the ring above or below, skipping up to `max_gap_cells` empty cells)
//! are one object when their ranges differ by at most `max_range_jump`; the segments are the connected
//! components, grown breadth first. Because adjacency is by beam and azimuth index, a person's rings stay
//! connected however far apart they are in space (0.52 m at 15 m for a VLP-16), where a fixed Euclidean
//! tolerance breaks them up. This is the grid-and-range neighbourhood of Lee et al.'s mean-shift
//! segmentation of the range image, in its simplest (flat-kernel, one-pass) form.

use super::range_image::{RangeImage, RangeImageConfig, EMPTY};

/// The segments of the image: each the indices of its points (into the cloud the image was built from),
/// those with `min_points..=max_points` members, in the order of their first cell. A point shadowed by a
/// nearer one in its cell joins that one's segment when their ranges are within `max_range_jump`.
pub(super) fn segment_range_image(
    image: &RangeImage,
    points: &[[f64; 3]],
    config: &RangeImageConfig,
) -> Vec<Vec<usize>> {
    let range = |cell: usize| norm(&points[image.cells[cell] as usize]);
    let mut label = vec![u32::MAX; image.cells.len()];
    let mut segments: Vec<Vec<usize>> = Vec::new();
    let mut queue = Vec::new();
    for seed in 0..image.cells.len() {
        if image.cells[seed] == EMPTY || label[seed] != u32::MAX {
            continue;
        }
        let id = segments.len() as u32;
        label[seed] = id;
        queue.clear();
        queue.push(seed);
        let mut next = 0;
        while let Some(&cell) = queue.get(next) {
            next += 1;
            let here = range(cell);
            for neighbour in neighbours(image, cell, config.max_gap_cells) {
                if label[neighbour] == u32::MAX
                    && (range(neighbour) - here).abs() <= config.max_range_jump
                {
                    label[neighbour] = id;
                    queue.push(neighbour);
                }
            }
        }
        segments.push(queue.iter().map(|&c| image.cells[c] as usize).collect());
    }
    for &(point, cell) in &image.shadowed {
        if (norm(&points[point]) - range(cell)).abs() <= config.max_range_jump {
            segments[label[cell] as usize].push(point);
        }
    }
    segments.retain(|s| (config.min_points..=config.max_points).contains(&s.len()));
    segments
}

/// The nearest occupied cell in each of the four grid directions within `max_gap` empty cells.
fn neighbours(image: &RangeImage, cell: usize, max_gap: usize) -> impl Iterator<Item = usize> + '_ {
    let (ring, column) = (cell / image.columns, cell % image.columns);
    let columns = image.columns;
    let along_ring = [1, columns - 1].into_iter().map(move |step| {
        (1..=max_gap + 1)
            .map(|k| ring * columns + (column + k * step) % columns)
            .find(|&c| image.cells[c] != EMPTY)
    });
    let across_rings = [1isize, -1].into_iter().map(move |step| {
        (1..=max_gap as isize + 1)
            .map(|k| ring as isize + k * step)
            .take_while(|&r| r >= 0 && (r as usize) < image.rings)
            .map(|r| r as usize * columns + column)
            .find(|&c| image.cells[c] != EMPTY)
    });
    along_ring
        .chain(across_rings)
        .flatten()
        .filter(move |&c| c != cell)
}

fn norm(point: &[f64; 3]) -> f64 {
    point.iter().map(|v| v * v).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point at `range` along (elevation, azimuth) in degrees.
    fn ray(range: f64, elevation: f64, azimuth: f64) -> [f64; 3] {
        let (e, a) = (elevation.to_radians(), azimuth.to_radians());
        [
            range * e.cos() * a.cos(),
            range * e.cos() * a.sin(),
            range * e.sin(),
        ]
    }

    #[test]
    fn rings_two_degrees_apart_at_twenty_metres_stay_one_object_and_depth_jumps_split() {
        let mut points = Vec::new();
        // A person-sized patch 20 m away: 4 rings 2° apart (0.7 m in space), 5 columns.
        for ring in 0..4 {
            for column in 0..5 {
                points.push(ray(
                    20.0 + 0.02 * column as f64,
                    -5.0 + 2.0 * ring as f64,
                    0.1 + 0.2 * column as f64,
                ));
            }
        }
        // A wall 1 m behind, to the side, touching the patch in the grid.
        for column in 5..40 {
            points.push(ray(21.0, -3.0, 0.1 + 0.2 * column as f64));
        }
        // One dropout gap inside a ring does not break it.
        points.remove(7);
        let config = RangeImageConfig::default();
        let image = RangeImage::build(&points, &vec![true; points.len()], &config).unwrap();
        let segments = segment_range_image(&image, &points, &config);
        let sizes: Vec<usize> = segments.iter().map(Vec::len).collect();
        println!("segment sizes {sizes:?}");
        assert_eq!(sizes, vec![19, 35]);
    }
}
