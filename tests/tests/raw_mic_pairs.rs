//! The default room's four microphone pairs rendered from the truth (speech-like talkers walking
//! in a reverberant room, `simulator::render`) and run through the mic-pair front end: how often
//! each talking target's time difference is among the frame's TDOAs, and how many TDOAs the front
//! end emits that no talker explains (the clutter its descriptor should announce).

use frontends::mic::{MicPairConfig, MicPairPipeline, StereoAudio};
use protocol::SensorModel;
use simulator::render::{render_mic_pair, AcousticRoom, RenderedPair};

/// Seconds rendered: every target of the default room has appeared and talked by then.
const SECONDS: f64 = 16.0;
/// A TDOA within two samples (at 16 kHz) of a talker's true one finds it.
const TOLERANCE_S: f64 = 2.0 / 16_000.0;
const PAIRS: [&str; 4] = ["mics_s", "mics_e", "mics_n", "mics_w"];

/// What the front end made of one pair's signal.
#[derive(Debug, Default)]
struct PairFigures {
    /// (talker, frame) pairs in which the talker talks.
    active: usize,
    /// Of those, the ones whose true TDOA is among the frame's.
    found: usize,
    frames: usize,
    tdoas: usize,
    /// TDOAs within the tolerance of no talker who talks in that frame.
    unexplained: usize,
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

fn true_tdoa(position: [f64; 3], mics: [[f64; 3]; 2], c: f64) -> f64 {
    (distance(position, mics[1]) - distance(position, mics[0])) / c
}

fn figures(pair: &str, seed: u64) -> PairFigures {
    let scenario = simulator::default_room();
    let room = AcousticRoom::default();
    let rendered: RenderedPair = render_mic_pair(&scenario, pair, &room, seed, SECONDS).unwrap();
    let (_, spec) = scenario.sensor(pair).unwrap();
    let SensorModel::MicPair(model) = &spec.model else {
        panic!("{pair} is a mic pair")
    };
    let baseline = distance(model.mics[0], model.mics[1]);
    let audio = StereoAudio::new(rendered.sample_rate, rendered.mic1, rendered.mic2).unwrap();
    let mut pipeline =
        MicPairPipeline::new(MicPairConfig::new(baseline), rendered.sample_rate).unwrap();
    let frames = pipeline.process(&audio, 0.0).unwrap();
    let layout = pipeline.layout();
    let rate = f64::from(rendered.sample_rate);
    let mut out = PairFigures::default();
    for (index, frame) in frames.iter().enumerate() {
        let span = layout.span(index);
        let middle = (span.start as f64 + layout.frame_len() as f64 / 2.0) / rate;
        out.frames += 1;
        out.tdoas += frame.tdoas.len();
        let mut explained = vec![false; frame.tdoas.len()];
        for (index, talker) in rendered.talkers.iter().enumerate() {
            if !talker.is_active(span.start, layout.frame_len(), rendered.sample_rate) {
                continue;
            }
            let mut mouth = scenario.position_of(index, seed, middle);
            mouth[2] -= simulator::render::mic_pair::MOUTH_BELOW_HEAD_M;
            let tau = true_tdoa(mouth, model.mics, model.speed_of_sound);
            out.active += 1;
            let mut hit = false;
            for (i, measured) in frame.tdoas.iter().enumerate() {
                if (measured - tau).abs() <= TOLERANCE_S {
                    explained[i] = true;
                    hit = true;
                }
            }
            out.found += usize::from(hit);
        }
        out.unexplained += explained.iter().filter(|e| !**e).count();
    }
    out
}

#[test]
fn rendered_talkers_are_heard_by_every_pair() {
    let seed = 1;
    let mut total_found = 0.0;
    for pair in PAIRS {
        let f = figures(pair, seed);
        let found = f.found as f64 / f.active.max(1) as f64;
        println!(
            "{pair}: {} frames, talker found in {:.0} % of {} (talker, frame) pairs; {:.2} TDOAs per frame, {:.2} of them unexplained",
            f.frames,
            100.0 * found,
            f.active,
            f.tdoas as f64 / f.frames as f64,
            f.unexplained as f64 / f.frames as f64,
        );
        assert!(f.active > 0, "{pair}: nobody talked");
        total_found += found;
    }
    let mean = total_found / PAIRS.len() as f64;
    println!(
        "mean share of talking (talker, frame) pairs found: {:.0} %",
        100.0 * mean
    );
    // A floor under today's figure (44 % for seed 1 with at most three peaks a frame, the default, and
    // 1.3 unexplained TDOAs per frame; 50 % and 1.8 with four): it catches a front end or a renderer
    // gone worse. Reverberation at T60 0.3 s and a second talker often put a reflection's peak above
    // the direct path's.
    assert!(mean >= 0.4, "only {:.0} % found", 100.0 * mean);
}

#[test]
fn rendering_is_deterministic() {
    let scenario = simulator::default_room();
    let room = AcousticRoom::default();
    let a = render_mic_pair(&scenario, "mics_e", &room, 3, 3.0).unwrap();
    let b = render_mic_pair(&scenario, "mics_e", &room, 3, 3.0).unwrap();
    assert_eq!(a.mic1, b.mic1);
    assert_eq!(a.mic2, b.mic2);
    let c = render_mic_pair(&scenario, "mics_e", &room, 4, 3.0).unwrap();
    assert_ne!(a.mic1, c.mic1);
    assert!(render_mic_pair(&scenario, "cam1", &room, 3, 1.0).is_err());
}
