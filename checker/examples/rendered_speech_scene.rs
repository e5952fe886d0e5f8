//! Writes the simulator's rendered two-talker room as a scene directory of `tools/speech_scene/`, so
//! that `score_scene.py` scores the simulator's own room as it scores the speech made elsewhere.
//!
//! The room is the one `tests/tests/raw_mic_tracks.rs` renders: the default room's first two people
//! and its four microphone pairs, speech-like talkers through the image-source model (T60 0.3 s,
//! SNR 20 dB). Written: each pair's stereo WAV and the descriptor it is given, the truth
//! (`truth.jsonl`), the talk spurts and scenario time 0 (`scene.json`) and the server configuration
//! of the test (`server.toml`).
//!
//! ```sh
//! cargo run --release -p checker --example rendered_speech_scene -- scenes/seed1 --seed 1
//! python3 tools/speech_scene/score_scene.py scenes/seed1 --bin target/release
//! ```

use std::path::{Path, PathBuf};

use anyhow::Context;
use checker::raw_inputs::write_stereo_wav;
use checker::talker_room::{two_talker_room, SERVER_TOML, START};
use clap::Parser;
use protocol::ReplayLine;
use simulator::render::{render_mic_pair, AcousticRoom, Talker};
use simulator::Scenario;

/// Write the rendered two-talker room as a speech scene directory.
#[derive(Parser)]
struct Arguments {
    /// Directory to write (created if missing; its files are overwritten).
    out: PathBuf,
    /// Seed of the scenario's random streams.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seconds to render.
    #[arg(long, default_value_t = 40.0)]
    duration: f64,
}

fn main() -> anyhow::Result<()> {
    let arguments = Arguments::parse();
    let scenario = two_talker_room(arguments.duration);
    let out = &arguments.out;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut talkers = Vec::new();
    for spec in &scenario.sensors {
        let name = spec.sensor.as_str();
        eprintln!("rendering {name} ({} s)", arguments.duration);
        let room = AcousticRoom::default();
        let rendered = render_mic_pair(&scenario, name, &room, arguments.seed, arguments.duration)?;
        write_stereo_wav(&rendered, &out.join(format!("{name}.wav")))?;
        let given = serde_json::to_string(&spec.descriptor(&scenario.site))?;
        write(out, &format!("{name}.json"), &given)?;
        talkers = rendered.talkers;
    }
    write_truth(out, &scenario, arguments.seed, arguments.duration)?;
    write(out, "scene.json", &scene_json(&talkers).to_string())?;
    write(out, "server.toml", SERVER_TOML)?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

/// `truth.jsonl`: one replay line per truth set.
fn write_truth(out: &Path, scenario: &Scenario, seed: u64, duration_s: f64) -> anyhow::Result<()> {
    let mut text = String::new();
    for line in simulator::replay_lines(scenario, seed, duration_s)? {
        if let ReplayLine::Truth(_) = &line {
            text.push_str(&serde_json::to_string(&line)?);
            text.push('\n');
        }
    }
    write(out, "truth.jsonl", &text)
}

/// `scene.json`: scenario time 0 and each talker's spurts (seconds from it), as `make_scene.py`
/// writes them.
fn scene_json(talkers: &[Talker]) -> serde_json::Value {
    let spurts: Vec<&[(f64, f64)]> = talkers.iter().map(|t| t.spurts.as_slice()).collect();
    serde_json::json!({ "start": START, "spurts": spurts })
}

fn write(out: &Path, name: &str, text: &str) -> anyhow::Result<()> {
    let path = out.join(name);
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))
}
