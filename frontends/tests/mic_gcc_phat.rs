//! GCC-PHAT delay estimation: the protocol's sign convention, sub-sample accuracy in the free field, and empty
//! sets when there is nothing to localise.

#[path = "support/room_scene.rs"]
mod room_scene;

use frontends::mic::{MicPairConfig, MicPairPipeline, StereoAudio};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use room_scene::{
    render_scene, talker_active_in_frame, Scene, TalkerSpec, MICS, ROOM_SIZE, SAMPLE_RATE,
    SPEED_OF_SOUND,
};
use simulator::render::room_acoustics::{add_fractional_impulse, convolve, ShoeboxRoom};
use simulator::render::speech::Voice;

const RATE: f64 = SAMPLE_RATE as f64;
const MIC_DISTANCE: f64 = 0.5;

/// Gaussian white noise, `len` samples, seeded.
fn white_noise(len: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, 0.3).unwrap();
    (0..len).map(|_| normal.sample(&mut rng)).collect()
}

/// `signal` delayed by a (possibly fractional) number of samples.
fn delayed(signal: &[f64], delay: f64) -> Vec<f64> {
    let mut kernel = vec![0.0; delay.ceil() as usize + 40];
    add_fractional_impulse(&mut kernel, delay, 1.0);
    convolve(signal, &kernel)
}

/// One talker alone in the free field (no walls), at the given SNR in dB.
fn anechoic_talker(position: [f64; 3], seed: u64, snr_db: f64) -> Scene {
    let talker = TalkerSpec {
        position,
        interval: (0.2, 5.8),
        voice: Voice {
            min_pitch: 100.0,
            max_pitch: 250.0,
        },
    };
    render_scene(
        &ShoeboxRoom::anechoic(ROOM_SIZE),
        &[talker],
        6.0,
        snr_db,
        seed,
    )
}

/// The strongest TDOA of every frame in which the scene's only talker is active, in samples.
fn strongest_tdoas_while_active(scene: &Scene, config: MicPairConfig) -> Vec<f64> {
    let audio = StereoAudio::new(SAMPLE_RATE, scene.mic1.clone(), scene.mic2.clone()).unwrap();
    let mut pipeline = MicPairPipeline::new(config, SAMPLE_RATE).unwrap();
    let layout = pipeline.layout();
    let frames = pipeline.process(&audio, 0.0).unwrap();
    let talker = &scene.talkers[0];
    frames
        .iter()
        .enumerate()
        .filter(|(index, _)| {
            talker_active_in_frame(talker, layout.span(*index).start, layout.frame_len())
        })
        .map(|(index, frame)| {
            assert!(!frame.tdoas.is_empty(), "no TDOA in active frame {index}");
            frame.tdoas[0] * RATE
        })
        .collect()
}

#[test]
fn positive_tdoa_when_sound_reaches_mic_2_later() {
    let source = white_noise(16_000, 1);
    let delay_samples = 5.0;
    // White noise is exactly what the speech-presence check rejects, so it is switched off here.
    let mut config = MicPairConfig::new(MIC_DISTANCE);
    config.min_spectral_contrast = 0.0;
    let mut pipeline = MicPairPipeline::new(config, SAMPLE_RATE).unwrap();

    // Mic 2 hears the sound 5 samples after mic 1: the source is closer to mic 1, so tau = +5 samples.
    let mic2_late = StereoAudio::new(
        SAMPLE_RATE,
        delayed(&source, 20.0),
        delayed(&source, 20.0 + delay_samples),
    )
    .unwrap();
    let frames = pipeline.process(&mic2_late, 0.0).unwrap();
    assert_eq!(frames.len(), 3);
    for frame in &frames {
        let strongest = frame.tdoas[0] * RATE;
        println!("mic 2 late by {delay_samples} samples: strongest tau {strongest:+.3} samples");
        assert!((strongest - delay_samples).abs() < 0.05, "{strongest}");
    }

    // Mic 1 late instead: the sign flips.
    let mic1_late = StereoAudio::new(
        SAMPLE_RATE,
        delayed(&source, 20.0 + delay_samples),
        delayed(&source, 20.0),
    )
    .unwrap();
    for frame in pipeline.process(&mic1_late, 0.0).unwrap() {
        let strongest = frame.tdoas[0] * RATE;
        assert!((strongest + delay_samples).abs() < 0.05, "{strongest}");
    }
}

#[test]
fn sign_follows_the_protocol_geometry() {
    // Closer to mic 1 → sound reaches mic 2 later → tau = (‖x − m2‖ − ‖x − m1‖)/c > 0, and the mirror image.
    let near_mic1 = [0.8, 1.0, 1.2];
    let near_mic2 = [2.2, 1.0, 1.2];
    for (position, expected_sign) in [(near_mic1, 1.0), (near_mic2, -1.0)] {
        let scene = anechoic_talker(position, 3, 20.0);
        let truth = scene.talkers[0].tdoa * RATE;
        assert_eq!(
            truth.signum(),
            expected_sign,
            "the scene's own truth must follow the protocol"
        );
        let measured = strongest_tdoas_while_active(&scene, MicPairConfig::new(MIC_DISTANCE));
        println!(
            "talker at {position:?}: true tau {truth:+.2} samples, strongest peaks {measured:.2?}"
        );
        assert!(measured.len() >= 15);
        assert!(measured.iter().all(|tau| tau.signum() == expected_sign));
        assert!(measured.iter().all(|tau| (tau - truth).abs() <= 2.0));
    }
}

#[test]
fn end_fire_talkers_are_found_at_plus_minus_d_over_c() {
    let max_lag = MIC_DISTANCE / SPEED_OF_SOUND * RATE;
    let beyond_mic1 = [0.6, MICS[0][1], MICS[0][2]];
    let beyond_mic2 = [2.4, MICS[1][1], MICS[1][2]];
    for (position, expected) in [(beyond_mic1, max_lag), (beyond_mic2, -max_lag)] {
        let scene = anechoic_talker(position, 4, 30.0);
        let measured = strongest_tdoas_while_active(&scene, MicPairConfig::new(MIC_DISTANCE));
        println!("end-fire talker at {position:?}: expected {expected:+.2} samples, strongest peaks {measured:.2?}");
        // Half of an end-fire peak lies outside the searched range, so it is found a little less precisely.
        assert!(measured.len() >= 15);
        assert!(measured.iter().all(|tau| tau.signum() == expected.signum()));
        let close = measured
            .iter()
            .filter(|tau| (*tau - expected).abs() <= 0.5)
            .count();
        assert!(
            close * 10 >= measured.len() * 9,
            "only {close} of {} within 0.5 samples",
            measured.len()
        );
    }
}

#[test]
fn single_anechoic_talker_is_located_within_a_quarter_sample() {
    // An oblique position whose TDOA falls between samples; 30 dB SNR, so that what is measured is the
    // interpolation and refinement, not the noise.
    let scene = anechoic_talker([0.9, 2.2, 1.5], 11, 30.0);
    let truth = scene.talkers[0].tdoa * RATE;
    let measured = strongest_tdoas_while_active(&scene, MicPairConfig::new(MIC_DISTANCE));
    let errors: Vec<f64> = measured.iter().map(|tau| tau - truth).collect();
    let worst = errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    println!(
        "true tau {truth:+.3} samples; {} active frames; error RMS {rms:.3}, worst {worst:.3} samples",
        errors.len()
    );
    assert!(errors.len() >= 15);
    assert!(worst <= 0.25, "worst error {worst} samples");
}

#[test]
fn noise_only_and_silent_frames_give_empty_sets() {
    let mut pipeline = MicPairPipeline::new(MicPairConfig::new(MIC_DISTANCE), SAMPLE_RATE).unwrap();
    let noise = StereoAudio::new(
        SAMPLE_RATE,
        white_noise(160_000, 5),
        white_noise(160_000, 6),
    )
    .unwrap();
    let frames = pipeline.process(&noise, 0.0).unwrap();
    let with_tdoas = frames.iter().filter(|f| !f.tdoas.is_empty()).count();
    println!(
        "independent white noise: {with_tdoas} of {} frames with TDOAs",
        frames.len()
    );
    assert_eq!(frames.len(), 39);
    assert!(
        with_tdoas <= 1,
        "{with_tdoas} noise-only frames produced TDOAs"
    );

    let silence = StereoAudio::new(SAMPLE_RATE, vec![0.0; 16_000], vec![0.0; 16_000]).unwrap();
    for frame in pipeline.process(&silence, 0.0).unwrap() {
        assert!(frame.tdoas.is_empty());
    }
}

/// Eight frames of two white sources, the quiet one at half the loud one's amplitude: mic 2 hears the
/// loud source 8 samples after mic 1 (TDOA +8) and the quiet one 10 before (−10).
fn loud_and_quiet_sources() -> StereoAudio {
    const LEN: usize = 8 * 4096;
    let loud = white_noise(LEN, 11);
    let quiet: Vec<f64> = white_noise(LEN, 12).iter().map(|v| 0.5 * v).collect();
    let sum = |a: Vec<f64>, b: Vec<f64>| -> Vec<f64> {
        a.iter().zip(&b).map(|(x, y)| x + y).take(LEN).collect()
    };
    let mic1 = sum(delayed(&loud, 20.0), delayed(&quiet, 20.0));
    let mic2 = sum(delayed(&loud, 28.0), delayed(&quiet, 10.0));
    StereoAudio::new(SAMPLE_RATE, mic1, mic2).unwrap()
}

/// Two broadband sources at once, one at half the other's amplitude (a quarter of its power: its PHAT
/// peak stands at 0.17 against 0.91): with every peak reported both are found; with a
/// `relative_peak_threshold` of 0.6, or the default 0.9, only the louder, as an echo of that strength
/// would be.
#[test]
fn a_much_quieter_source_is_left_out_by_default() {
    let audio = loud_and_quiet_sources();
    let found =
        |tdoas: &[f64], samples: f64| tdoas.iter().any(|tau| (tau * RATE - samples).abs() <= 0.5);
    for (relative_peak_threshold, quiet_expected) in [(0.0, true), (0.6, false), (0.9, false)] {
        let mut config = MicPairConfig::new(MIC_DISTANCE);
        config.min_spectral_contrast = 0.0; // white noise is the signal here
                                            // Whole-frame PHAT: there a peak's height follows its source's share of the power (the
                                            // coherence weighting of a noise-free mix gives both sources nearly full height).
        config.segment_duration = 0.0;
        assert_eq!(
            MicPairConfig::new(MIC_DISTANCE).relative_peak_threshold,
            0.9
        );
        config.relative_peak_threshold = relative_peak_threshold;
        let mut pipeline = MicPairPipeline::new(config, SAMPLE_RATE).unwrap();
        let frames = pipeline.process(&audio, 0.0).unwrap();
        assert_eq!(frames.len(), 8);
        for frame in &frames {
            let in_samples: Vec<f64> = frame.tdoas.iter().map(|tau| tau * RATE).collect();
            println!("relative_peak_threshold {relative_peak_threshold}: {in_samples:.2?}");
            assert!(found(&frame.tdoas, 8.0), "{in_samples:?}");
            assert_eq!(found(&frame.tdoas, -10.0), quiet_expected, "{in_samples:?}");
        }
    }
}

/// A weaker peak's TDOA is trusted less: the strongest peak of each frame keeps the descriptor's
/// variance (factor 1) and the quieter source's gets Knapp & Carter's larger one.
#[test]
fn the_quieter_sources_tdoa_gets_the_wider_variance() {
    let audio = loud_and_quiet_sources();
    let mut config = MicPairConfig::new(MIC_DISTANCE);
    config.min_spectral_contrast = 0.0;
    config.segment_duration = 0.0;
    config.relative_peak_threshold = 0.0;
    let mut pipeline = MicPairPipeline::new(config, SAMPLE_RATE).unwrap();
    for frame in pipeline.process(&audio, 0.0).unwrap() {
        assert_eq!(frame.relative_variances.len(), frame.tdoas.len());
        let factor_at = |samples: f64| {
            let i = frame
                .tdoas
                .iter()
                .position(|tau| (tau * RATE - samples).abs() <= 0.5)
                .expect("both sources are reported");
            frame.relative_variances[i]
        };
        println!("loud {:.2}, quiet {:.2}", factor_at(8.0), factor_at(-10.0));
        assert_eq!(factor_at(8.0), 1.0);
        assert!(factor_at(-10.0) > 1.5, "quiet {}", factor_at(-10.0));
    }
}
