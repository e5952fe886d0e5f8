//! Renders a scenario camera's raw frames (`simulator::render::camera`) to a PNG frame directory
//! (what `edge-agent camera --frames` reads), a YUV4MPEG2 stream or raw RGB24, and prints how long
//! a frame took.
//!
//! ```sh
//! cargo run --release -p simulator --example render_camera -- --sensor cam1 --from 0 --to 30 --frames cam1/
//! cargo run --release -p simulator --example render_camera -- --sensor cam2 --y4m - | ffplay -f yuv4mpegpipe -
//! ```
//!
//! Flags: `--scenario FILE` (default: the built-in room), `--sensor NAME` (default `cam1`),
//! `--seed N` (1), `--from S` (0), `--to S` (the scenario's duration), and one of `--frames DIR`,
//! `--y4m FILE|-`, `--rgb FILE|-`.

use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

use simulator::render::camera::{
    write_frame_directory, write_raw_rgb, write_y4m, CameraRenderer, CameraRoom,
};
use simulator::Scenario;

/// Where the frames go.
enum Output {
    Frames(PathBuf),
    Y4m(String),
    Rgb(String),
}

/// The parsed flags.
struct Args {
    scenario: Option<PathBuf>,
    sensor: String,
    seed: u64,
    from: f64,
    to: Option<f64>,
    output: Output,
}

fn parse() -> Result<Args, String> {
    let mut args = Args {
        scenario: None,
        sensor: "cam1".into(),
        seed: 1,
        from: 0.0,
        to: None,
        output: Output::Frames("frames".into()),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let number = |v: &str| v.parse::<f64>().map_err(|e| format!("{flag} {v}: {e}"));
        match flag.as_str() {
            "--scenario" => args.scenario = Some(value.into()),
            "--sensor" => args.sensor = value,
            "--seed" => args.seed = value.parse().map_err(|e| format!("--seed {value}: {e}"))?,
            "--from" => args.from = number(&value)?,
            "--to" => args.to = Some(number(&value)?),
            "--frames" => args.output = Output::Frames(value.into()),
            "--y4m" => args.output = Output::Y4m(value),
            "--rgb" => args.output = Output::Rgb(value),
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    Ok(args)
}

fn writer(target: &str) -> std::io::Result<Box<dyn Write>> {
    Ok(if target == "-" {
        Box::new(BufWriter::new(std::io::stdout().lock()))
    } else {
        Box::new(BufWriter::new(std::fs::File::create(target)?))
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = parse()?;
    let scenario = match &args.scenario {
        Some(path) => Scenario::from_file(path)?,
        None => simulator::default_room(),
    };
    let (_, spec) = scenario.sensor(&args.sensor)?;
    let spec = spec.clone();
    let to = args.to.unwrap_or(scenario.duration_s);
    let built = Instant::now();
    let mut renderer =
        CameraRenderer::new(&scenario, &args.sensor, &CameraRoom::default(), args.seed)?;
    let setup_s = built.elapsed().as_secs_f64();
    let started = Instant::now();
    let frames = match &args.output {
        Output::Frames(dir) => write_frame_directory(&mut renderer, &spec, args.from, to, dir)?
            .paths
            .len(),
        Output::Y4m(target) => {
            write_y4m(&mut renderer, &spec, args.from, to, &mut writer(target)?)?
        }
        Output::Rgb(target) => {
            write_raw_rgb(&mut renderer, &spec, args.from, to, &mut writer(target)?)?
        }
    };
    let per_frame_ms = 1e3 * started.elapsed().as_secs_f64() / frames.max(1) as f64;
    eprintln!(
        "{}: {frames} frames of {:?} in [{}, {to}) s, {per_frame_ms:.1} ms per frame written (background {:.0} ms once)",
        args.sensor,
        renderer.size(),
        args.from,
        setup_s * 1e3
    );
    Ok(())
}
