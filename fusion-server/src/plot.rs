//! `replay --plot FILE.svg`: the tracks over the truth (top view, and height over time) with the
//! OSPA curve beneath.

use std::collections::BTreeMap;
use std::path::Path;

use plotters::prelude::*;

use protocol::{TrackSet, TruthSet};

use crate::replay::Score;

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

fn colour(id: u64) -> RGBColor {
    PALETTE[(id % PALETTE.len() as u64) as usize]
}

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// What a plot shows: the track sets, the truth and the scores of the track sets.
#[derive(Debug, Clone, Copy)]
pub struct PlotData<'a> {
    /// Track sets in stamp order.
    pub tracks: &'a [TrackSet],
    /// Truth sets in stamp order.
    pub truth: &'a [TruthSet],
    /// OSPA per scored track set.
    pub scores: &'a [Score],
}

/// Draws `data` into an SVG file at `path`.
pub fn plot(data: PlotData<'_>, path: &Path) -> anyhow::Result<()> {
    draw(data, path).map_err(|e| anyhow::anyhow!("plotting to {}: {e}", path.display()))
}

fn draw(report: PlotData<'_>, path: &Path) -> PlotResult {
    let root = SVGBackend::new(path, (1000, 1100)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, rest) = root.split_vertically(560);
    let (height, ospa_area) = rest.split_vertically(300);

    // Per-object paths of the truth and per-id paths of the tracks: (t, x, y, z).
    let mut truth_paths: BTreeMap<u64, Vec<(f64, [f64; 3])>> = BTreeMap::new();
    for set in report.truth {
        for object in &set.objects {
            truth_paths
                .entry(object.id)
                .or_default()
                .push((set.stamp, object.position));
        }
    }
    let mut track_paths: BTreeMap<u64, Vec<(f64, [f64; 3])>> = BTreeMap::new();
    for set in report.tracks {
        for track in &set.tracks {
            track_paths
                .entry(track.id)
                .or_default()
                .push((set.stamp, track.position));
        }
    }
    let all = || truth_paths.values().chain(track_paths.values()).flatten();
    let range = |axis: usize| {
        let (lo, hi) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, p)| {
            (lo.min(p[axis]), hi.max(p[axis]))
        });
        if lo.is_finite() {
            (lo - 0.2)..(hi + 0.2)
        } else {
            0.0..1.0
        }
    };
    let t0 = all().map(|(t, _)| *t).fold(f64::INFINITY, f64::min);
    let t1 = all().map(|(t, _)| *t).fold(f64::NEG_INFINITY, f64::max);
    let (t0, t1) = if t0.is_finite() && t1 > t0 {
        (t0, t1)
    } else {
        (0.0, 1.0)
    };

    let mut chart = ChartBuilder::on(&top)
        .caption(
            "Top view: truth (grey) and tracks (colour per id)",
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(range(0), range(1))?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()?;
    for path in truth_paths.values() {
        chart.draw_series(LineSeries::new(
            path.iter().map(|(_, p)| (p[0], p[1])),
            &RGBColor(160, 160, 160),
        ))?;
    }
    for (id, path) in &track_paths {
        let style = colour(*id).filled();
        chart
            .draw_series(
                path.iter()
                    .map(|(_, p)| Circle::new((p[0], p[1]), 2, style)),
            )?
            .label(format!("track {id}"))
            .legend(move |(x, y)| Circle::new((x, y), 3, style));
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()?;

    let mut chart = ChartBuilder::on(&height)
        .caption("Height over time", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d((0.0)..(t1 - t0), range(2))?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("z (m)")
        .draw()?;
    for path in truth_paths.values() {
        chart.draw_series(LineSeries::new(
            path.iter().map(|(t, p)| (t - t0, p[2])),
            &RGBColor(160, 160, 160),
        ))?;
    }
    for (id, path) in &track_paths {
        let style = colour(*id).filled();
        chart.draw_series(
            path.iter()
                .map(|(t, p)| Circle::new((t - t0, p[2]), 2, style)),
        )?;
    }

    let max_ospa = report
        .scores
        .iter()
        .map(|s| s.ospa)
        .fold(0.0, f64::max)
        .max(0.1);
    let mut chart = ChartBuilder::on(&ospa_area)
        .caption("OSPA (c = 1 m, p = 1)", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d((0.0)..(t1 - t0), 0.0..max_ospa * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("OSPA (m)")
        .draw()?;
    chart.draw_series(LineSeries::new(
        report.scores.iter().map(|s| (s.stamp - t0, s.ospa)),
        &BLACK,
    ))?;
    root.present()?;
    Ok(())
}
