//! `fusion-demo --raw`: every sensor's raw signal rendered from the scenario's truth
//! (`simulator::render`), written where the real front ends read it, the agent command that runs
//! each front end on it, and the truth published by the demo itself (no simulating agent runs to
//! publish it).
//!
//! Files per sensor, under the render directory: a camera's PNG frames in `<sensor>/`, a
//! microphone pair's stereo float WAV `<sensor>.wav`, a LIDAR's KITTI `.bin` scans in `<sensor>/`,
//! and every sensor's `SensorDescriptor` as `<sensor>.json`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use protocol::{keys, SensorModel, WireFormat};
use rayon::prelude::*;
use simulator::render::camera::{write_frame_directory, CameraRenderer, CameraRoom};
use simulator::render::{
    render_lidar_scan, render_mic_pair, AcousticRoom, LidarScene, RenderedPair, ScanPattern,
};
use simulator::{Scenario, SensorSpec};
use transport::ZenohConfig;
use zenoh::qos::CongestionControl;

/// Scenario time of a camera's first frame: the front end's background model learns the room
/// from the first frames, so they are taken before anybody walks in (the room's first person
/// enters at 0.5 s).
const CAMERA_FROM_S: f64 = -1.0;

/// One rendered sensor and what its agent reads.
#[derive(Debug, Clone)]
pub struct RawSensor {
    /// The sensor's name (its key chunk).
    pub sensor: String,
    /// Its descriptor, as JSON.
    pub descriptor: PathBuf,
    /// Its rendered signal.
    pub input: RawInput,
    /// Seconds the rendering took.
    pub render_s: f64,
}

/// A rendered signal, in the form its `edge-agent` subcommand reads.
#[derive(Debug, Clone)]
pub enum RawInput {
    /// A camera's PNG frames (`edge-agent camera --frames`), `fps` a second, the first taken at
    /// scenario time `first_s`.
    Frames {
        /// The frame directory.
        dir: PathBuf,
        /// Frames per second.
        fps: f64,
        /// Scenario time of the first frame, s.
        first_s: f64,
    },
    /// A microphone pair's stereo WAV from scenario time 0 (`edge-agent mic-pair --wav`).
    Wav {
        /// The WAV file.
        file: PathBuf,
    },
    /// A LIDAR's KITTI scans (`edge-agent lidar --scans`), `rate` a second, the first taken at
    /// scenario time `first_s`.
    Scans {
        /// The scan directory.
        dir: PathBuf,
        /// Scans per second.
        rate: f64,
        /// Scenario time of the first scan, s.
        first_s: f64,
    },
}

/// Renders every sensor of `scenario` for `duration_s` seconds of run `seed` into `dir`, two
/// sensors at a time (one per core), printing each one as it is done and the total, each line
/// begun with `program` (the program printing it). Whatever `dir`
/// held is removed first (the directory itself is kept: it may be a mount point): the agents read
/// every frame and scan there, so a longer earlier run's would be read too.
pub fn render_sensors(
    scenario: &Scenario,
    seed: u64,
    duration_s: f64,
    dir: &Path,
    program: &str,
) -> anyhow::Result<Vec<RawSensor>> {
    clear_directory(dir)?;
    println!(
        "{program}: rendering the raw signals of {} sensors ({duration_s} s) into {} …",
        scenario.sensors.len(),
        dir.display()
    );
    let began = Instant::now();
    let sensors = scenario
        .sensors
        .par_iter()
        .map(|spec| {
            let sensor = render_sensor(scenario, spec, seed, duration_s, dir)?;
            println!(
                "{program}: rendered {:8} {} in {:.1} s",
                sensor.sensor,
                sensor.input.describe(),
                sensor.render_s
            );
            Ok(sensor)
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let took = began.elapsed().as_secs_f64();
    println!("{program}: rendering took {took:.1} s");
    if took > 60.0 {
        // The demo's start is paced by this, not by the pipeline: say what shortens it.
        println!("{program}: rendering takes over a minute; a shorter --duration renders less");
    }
    Ok(sensors)
}

/// Creates `dir`, or empties it when it exists.
fn clear_directory(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            std::fs::remove_dir_all(&path)?;
        } else {
            std::fs::remove_file(&path)?;
        }
    }
    Ok(())
}

/// Removes the rendered signals in `dir` (about 40 MB per second of the default room, mostly PNG
/// frames and scans) and says so; they are rendered again, the same, by the next run.
pub fn remove_rendered(dir: &Path) {
    let size = directory_size(dir);
    match std::fs::remove_dir_all(dir) {
        Ok(()) => println!(
            "fusion-demo: removed the rendered signals ({:.0} MB; --keep-raw keeps them)",
            size as f64 / 1e6
        ),
        Err(e) => println!("fusion-demo: could not remove {}: {e}", dir.display()),
    }
}

/// Bytes of the files in `dir` and its subdirectories.
fn directory_size(dir: &Path) -> u64 {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    entries
        .flatten()
        .map(|entry| match entry.metadata() {
            Ok(meta) if meta.is_dir() => directory_size(&entry.path()),
            Ok(meta) => meta.len(),
            Err(_) => 0,
        })
        .sum()
}

impl RawSensor {
    /// Where `edge-agent --start-file` reads this sensor's first stamp: `<sensor>.start` beside
    /// its descriptor.
    pub fn start_file(&self) -> PathBuf {
        self.descriptor.with_extension("start")
    }

    /// Writes the stamp of this sensor's first frame, scenario time 0 being Unix time `start`, to
    /// [`RawSensor::start_file`], whole or not at all (written beside it, then renamed), so an
    /// agent waiting for it never reads half a number.
    pub fn write_start_file(&self, start: f64) -> std::io::Result<()> {
        let path = self.start_file();
        let partial = path.with_extension("start.partial");
        std::fs::write(&partial, format!("{:.6}\n", start + self.input.first_s()))?;
        std::fs::rename(&partial, &path)
    }
}

impl RawInput {
    /// Scenario time of the first frame, scan or sample.
    pub fn first_s(&self) -> f64 {
        match self {
            RawInput::Frames { first_s, .. } | RawInput::Scans { first_s, .. } => *first_s,
            RawInput::Wav { .. } => 0.0,
        }
    }

    /// What was rendered, for the progress lines.
    fn describe(&self) -> String {
        let count = |dir: &Path| std::fs::read_dir(dir).map_or(0, |d| d.count());
        match self {
            RawInput::Frames { dir, .. } => format!("{} frames", count(dir)),
            RawInput::Wav { file } => format!("audio {}", file.display()),
            RawInput::Scans { dir, .. } => format!("{} scans", count(dir)),
        }
    }
}

/// Renders one sensor and writes its descriptor; refused for a kind that has no raw signal.
fn render_sensor(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    duration_s: f64,
    dir: &Path,
) -> anyhow::Result<RawSensor> {
    let sensor = spec.sensor.as_str().to_string();
    let began = Instant::now();
    let input = match &spec.model {
        SensorModel::Camera(_) => render_camera(scenario, spec, seed, duration_s, dir)?,
        SensorModel::MicPair(_) => render_audio(scenario, spec, seed, duration_s, dir)?,
        SensorModel::Lidar(model) => {
            render_scans(scenario, spec, model, seed, duration_s, dir)?
        }
        other => anyhow::bail!(
            "sensor {sensor} is a {}: the simulator renders no raw signal for it (run without --raw)",
            other.kind_name()
        ),
    };
    let descriptor = dir.join(format!("{sensor}.json"));
    std::fs::write(
        &descriptor,
        serde_json::to_vec_pretty(&spec.descriptor(&scenario.site))?,
    )?;
    Ok(RawSensor {
        sensor,
        descriptor,
        input,
        render_s: began.elapsed().as_secs_f64(),
    })
}

/// A camera's frames from [`CAMERA_FROM_S`] to `duration_s`, as a PNG directory.
fn render_camera(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    duration_s: f64,
    dir: &Path,
) -> anyhow::Result<RawInput> {
    let name = spec.sensor.as_str();
    let mut renderer = CameraRenderer::new(scenario, name, &CameraRoom::default(), seed)?;
    let frames = dir.join(name);
    let rendered = write_frame_directory(&mut renderer, spec, CAMERA_FROM_S, duration_s, &frames)?;
    let first_s = *rendered
        .times
        .first()
        .ok_or_else(|| anyhow::anyhow!("camera {name}: no frame before {duration_s} s"))?;
    Ok(RawInput::Frames {
        dir: frames,
        fps: spec.rate_hz,
        first_s,
    })
}

/// A microphone pair's audio from scenario time 0, as a 32-bit float stereo WAV (channel 1 is the
/// descriptor's microphone 1), the form the raw-audio tests feed the agent.
fn render_audio(
    scenario: &Scenario,
    spec: &SensorSpec,
    seed: u64,
    duration_s: f64,
    dir: &Path,
) -> anyhow::Result<RawInput> {
    let name = spec.sensor.as_str();
    let rendered = render_mic_pair(scenario, name, &AcousticRoom::default(), seed, duration_s)?;
    let file = dir.join(format!("{name}.wav"));
    write_stereo_wav(&rendered, &file)?;
    Ok(RawInput::Wav { file })
}

/// Writes a pair's rendered audio as a 32-bit float stereo WAV (channel 1 is the descriptor's
/// microphone 1): what `edge-agent mic-pair --wav` reads.
pub fn write_stereo_wav(rendered: &RenderedPair, file: &Path) -> Result<(), hound::Error> {
    let format = hound::WavSpec {
        channels: 2,
        sample_rate: rendered.sample_rate,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut writer = hound::WavWriter::create(file, format)?;
    for (a, b) in rendered.mic1.iter().zip(&rendered.mic2) {
        writer.write_sample(*a as f32)?;
        writer.write_sample(*b as f32)?;
    }
    writer.finalize()
}

/// A LIDAR's scans at its frame times up to `duration_s`, ray-cast over the default room's scene
/// with the ceiling pattern, as KITTI `.bin` files named by index (the agent takes them in name
/// order).
fn render_scans(
    scenario: &Scenario,
    spec: &SensorSpec,
    model: &protocol::LidarModel,
    seed: u64,
    duration_s: f64,
    dir: &Path,
) -> anyhow::Result<RawInput> {
    let name = spec.sensor.as_str();
    let scans = dir.join(name);
    std::fs::create_dir_all(&scans)?;
    let scene = LidarScene::default_room();
    let pattern = ScanPattern::ceiling(model);
    for k in 0..spec.frame_count(duration_s) {
        let scan = render_lidar_scan(scenario, name, &scene, &pattern, seed, spec.frame_time(k))?;
        let cloud = frontends::lidar::PointCloud::from_points(scan.points());
        frontends::lidar::write_kitti_bin(scans.join(format!("{k:06}.bin")), &cloud)?;
    }
    Ok(RawInput::Scans {
        dir: scans,
        rate: spec.rate_hz,
        first_s: spec.phase_s,
    })
}

/// The `edge-agent` command that runs `sensor`'s front end on its rendered signal as a Zenoh
/// peer of `endpoint`, with scenario time 0 at Unix time `start`: each input's first frame is
/// stamped `start` plus its own scenario time, so that every agent's stamps and the truth agree.
pub fn agent_command(agent_bin: &Path, sensor: &RawSensor, endpoint: &str, start: f64) -> Command {
    let mut cmd = front_end_command(agent_bin, sensor, start);
    cmd.args(["--mode", "peer", "--connect", endpoint]);
    cmd
}

/// The `edge-agent` command that runs `sensor`'s front end on its rendered signal as fast as it
/// can and writes its replay lines to `output` (`-`: stdout) instead of publishing; stamps as
/// [`agent_command`]'s.
pub fn agent_output_command(
    agent_bin: &Path,
    sensor: &RawSensor,
    start: f64,
    output: &Path,
) -> Command {
    let mut cmd = front_end_command(agent_bin, sensor, start);
    cmd.arg("--output").arg(output);
    cmd
}

/// The subcommand, input, stamps and descriptor of `sensor`'s agent.
fn front_end_command(agent_bin: &Path, sensor: &RawSensor, start: f64) -> Command {
    let mut cmd = Command::new(agent_bin);
    match &sensor.input {
        RawInput::Frames { dir, fps, .. } => {
            cmd.arg("camera").arg("--frames").arg(dir);
            cmd.args(["--fps", &fps.to_string()]);
        }
        RawInput::Wav { file } => {
            cmd.arg("mic-pair").arg("--wav").arg(file);
        }
        RawInput::Scans { dir, rate, .. } => {
            cmd.arg("lidar").arg("--scans").arg(dir);
            cmd.args(["--rate", &rate.to_string()]);
        }
    }
    let first_stamp = start + sensor.input.first_s();
    cmd.args(["--start", &format!("{first_stamp:.6}")]);
    cmd.arg("--descriptor").arg(&sensor.descriptor);
    cmd
}

/// Publishes the scenario's truth for `duration_s` seconds of run `seed` on `fusion/<site>/truth`,
/// each set when the wall clock reaches its stamp (scenario time 0 at `start`), from a session of
/// its own connected to `endpoint`: what `edge-agent sim --truth` does in a simulated run, so the
/// demo's observer and `fusion-view` score the tracks alike.
pub async fn publish_truth(
    scenario: Scenario,
    seed: u64,
    start: f64,
    duration_s: f64,
    endpoint: String,
) -> anyhow::Result<()> {
    let config = ZenohConfig {
        connect: vec![endpoint],
        ..ZenohConfig::default()
    };
    let session = config.open().await?;
    publish_truth_on(&session, &scenario, seed, start, duration_s).await?;
    session
        .close()
        .await
        .map_err(|e| anyhow::anyhow!("closing the truth session: {e}"))
}

/// Publishes the scenario's truth on `session` as [`publish_truth`] does.
pub async fn publish_truth_on(
    session: &zenoh::Session,
    scenario: &Scenario,
    seed: u64,
    start: f64,
    duration_s: f64,
) -> anyhow::Result<()> {
    let format = WireFormat::Postcard;
    // Block, as the agents do: a truth set dropped under a burst would leave tracks unscored.
    let publisher = session
        .declare_publisher(keys::truth_key(&scenario.site))
        .encoding(format.to_zenoh())
        .congestion_control(CongestionControl::Block)
        .await
        .map_err(|e| anyhow::anyhow!("declaring the truth publisher: {e}"))?;
    for k in 0..scenario.truth_count(duration_s) {
        let truth = simulator::truth_set(scenario, seed, start, k);
        let wait = truth.stamp - fusion_server::clock::now();
        if wait > 0.0 {
            tokio::time::sleep(Duration::from_secs_f64(wait)).await;
        }
        let payload = protocol::encode(&truth, format)?;
        if let Err(e) = publisher.put(payload).await {
            tracing::warn!(error = %e, "putting a truth set failed");
        }
    }
    Ok(())
}
