//! Test utility: the microphone-pair test scene — talkers in a 3 × 3 × 2.5 m room (T60 ≈ 0.15 s by Sabine),
//! two microphones 0.5 m apart, 16 kHz, white sensor noise at a given SNR (the room and the voices are
//! `simulator::render`'s).
#![allow(dead_code)] // each test crate includes this file and uses a different part of it

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use simulator::render::room_acoustics::{convolve, true_tdoa, ShoeboxRoom};
use simulator::render::speech::{speech_like, Voice};

/// Sample rate of every scene, Hz.
pub const SAMPLE_RATE: u32 = 16_000;
/// Speed of sound used to build scenes, m/s.
pub const SPEED_OF_SOUND: f64 = 343.0;
/// Room dimensions, m.
pub const ROOM_SIZE: [f64; 3] = [3.0, 3.0, 2.5];
/// Target reverberation time, s.
pub const T60: f64 = 0.15;
/// Microphone 1 and microphone 2, 0.5 m apart along x.
pub const MICS: [[f64; 3]; 2] = [[1.25, 1.4, 1.2], [1.75, 1.4, 1.2]];
/// Room impulse responses are cut after this many seconds (beyond T60, the tail is below −60 dB).
const RESPONSE_SECONDS: f64 = 0.25;

/// One talker of a scene, as the test wants it.
pub struct TalkerSpec {
    /// Mouth position, m.
    pub position: [f64; 3],
    /// Speaking interval [start, end) in seconds.
    pub interval: (f64, f64),
    /// Pitch range of the voice.
    pub voice: Voice,
}

/// What the scene knows about a talker: where it is, when it talks and its dry (source) signal.
pub struct TalkerTruth {
    /// Mouth position, m.
    pub position: [f64; 3],
    /// Speaking interval [start, end) in seconds.
    pub interval: (f64, f64),
    /// The protocol TDOA of this talker for `MICS`, s.
    pub tdoa: f64,
    /// The source signal before the room, unit RMS over `interval`.
    pub dry: Vec<f64>,
}

/// A rendered scene: the two microphone signals and the truth behind them.
pub struct Scene {
    /// Signal of microphone 1.
    pub mic1: Vec<f64>,
    /// Signal of microphone 2.
    pub mic2: Vec<f64>,
    /// Every talker of the scene.
    pub talkers: Vec<TalkerTruth>,
}

/// Renders talkers in `room` to both microphones, then adds independent white noise so that the speech-to-noise
/// power ratio over the samples where someone talks is `snr_db` at each microphone.
pub fn render_scene(
    room: &ShoeboxRoom,
    talkers: &[TalkerSpec],
    seconds: f64,
    snr_db: f64,
    seed: u64,
) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let rate = f64::from(SAMPLE_RATE);
    let total_len = (seconds * rate) as usize;
    let response_len = (RESPONSE_SECONDS * rate) as usize;
    let mut mics = [vec![0.0; total_len], vec![0.0; total_len]];
    let mut truths = Vec::new();
    for talker in talkers {
        let dry = speech_like(&mut rng, talker.voice, rate, total_len, talker.interval);
        for (signal, mic) in mics.iter_mut().zip(MICS) {
            let response =
                room.impulse_response(talker.position, mic, rate, SPEED_OF_SOUND, response_len);
            for (out, wet) in signal.iter_mut().zip(convolve(&dry, &response)) {
                *out += wet;
            }
        }
        truths.push(TalkerTruth {
            position: talker.position,
            interval: talker.interval,
            tdoa: true_tdoa(talker.position, MICS[0], MICS[1], SPEED_OF_SOUND),
            dry,
        });
    }
    let speaking = |i: usize| {
        let t = i as f64 / rate;
        talkers
            .iter()
            .any(|talker| t >= talker.interval.0 && t < talker.interval.1)
    };
    for signal in &mut mics {
        let (energy, count) = signal
            .iter()
            .enumerate()
            .filter(|&(i, _)| speaking(i))
            .fold((0.0, 0usize), |(e, n), (_, x)| (e + x * x, n + 1));
        let noise_power = energy / count.max(1) as f64 / 10f64.powf(snr_db / 10.0);
        let noise = Normal::new(0.0, noise_power.sqrt()).expect("finite, non-negative deviation");
        signal.iter_mut().for_each(|x| *x += noise.sample(&mut rng));
    }
    let [mic1, mic2] = mics;
    Scene {
        mic1,
        mic2,
        talkers: truths,
    }
}

/// Whether `talker` is audible in the frame `[start, start + len)`: the frame lies inside its speaking interval
/// by at least half and the dry signal's power there is at least a tenth (−10 dB) of its average power (1), so
/// that a frame falling into a pause between syllables does not count as one where the talker talks.
pub fn talker_active_in_frame(talker: &TalkerTruth, start: usize, len: usize) -> bool {
    let rate = f64::from(SAMPLE_RATE);
    let (from, to) = (
        (talker.interval.0 * rate) as usize,
        (talker.interval.1 * rate) as usize,
    );
    let overlap = (start + len).min(to).saturating_sub(start.max(from));
    if 2 * overlap < len {
        return false;
    }
    let power = talker.dry[start..start + len]
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        / len as f64;
    power >= 0.1
}
