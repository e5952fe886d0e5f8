//! `edge-agent mic-pair`: two-channel audio → GCC-PHAT → one set of TDOAs `[tau]` per audio frame.
//!
//! Channel 1 (or `--left`) is microphone m₁ of the descriptor, channel 2 (`--right`) is m₂; the front end's
//! sign convention is the protocol's, tau = (‖x−m₂‖ − ‖x−m₁‖)/c. Frame stamps are `--start` (the capture time
//! of the first sample; default the launch time) plus the frame centre's offset. `--wav -` reads a live stream
//! (`mic_stream.rs`), stamped on arrival.

use std::path::Path;

use frontends::mic::{read_mono_pair, read_stereo_wav, MicPairConfig, MicPairPipeline};
use protocol::{MicPairModel, SensorKind, SensorModel};

use crate::cli::MicPairCommand;
use crate::descriptor::load_descriptor;
use crate::emit::Frame;
use crate::error::AgentError;
use crate::launch::Prepared;
use crate::mic_stream::LiveMic;
use crate::pacing::wall_clock;
use crate::run::{Event, EventSource};
use crate::settings::read_frontend_config;
use crate::sim::prepare_simulated_sensor;
use crate::tdoa_noise::TdoaNoise;

/// Largest relative difference between the front end's `mic_distance` and the descriptor's baseline that
/// passes without a warning.
const BASELINE_TOLERANCE: f64 = 1e-3;

/// Prepares `edge-agent mic-pair`.
pub fn prepare_mic_pair(command: &MicPairCommand) -> Result<Prepared, AgentError> {
    if command.simulate.simulate {
        if command.wav.is_some() || command.left.is_some() || command.descriptor.is_some() {
            return Err(AgentError::Usage(
                "--simulate takes the pair from --scenario: do not give --wav, --left/--right or --descriptor".into(),
            ));
        }
        return prepare_simulated_sensor(
            &command.simulate,
            command.common.site.as_ref(),
            &command.timing,
            SensorKind::MicPair,
        );
    }
    let descriptor_path = command.descriptor.as_deref().ok_or_else(|| {
        AgentError::Usage("mic-pair needs --descriptor FILE (or --simulate)".into())
    })?;
    let descriptor = load_descriptor(
        descriptor_path,
        command.common.site.as_ref(),
        SensorKind::MicPair,
    )?;
    let SensorModel::MicPair(model) = &descriptor.model else {
        return Err(AgentError::Usage("the descriptor is not a mic pair".into()));
    };
    let config = frontend_config(command.frontend_config.as_deref(), model)?;
    let noise = TdoaNoise::new(model.noise_std, config.noise_by_peak_height);
    #[cfg(feature = "sound-card")]
    if let Some(device) = &command.sound_card {
        let device = (device != "default").then_some(device.as_str());
        let source = crate::sound_card::start(
            device,
            command.sample_rate,
            config,
            command.pipeline_delay_ms,
        )?;
        return live_prepared(source.with_noise(noise), descriptor);
    }
    if command
        .wav
        .as_deref()
        .is_some_and(|wav| wav.as_os_str() == "-")
    {
        return prepare_live(command, config, noise, descriptor);
    }
    prepare_recording(command, config, noise, descriptor)
}

/// `--wav FILE` or `--left`/`--right`: the whole recording analysed up front.
fn prepare_recording(
    command: &MicPairCommand,
    config: MicPairConfig,
    noise: TdoaNoise,
    descriptor: protocol::SensorDescriptor,
) -> Result<Prepared, AgentError> {
    let audio =
        match (&command.wav, &command.left, &command.right) {
            (Some(wav), None, None) => read_stereo_wav(wav)?,
            (None, Some(left), Some(right)) => read_mono_pair(left, right)?,
            _ => return Err(AgentError::Usage(
                "mic-pair needs one input: --wav FILE, --wav - (a stream on stdin), --left A.wav --right B.wav, or --simulate"
                    .into(),
            )),
        };
    let mut pipeline = MicPairPipeline::new(config, audio.sample_rate())?;
    let start = command.timing.start.unwrap_or_else(wall_clock);
    let frames = pipeline.process(&audio, start)?;
    tracing::info!(
        frames = frames.len(),
        seconds = audio.duration(),
        sample_rate = audio.sample_rate(),
        "audio analysed"
    );
    let source = MicSource {
        frames: frames
            .into_iter()
            .map(|f| Frame {
                stamp: f.stamp,
                covariances: noise.covariances(&f.relative_variances),
                measurements: f.tdoas.into_iter().map(|tau| vec![tau]).collect(),
            })
            .collect::<Vec<_>>()
            .into_iter(),
    };
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        start,
        start,
    ))
}

/// `--wav -`: the stream on stdin, stamped on arrival.
fn prepare_live(
    command: &MicPairCommand,
    config: MicPairConfig,
    noise: TdoaNoise,
    descriptor: protocol::SensorDescriptor,
) -> Result<Prepared, AgentError> {
    if command.timing.start.is_some() {
        return Err(AgentError::Usage(
            "--wav - is stamped on arrival (host clock less --pipeline-delay-ms): do not give --start"
                .into(),
        ));
    }
    let source = LiveMic::start(std::io::stdin(), config, command.pipeline_delay_ms)?;
    live_prepared(source.with_noise(noise), descriptor)
}

/// A live pair's run: its pacing origin is when its capture started.
fn live_prepared(
    source: LiveMic,
    descriptor: protocol::SensorDescriptor,
) -> Result<Prepared, AgentError> {
    let origin = source.origin_wall();
    Ok(Prepared::single_sensor(
        Box::new(source),
        descriptor,
        origin,
        origin,
    ))
}

/// The front end's configuration: the TOML file, or the defaults with the descriptor's baseline and speed
/// of sound (so that the search range ±d/c is the descriptor's).
fn frontend_config(path: Option<&Path>, model: &MicPairModel) -> Result<MicPairConfig, AgentError> {
    let baseline = model.baseline();
    let Some(path) = path else {
        let mut config = MicPairConfig::new(baseline);
        config.speed_of_sound = model.speed_of_sound;
        return Ok(config);
    };
    let config: MicPairConfig = read_frontend_config(path)?;
    if (config.mic_distance - baseline).abs() > BASELINE_TOLERANCE * baseline {
        tracing::warn!(
            mic_distance = config.mic_distance,
            descriptor_baseline = baseline,
            "the front end's mic_distance differs from the descriptor's baseline"
        );
    }
    Ok(config)
}

/// The TDOA sets of the whole recording, computed up front (audio files are small next to memory).
struct MicSource {
    frames: std::vec::IntoIter<Frame>,
}

impl EventSource for MicSource {
    fn next_event(&mut self) -> Result<Option<Event>, AgentError> {
        Ok(self
            .frames
            .next()
            .map(|frame| Event::Set { stream: 0, frame }))
    }
}
