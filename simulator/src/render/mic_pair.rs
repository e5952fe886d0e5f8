//! The raw signal of a scenario's microphone pair: every target talks on a seeded schedule of
//! spurts and pauses (speech-like voices, `speech.rs`), its voice reaches each microphone through
//! the image-source model of the room (`room_acoustics.rs`) from where its mouth is, and white
//! sensor noise sets the signal-to-noise ratio.
//!
//! A walking talker is rendered block by block ([`BLOCK_S`]): each block of its voice is convolved
//! with the room's response from its mouth's position at the block's middle and added to the
//! output, tails overlapping, which is exact for a source that stands still within each block.

use std::ops::Range;

use protocol::SensorModel;
use rand::Rng;
use rand_distr::{Distribution, Normal};

use super::room_acoustics::{convolve, ShoeboxRoom, SINC_HALF_WIDTH};
use super::speech::{speech_like, Voice};
use crate::error::{invalid, ScenarioError};
use crate::scenario::Scenario;
use crate::seeding::StreamKey;
use crate::target::Target;

/// Length of the blocks over which a walking talker is taken to stand still, s: at walking pace
/// (1.4 m/s) it moves 3 cm, under a tenth of a sample of time difference per centimetre of
/// baseline.
pub const BLOCK_S: f64 = 0.02;
/// The early part of a room response, s: the direct path and the reflections of the first
/// metres, which carry the direction; rendered from where the talker is every [`BLOCK_S`].
pub const EARLY_S: f64 = 0.03;
/// How often the diffuse tail of the response follows a walking talker, s.
pub const LATE_BLOCK_S: f64 = 1.0;
/// Half width of the tail's fractional-delay kernels, samples: the tail's thousands of images
/// need no sub-sample precision, and a short kernel makes it four times cheaper.
const LATE_SINC_HALF_WIDTH: usize = 8;
/// How far below the top of the head (a target's position) the mouth is, m.
pub const MOUTH_BELOW_HEAD_M: f64 = 0.12;
/// Room responses are cut after this many seconds at most (beyond T60 they are below −60 dB).
const MAX_RESPONSE_S: f64 = 0.4;

/// The room the microphones hear: its walls, its reverberation and the sensor noise.
#[derive(Debug, Clone, PartialEq)]
pub struct AcousticRoom {
    /// Lower corner of the walls in world coordinates, m.
    pub min: [f64; 3],
    /// Upper corner of the walls, m.
    pub max: [f64; 3],
    /// Reverberation time (Sabine), s; 0 for the free field.
    pub t60_s: f64,
    /// Speech-to-noise power ratio at each microphone over the samples where someone talks, dB.
    pub snr_db: f64,
    /// Samples per second.
    pub sample_rate: u32,
}

impl Default for AcousticRoom {
    /// The default room's walls (5 cm outside the microphones on them), T60 0.3 s, SNR 20 dB,
    /// 16 kHz.
    fn default() -> Self {
        Self {
            min: [-0.05, -0.05, 0.0],
            max: [3.05, 2.05, 2.5],
            t60_s: 0.3,
            snr_db: 20.0,
            sample_rate: 16_000,
        }
    }
}

impl AcousticRoom {
    fn shoebox(&self) -> ShoeboxRoom {
        let size = std::array::from_fn(|i| self.max[i] - self.min[i]);
        if self.t60_s > 0.0 {
            ShoeboxRoom::with_sabine_t60(size, self.t60_s)
        } else {
            ShoeboxRoom::anechoic(size)
        }
    }

    /// A world point in the room's own coordinates (its lower corner at the origin).
    fn local(&self, point: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| point[i] - self.min[i])
    }

    fn contains(&self, point: [f64; 3]) -> bool {
        (0..3).all(|i| point[i] > self.min[i] && point[i] < self.max[i])
    }

    fn response_len(&self) -> usize {
        let seconds = self.t60_s.clamp(0.05, MAX_RESPONSE_S);
        (seconds * f64::from(self.sample_rate)) as usize
    }
}

/// What the renderer knows about one talker.
#[derive(Debug, Clone)]
pub struct Talker {
    /// The target's id.
    pub target: u64,
    /// Scenario times `[start, end)` of its spurts of speech, s.
    pub spurts: Vec<(f64, f64)>,
    /// Its voice before the room: unit RMS over each spurt, silent elsewhere.
    pub dry: Vec<f64>,
}

impl Talker {
    /// Whether the talker is heard in the samples `[start, start + len)`: they lie in a spurt by
    /// at least half and the voice's power there is at least a tenth (−10 dB) of its average, so
    /// that a pause between two syllables does not count as talking.
    pub fn is_active(&self, start: usize, len: usize, sample_rate: u32) -> bool {
        let rate = f64::from(sample_rate);
        let end = (start + len).min(self.dry.len());
        let inside: usize = self
            .spurts
            .iter()
            .map(|&(a, b)| {
                let (a, b) = ((a * rate) as usize, (b * rate) as usize);
                end.min(b).saturating_sub(start.max(a))
            })
            .sum();
        if 2 * inside < len || start >= end {
            return false;
        }
        let power = self.dry[start..end].iter().map(|x| x * x).sum::<f64>() / len as f64;
        power >= 0.1
    }
}

/// A rendered microphone pair: both signals from scenario time 0 and the talkers behind them.
#[derive(Debug, Clone)]
pub struct RenderedPair {
    /// Samples per second.
    pub sample_rate: u32,
    /// Microphone 1 of the descriptor.
    pub mic1: Vec<f64>,
    /// Microphone 2 of the descriptor.
    pub mic2: Vec<f64>,
    /// Every target that talks, with its schedule and voice.
    pub talkers: Vec<Talker>,
}

/// When a target talks: spurts of 1–3 s separated by pauses of 0.5–2.5 s, from its appearance to
/// its disappearance (or `duration_s`), drawn from the stream `(seed, "talk", target id)`.
pub fn talk_spurts(seed: u64, target: &Target, duration_s: f64) -> Vec<(f64, f64)> {
    let mut rng = StreamKey::new(seed, "talk").with(target.id).rng();
    let end = target.disappear_s.unwrap_or(duration_s).min(duration_s);
    let mut spurts = Vec::new();
    let mut t = target.appear_s + rng.gen_range(0.2..1.0);
    while t < end {
        let spurt_end = (t + rng.gen_range(1.0..3.0)).min(end);
        spurts.push((t, spurt_end));
        t = spurt_end + rng.gen_range(0.5..2.5);
    }
    spurts
}

/// The voices of every target of the scenario, `len` samples at `sample_rate`.
fn talkers(scenario: &Scenario, seed: u64, len: usize, sample_rate: u32) -> Vec<Talker> {
    let duration_s = len as f64 / f64::from(sample_rate);
    scenario
        .targets
        .iter()
        .map(|target| {
            let spurts = talk_spurts(seed, target, duration_s);
            let mut rng = StreamKey::new(seed, "voice").with(target.id).rng();
            // Voices from low (male) to high (female) pitch ranges.
            let low = rng.gen_range(90.0..200.0);
            let voice = Voice {
                min_pitch: low,
                max_pitch: low * 1.4,
            };
            let mut dry = vec![0.0; len];
            for &spurt in &spurts {
                let part = speech_like(&mut rng, voice, f64::from(sample_rate), len, spurt);
                dry.iter_mut().zip(part).for_each(|(d, p)| *d += p);
            }
            Talker {
                target: target.id,
                spurts,
                dry,
            }
        })
        .collect()
}

/// Renders `duration_s` seconds of the scenario's microphone pair `sensor` in `room`, for run
/// `seed` (the same truth as the simulated measurement sets of that run).
pub fn render_mic_pair(
    scenario: &Scenario,
    sensor: &str,
    room: &AcousticRoom,
    seed: u64,
    duration_s: f64,
) -> Result<RenderedPair, ScenarioError> {
    let (index, spec) = scenario.sensor(sensor)?;
    let key = format!("sensors[{index}].model");
    let SensorModel::MicPair(model) = &spec.model else {
        return Err(invalid(key, "not a mic_pair sensor"));
    };
    if let Some(outside) = model.mics.iter().find(|m| !room.contains(**m)) {
        return Err(invalid(
            key,
            format!("microphone at {outside:?} is not inside the room's walls"),
        ));
    }
    let rate = room.sample_rate;
    let len = (duration_s * f64::from(rate)) as usize;
    let talkers = talkers(scenario, seed, len, rate);
    let mut mics = [vec![0.0; len], vec![0.0; len]];
    for (out, mic) in mics.iter_mut().zip(model.mics) {
        let listener = Listener {
            room,
            shoebox: room.shoebox(),
            mic,
            speed_of_sound: model.speed_of_sound,
        };
        for (index, talker) in talkers.iter().enumerate() {
            let head_at = |t: f64| scenario.position_of(index, seed, t);
            add_reverberant(out, talker, &head_at, &listener);
        }
    }
    let mut noise_rng = StreamKey::new(seed, "mic noise").with_text(sensor).rng();
    for signal in &mut mics {
        add_noise(signal, &talkers, room, &mut noise_rng);
    }
    let [mic1, mic2] = mics;
    Ok(RenderedPair {
        sample_rate: rate,
        mic1,
        mic2,
        talkers,
    })
}

/// One microphone in the room, and how it hears a voice.
struct Listener<'a> {
    room: &'a AcousticRoom,
    shoebox: ShoeboxRoom,
    mic: [f64; 3],
    speed_of_sound: f64,
}

impl Listener<'_> {
    /// Adds a voice as heard here through the room's images with delays in `delays` (samples),
    /// `block` samples at a time, each block from where `mouth_at` says the mouth is at its middle
    /// (nothing where it says `None`).
    fn add(
        &self,
        out: &mut [f64],
        dry: &[f64],
        mouth_at: &impl Fn(f64) -> Option<[f64; 3]>,
        delays: Range<usize>,
        block: usize,
        half_width: usize,
    ) {
        let rate = f64::from(self.room.sample_rate);
        let response_len = delays.end;
        for start in (0..dry.len()).step_by(block.max(1)) {
            let end = (start + block).min(dry.len());
            let voice = &dry[start..end];
            if voice.iter().all(|&x| x == 0.0) {
                continue;
            }
            let Some(mouth) = mouth_at((start + end) as f64 / 2.0 / rate) else {
                continue;
            };
            let response = self.shoebox.impulse_response_part(
                self.room.local(mouth),
                self.room.local(self.mic),
                rate,
                self.speed_of_sound,
                delays.clone(),
                half_width,
            );
            let mut padded = voice.to_vec();
            padded.resize(voice.len() + response_len, 0.0);
            for (o, wet) in out[start..].iter_mut().zip(convolve(&padded, &response)) {
                *o += wet;
            }
        }
    }
}

/// Adds `talker`'s voice as heard at `mic`: the direct path and first reflections (the
/// [`EARLY_S`] that carry the direction) from where the mouth is every [`BLOCK_S`], the diffuse
/// tail, almost all of the images, only every [`LATE_BLOCK_S`].
fn add_reverberant(
    out: &mut [f64],
    talker: &Talker,
    head_at: &dyn Fn(f64) -> [f64; 3],
    listener: &Listener,
) {
    let room = listener.room;
    let rate = f64::from(room.sample_rate);
    let mouth_at = |t: f64| {
        let mut mouth = head_at(t);
        mouth[2] -= MOUTH_BELOW_HEAD_M;
        room.contains(mouth).then_some(mouth)
    };
    let response_len = room.response_len();
    let early_len = ((EARLY_S * rate) as usize).min(response_len);
    let block = |seconds: f64| (seconds * rate) as usize;
    let (early, late) = (0..early_len, early_len..response_len);
    listener.add(
        out,
        &talker.dry,
        &mouth_at,
        early,
        block(BLOCK_S),
        SINC_HALF_WIDTH,
    );
    listener.add(
        out,
        &talker.dry,
        &mouth_at,
        late,
        block(LATE_BLOCK_S),
        LATE_SINC_HALF_WIDTH,
    );
}

/// Adds white noise so that the speech power over the samples where someone talks is
/// `room.snr_db` above the noise.
fn add_noise(signal: &mut [f64], talkers: &[Talker], room: &AcousticRoom, rng: &mut impl Rng) {
    let rate = f64::from(room.sample_rate);
    let talking = |i: usize| {
        let t = i as f64 / rate;
        talkers
            .iter()
            .any(|talker| talker.spurts.iter().any(|&(a, b)| t >= a && t < b))
    };
    let (energy, count) = signal
        .iter()
        .enumerate()
        .filter(|&(i, _)| talking(i))
        .fold((0.0, 0usize), |(e, n), (_, x)| (e + x * x, n + 1));
    let noise_power = energy / count.max(1) as f64 / 10f64.powf(room.snr_db / 10.0);
    let noise = Normal::new(0.0, noise_power.sqrt().max(1e-12)).expect("finite deviation");
    signal.iter_mut().for_each(|x| *x += noise.sample(rng));
}
