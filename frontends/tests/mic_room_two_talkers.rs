//! Two talkers in a reverberant room: the pipeline's TDOA sets contain each active talker's true TDOA.

#[path = "support/room_scene.rs"]
mod room_scene;

use frontends::mic::{MicPairConfig, MicPairPipeline, StereoAudio};
use room_scene::{
    render_scene, talker_active_in_frame, TalkerSpec, MICS, ROOM_SIZE, SAMPLE_RATE, SPEED_OF_SOUND,
    T60,
};
use simulator::render::room_acoustics::{schroeder_t60, ShoeboxRoom};
use simulator::render::speech::Voice;

/// Two samples at 16 kHz: how close a reported peak must be to a talker's true TDOA.
const TOLERANCE_S: f64 = 2.0 / 16_000.0;
/// Per cent of its active frames in which each talker must be among the TDOAs of the default configuration.
const FLOOR_WITH_DEFAULTS: f64 = 50.0;

/// A lower voice on the mic-1 side speaking first, a higher one on the mic-2 side later, overlapping 4.0–7.5 s.
fn two_talkers() -> Vec<TalkerSpec> {
    vec![
        TalkerSpec {
            position: [0.8, 2.3, 1.6],
            interval: (0.3, 7.5),
            voice: Voice {
                min_pitch: 100.0,
                max_pitch: 150.0,
            },
        },
        TalkerSpec {
            position: [2.4, 0.7, 1.5],
            interval: (4.0, 11.7),
            voice: Voice {
                min_pitch: 170.0,
                max_pitch: 250.0,
            },
        },
    ]
}

#[test]
fn room_reverberation_time_is_near_the_target() {
    let room = ShoeboxRoom::with_sabine_t60(ROOM_SIZE, T60);
    let rate = f64::from(SAMPLE_RATE);
    for talker in two_talkers() {
        for mic in MICS {
            let response = room.impulse_response(talker.position, mic, rate, SPEED_OF_SOUND, 8000);
            let measured = schroeder_t60(&response, rate);
            println!(
                "β = {:.3}; talker {:?} → mic {mic:?}: T60 (Schroeder, T20) {measured:.3} s, target {T60} s",
                room.reflection, talker.position
            );
            assert!((measured - T60).abs() <= 0.2 * T60, "T60 {measured} s");
        }
    }
}

/// Seed 7 is the scene the front end was developed on. The margin is not large: with whole-frame PHAT and five peaks, seeds
/// 7–16 give per-talker rates from 74 % to 100 % (mean 87 %), and 3 of those 10 scenes have one talker below
/// 80 %, nearly always in frames where the other talker is louder.
#[test]
fn each_active_talker_is_found_in_most_of_its_frames() {
    // Among every peak of a frame (`relative_peak_threshold` 0, up to four), whole-frame PHAT finds both
    // talkers of this mildly reverberant room (T60 0.15 s) in at least 80 % of their frames (92-96 %); the
    // default coherence-weighted segments, chosen for the default room's T60 of 0.3 s, lose some of the
    // end-fire talker here (85 %) and are held to 70 %. Leaving out peaks below 0.6 of the frame's
    // highest, the quieter talker of a frame in which the other is much louder goes with the echoes (81 %,
    // held to 60 %; 77 % with three peaks a frame, held to 55 %). The defaults leave out peaks below 0.9
    // of the highest (`MicPairConfig::relative_peak_threshold`: the fusion, which keeps a talker through
    // the frames that miss it, gains more from the clutter it is spared than it loses with these misses):
    // the end-fire talker is then found in 58 % of its frames, held to 50 %.
    let every_peak = 0.0;
    let defaults = MicPairConfig::new(0.5);
    let sixty_per_cent = 0.6;
    for (segment_duration, relative_peak_threshold, max_peaks, floor) in [
        (0.0, every_peak, 4, 80.0),
        (defaults.segment_duration, every_peak, 4, 70.0),
        (defaults.segment_duration, sixty_per_cent, 4, 60.0),
        (defaults.segment_duration, sixty_per_cent, 3, 55.0),
        (
            defaults.segment_duration,
            defaults.relative_peak_threshold,
            defaults.max_peaks,
            FLOOR_WITH_DEFAULTS,
        ),
    ] {
        println!("segment_duration {segment_duration} s, relative_peak_threshold {relative_peak_threshold}, max_peaks {max_peaks}:");
        let mut config = defaults.clone();
        config.segment_duration = segment_duration;
        config.relative_peak_threshold = relative_peak_threshold;
        config.max_peaks = max_peaks;
        talkers_found(config, floor);
    }
}

fn talkers_found(config: MicPairConfig, floor: f64) {
    let room = ShoeboxRoom::with_sabine_t60(ROOM_SIZE, T60);
    let scene = render_scene(&room, &two_talkers(), 12.0, 20.0, 7);
    let audio = StereoAudio::new(SAMPLE_RATE, scene.mic1.clone(), scene.mic2.clone()).unwrap();
    let mut pipeline = MicPairPipeline::new(config, SAMPLE_RATE).unwrap();
    let start_time = 1_763_700_000.0;
    let frames = pipeline.process(&audio, start_time).unwrap();
    let layout = pipeline.layout();
    assert_eq!(frames.len(), layout.frame_count(audio.len()));

    for (index, talker) in scene.talkers.iter().enumerate() {
        let (mut active, mut found) = (0, 0);
        for (frame_index, frame) in frames.iter().enumerate() {
            if !talker_active_in_frame(talker, layout.span(frame_index).start, layout.frame_len()) {
                continue;
            }
            active += 1;
            if frame
                .tdoas
                .iter()
                .any(|tau| (tau - talker.tdoa).abs() <= TOLERANCE_S)
            {
                found += 1;
            }
        }
        let percent = 100.0 * f64::from(found) / f64::from(active.max(1));
        println!(
            "talker {} (true TDOA {:+.1} µs = {:+.2} samples): within 2 samples in {found} of {active} active frames = {percent:.1} %",
            index + 1,
            talker.tdoa * 1e6,
            talker.tdoa * f64::from(SAMPLE_RATE)
        );
        assert!(
            active >= 20,
            "talker {} is active in only {active} frames",
            index + 1
        );
        assert!(
            percent >= floor,
            "talker {} found in only {percent:.1} % of its frames",
            index + 1
        );
    }

    let reported: usize = frames.iter().map(|frame| frame.tdoas.len()).sum();
    let empty = frames.iter().filter(|frame| frame.tdoas.is_empty()).count();
    println!(
        "{} frames, {:.2} TDOAs per frame on average, {empty} empty",
        frames.len(),
        reported as f64 / frames.len() as f64
    );
    let max_tdoa = 0.5 / SPEED_OF_SOUND;
    assert!(frames
        .iter()
        .flat_map(|f| &f.tdoas)
        .all(|tau| tau.abs() <= max_tdoa));
}
