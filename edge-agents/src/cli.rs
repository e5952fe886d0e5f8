//! The command line: one subcommand per sensor kind plus `sim`, and the flags they share.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use protocol::{SensorId, Site};

/// Edge agent of the fusion service: turns one sensor's data (or a simulation) into protocol measurement sets,
/// published over Zenoh and/or written as a replay file.
#[derive(Debug, Parser)]
#[command(name = "edge-agent", version, about)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate the sensors of a scenario (and optionally its truth) in real time or as fast as possible.
    Sim(SimCommand),
    /// A camera: frames or a video through the multi-Bernoulli image tracker (or blobs), or MOT detections
    /// through the single-view tracker → pixel estimates.
    Camera(CameraCommand),
    /// A microphone pair: stereo audio → GCC-PHAT time differences of arrival.
    #[command(name = "mic-pair")]
    MicPair(MicPairCommand),
    /// A LIDAR: point-cloud scans → ground removal and clustering → [range, azimuth, elevation].
    Lidar(LidarCommand),
}

/// Flags every subcommand has: where the data goes and how to join Zenoh.
#[derive(Debug, Args)]
pub struct CommonArgs {
    /// The deployment (`fusion/<site>/...`); default `default`, or the descriptor's / scenario's site.
    #[arg(long, value_parser = parse_site)]
    pub site: Option<Site>,
    /// TOML file with a `[zenoh]` (and optional `[log]`) section; `AGENT__ZENOH__MODE` etc. override it,
    /// and the flags below override both.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Zenoh mode: `peer` or `client` (a client needs a router in `--connect`).
    #[arg(long, value_name = "peer|client")]
    pub mode: Option<String>,
    /// Zenoh endpoint to connect to, e.g. `tcp/127.0.0.1:7447` (repeatable).
    #[arg(long, value_name = "ENDPOINT")]
    pub connect: Vec<String>,
    /// Zenoh endpoint to listen on, e.g. `tcp/0.0.0.0:7448` (repeatable).
    #[arg(long, value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// Write replay lines (JSON Lines of PROTOCOL.md) to this file, or `-` for stdout, instead of publishing.
    #[arg(long, value_name = "FILE.jsonl|-")]
    pub output: Option<PathBuf>,
    /// Publish over Zenoh as well when `--output` is given.
    #[arg(long)]
    pub publish: bool,
    /// Publish JSON payloads instead of postcard.
    #[arg(long)]
    pub json: bool,
    /// Keep the descriptor as given: only log when the front end's measured clutter rate or detection
    /// probability disagree with it, instead of announcing the measured figures (see edge-agents/README.md,
    /// "Descriptors that match the front end").
    #[arg(long)]
    pub keep_descriptor: bool,
}

/// When frames are stamped and published.
#[derive(Debug, Args)]
pub struct TimingArgs {
    /// Unix time (s) of the first frame / scenario time 0; default: the scenario's `start`, else the wall clock
    /// at launch. Processes given the same `--start` agree on every stamp.
    #[arg(long, value_name = "UNIX_SECONDS")]
    pub start: Option<f64>,
    /// Read `--start` from this file (one Unix time in seconds), waiting until it exists before reading the
    /// input: for inputs written by another process (`fusion-checker render`), which writes the file last.
    #[arg(long, value_name = "FILE", conflicts_with = "start")]
    pub start_file: Option<PathBuf>,
    /// Playback speed when publishing: 1 = real time, 2 = twice as fast. Ignored with `--output` alone,
    /// which writes as fast as possible.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
}

/// Which scenario to simulate and for how long.
#[derive(Debug, Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML, see simulator/SCENARIOS.md); default: the built-in room.
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Seed of the simulation's random streams.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Seconds of scenario to run; default: the scenario's `duration_s`.
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
}

/// `edge-agent sim`.
#[derive(Debug, Args)]
pub struct SimCommand {
    /// Output and Zenoh flags.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Stamping and pacing.
    #[command(flatten)]
    pub timing: TimingArgs,
    /// The scenario.
    #[command(flatten)]
    pub scenario: ScenarioArgs,
    /// A sensor of the scenario to simulate (repeatable); default: all of them.
    #[arg(long, value_name = "NAME", value_parser = parse_sensor)]
    pub sensor: Vec<SensorId>,
    /// Also publish (or write) the scenario's truth on `fusion/<site>/truth`.
    #[arg(long)]
    pub truth: bool,
}

/// Simulating one sensor instead of reading its data (`--simulate`).
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Simulate this sensor from `--scenario` instead of reading data (same code path as `sim --sensor`).
    #[arg(long)]
    pub simulate: bool,
    /// The scenario sensor to simulate; default: the scenario's first sensor of this subcommand's kind.
    #[arg(long, value_name = "NAME", value_parser = parse_sensor, requires = "simulate")]
    pub sensor: Option<SensorId>,
    /// The scenario.
    #[command(flatten)]
    pub scenario: ScenarioArgs,
}

/// `edge-agent camera`.
#[derive(Debug, Args)]
pub struct CameraCommand {
    /// Output and Zenoh flags.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Stamping and pacing.
    #[command(flatten)]
    pub timing: TimingArgs,
    /// `--simulate` instead of real data.
    #[command(flatten)]
    pub simulate: SimulateArgs,
    /// The camera's SensorDescriptor (TOML or JSON by extension; `site`/`version` may be omitted).
    #[arg(long, value_name = "FILE")]
    pub descriptor: Option<PathBuf>,
    /// Directory of PNG/JPEG frames (sorted by name) run through the camera front end (`--front-end`).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["detections", "video"])]
    pub frames: Option<PathBuf>,
    /// A video source decoded by the `ffmpeg` executable: a file, an `rtsp://`/`http://` URL, `/dev/videoN`,
    /// or `-` for a stream on stdin; its frames go through the camera front end like `--frames`.
    #[arg(long, value_name = "SRC", conflicts_with = "detections")]
    pub video: Option<String>,
    /// Extra ffmpeg input options for `--video`, split on spaces and placed before `-i`, e.g.
    /// `-rtsp_transport tcp` or `-f v4l2 -video_size 640x480`.
    #[arg(
        long,
        value_name = "ARGS",
        requires = "video",
        allow_hyphen_values = true
    )]
    pub ffmpeg_input_args: Option<String>,
    /// MOT Challenge detections (`det.txt`), one head point (top-centre) per box; `-` reads MOT or JSON
    /// lines live from stdin.
    #[arg(long, value_name = "FILE|-")]
    pub detections: Option<PathBuf>,
    /// Frame rate; frame i is stamped `start + i / fps` (for `--video FILE`: default the stream's rate).
    #[arg(long, value_name = "F", conflicts_with = "stamps")]
    pub fps: Option<f64>,
    /// Live sources (`--video -`, a device or a URL, `--detections -`): subtracted from the arrival time
    /// on the host clock to give the capture stamp (the camera's, encoder's and network's delay).
    #[arg(long, value_name = "MS", default_value_t = crate::capture_clock::DEFAULT_PIPELINE_DELAY_MS)]
    pub pipeline_delay_ms: f64,
    /// Stamps file (one per frame, for `--frames`): stamps as they are, or shifted so the first is `--start`.
    #[arg(long, value_name = "FILE")]
    pub stamps: Option<PathBuf>,
    /// Camera front-end configuration (TOML of `frontends::camera::CameraConfig`).
    #[arg(long, value_name = "FILE")]
    pub frontend_config: Option<PathBuf>,
    /// The front end frames (`--frames`, `--video`) go through: `multi-bernoulli` (people tracked on the
    /// background-subtracted image, head tops published with covariances) or `blobs` (head points of
    /// blobs, then the single-view tracker); default the configuration's `front_end` (`multi_bernoulli`).
    #[arg(long, value_enum, value_name = "KIND")]
    pub front_end: Option<FrontEndArg>,
    /// Publish the raw head points of the `blobs` front end (no single-view tracker, `covariances` null).
    #[arg(long)]
    pub raw: bool,
    /// Tracker: white-noise acceleration of a head on the image plane, px/s².
    #[arg(long, default_value_t = crate::camera_tracker::DEFAULT_ACCEL_NOISE, value_name = "PX_PER_S2")]
    pub accel_noise: f64,
    /// Tracker: expected number of new objects per frame over the whole image.
    #[arg(long, default_value_t = crate::camera_tracker::DEFAULT_BIRTH_RATE)]
    pub birth_rate: f64,
    /// Tracker: estimates are components (labels) with at least this weight.
    #[arg(long, default_value_t = crate::camera_tracker::DEFAULT_EXTRACTION_THRESHOLD)]
    pub extraction_threshold: f64,
}

/// `--front-end`: which camera front end decoded frames go through.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FrontEndArg {
    /// The multi-Bernoulli filter on the background-subtracted image.
    MultiBernoulli,
    /// Blobs and their head points, then the single-view point tracker.
    Blobs,
}

/// `edge-agent mic-pair`.
#[derive(Debug, Args)]
pub struct MicPairCommand {
    /// Output and Zenoh flags.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Stamping and pacing (`--start` is the capture time of the first audio sample).
    #[command(flatten)]
    pub timing: TimingArgs,
    /// `--simulate` instead of real data.
    #[command(flatten)]
    pub simulate: SimulateArgs,
    /// The pair's SensorDescriptor (TOML or JSON; `model.kind = "mic_pair"`).
    #[arg(long, value_name = "FILE")]
    pub descriptor: Option<PathBuf>,
    /// Stereo WAV file, or `-` for a live WAV stream on stdin (`arecord -t wav`, `sox ... -t wav -`): channel 1
    /// is microphone 1 of the descriptor, channel 2 microphone 2.
    #[arg(long, value_name = "FILE|-", conflicts_with_all = ["left", "right"])]
    pub wav: Option<PathBuf>,
    /// Live input (`--wav -`): subtracted from the host time at which a frame's audio arrived to give its
    /// capture stamp (the sound card's buffer and the pipe in front of the agent).
    #[arg(long, value_name = "MS", default_value_t = crate::capture_clock::DEFAULT_PIPELINE_DELAY_MS)]
    pub pipeline_delay_ms: f64,
    /// Mono WAV of microphone 1 (with `--right`).
    #[arg(long, value_name = "A.wav", requires = "right")]
    pub left: Option<PathBuf>,
    /// Mono WAV of microphone 2 (with `--left`).
    #[arg(long, value_name = "B.wav", requires = "left")]
    pub right: Option<PathBuf>,
    /// Capture from this sound input device (`default`: the host's default input), stereo, stamped on
    /// arrival like `--wav -` (built with the cargo feature `sound-card`).
    #[cfg(feature = "sound-card")]
    #[arg(long, value_name = "DEVICE", conflicts_with_all = ["wav", "left", "right"])]
    pub sound_card: Option<String>,
    /// Sample rate of `--sound-card`, Hz.
    #[cfg(feature = "sound-card")]
    #[arg(long, value_name = "HZ", default_value_t = 16_000)]
    pub sample_rate: u32,
    /// Mic front-end configuration (TOML of `frontends::mic::MicPairConfig`); default: its documented
    /// defaults with the descriptor's baseline and speed of sound.
    #[arg(long, value_name = "FILE")]
    pub frontend_config: Option<PathBuf>,
}

/// `edge-agent lidar`.
#[derive(Debug, Args)]
pub struct LidarCommand {
    /// Output and Zenoh flags.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Stamping and pacing (`--start` is the stamp of the first scan).
    #[command(flatten)]
    pub timing: TimingArgs,
    /// `--simulate` instead of real data.
    #[command(flatten)]
    pub simulate: SimulateArgs,
    /// The LIDAR's SensorDescriptor (TOML or JSON; `model.kind = "lidar"`).
    #[arg(long, value_name = "FILE")]
    pub descriptor: Option<PathBuf>,
    /// Directory of `.pcd` or KITTI `.bin` scans, taken in file-name order.
    #[arg(long, value_name = "DIR", conflicts_with = "velodyne")]
    pub scans: Option<PathBuf>,
    /// With `--scans`: keep watching the directory and take each new scan once it is complete (its size and
    /// modification time unchanged over two polls 100 ms apart), stamped when taken.
    #[arg(long, requires = "scans")]
    pub follow: bool,
    /// Receive VLP-16 / VLP-32C data packets on this UDP address (`ADDR` or `ADDR:PORT`, default port 2368);
    /// one scan per rotation, stamped at the host time of its first packet.
    #[arg(long, value_name = "ADDR:PORT")]
    pub velodyne: Option<String>,
    /// With `--velodyne`: end (withdrawing the sensor) after this many seconds without a packet, once packets
    /// have come; 0 waits for ever.
    #[arg(long, value_name = "S", default_value_t = 5.0)]
    pub idle_timeout_s: f64,
    /// Live input (`--velodyne`, `--follow`): subtracted from the host time at which a scan's first packet (or
    /// its file) arrived to give its capture stamp.
    #[arg(long, value_name = "MS", default_value_t = crate::capture_clock::DEFAULT_PIPELINE_DELAY_MS)]
    pub pipeline_delay_ms: f64,
    /// Scans per second; scan i is stamped `start + i / rate`.
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// LIDAR front-end configuration (TOML of the frontends LIDAR pipeline's configuration).
    #[arg(long, value_name = "FILE")]
    pub frontend_config: Option<PathBuf>,
}

/// Parses `--site` with the protocol's chunk rules.
fn parse_site(text: &str) -> Result<Site, String> {
    Site::new(text).map_err(|e| e.to_string())
}

/// Parses `--sensor` with the protocol's chunk rules.
fn parse_sensor(text: &str) -> Result<SensorId, String> {
    SensorId::new(text).map_err(|e| e.to_string())
}
