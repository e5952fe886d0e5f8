//! Tracks over the truth as an SVG file: a top view, the height over time, and the OSPA curve
//! beneath (`fusion-server replay --plot`, `fusion-demo`).

mod paths;

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use protocol::{TrackSet, TruthSet};

use crate::score::Score;
use paths::{Paths, TimeSpan};

/// Track colours, one per id modulo their number (matplotlib's "tab10" without its grey and olive).
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

/// The truth is drawn in grey so that the coloured tracks stand out over it.
const TRUTH_GREY: RGBColor = RGBColor(160, 160, 160);

fn colour(id: u64) -> RGBColor {
    PALETTE[(id % PALETTE.len() as u64) as usize]
}

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// One panel of the figure.
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

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

fn draw(data: PlotData<'_>, path: &Path) -> PlotResult {
    let root = SVGBackend::new(path, (1000, 1100)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, rest) = root.split_vertically(560);
    let (height, ospa_area) = rest.split_vertically(300);
    let paths = Paths::new(data.tracks, data.truth);
    let span = paths.time_span();
    draw_top_view(&top, &paths)?;
    draw_height(&height, &paths, span)?;
    draw_ospa(&ospa_area, data.scores, span)?;
    root.present()?;
    Ok(())
}

/// x against y: the truth as grey lines, each track as dots of its colour, with a legend.
fn draw_top_view(area: &Area<'_>, paths: &Paths) -> PlotResult {
    let mut chart = ChartBuilder::on(area)
        .caption(
            "Top view: truth (grey) and tracks (colour per id)",
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(paths.range(0), paths.range(1))?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()?;
    for path in paths.truth.values() {
        chart.draw_series(LineSeries::new(
            path.iter().map(|(_, p)| (p[0], p[1])),
            &TRUTH_GREY,
        ))?;
    }
    for (id, path) in &paths.tracks {
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
    Ok(())
}

/// z against time since the first stamp, truth and tracks drawn as in the top view.
fn draw_height(area: &Area<'_>, paths: &Paths, span: TimeSpan) -> PlotResult {
    let mut chart = ChartBuilder::on(area)
        .caption("Height over time", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(span.axis(), paths.range(2))?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("z (m)")
        .draw()?;
    for path in paths.truth.values() {
        chart.draw_series(LineSeries::new(
            path.iter().map(|(t, p)| (span.since_start(*t), p[2])),
            &TRUTH_GREY,
        ))?;
    }
    for (id, path) in &paths.tracks {
        let style = colour(*id).filled();
        chart.draw_series(
            path.iter()
                .map(|(t, p)| Circle::new((span.since_start(*t), p[2]), 2, style)),
        )?;
    }
    Ok(())
}

/// The OSPA of each scored track set against time, on the time axis of the height panel.
fn draw_ospa(area: &Area<'_>, scores: &[Score], span: TimeSpan) -> PlotResult {
    // At least 0.1 m tall, so that a perfect run still gets a readable axis.
    let max_ospa = scores.iter().map(|s| s.ospa).fold(0.0, f64::max).max(0.1);
    let mut chart = ChartBuilder::on(area)
        .caption("OSPA (c = 1 m, p = 1)", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(span.axis(), 0.0..max_ospa * 1.05)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("OSPA (m)")
        .draw()?;
    chart.draw_series(LineSeries::new(
        scores.iter().map(|s| (span.since_start(s.stamp), s.ospa)),
        &BLACK,
    ))?;
    Ok(())
}
