//! Track manager: no flicker under alternating sensors with misses, M-of-N
//! confirmation, deletion after K sets or max_coast_s, checkpointable state.

mod common;

use common::mixture_of;
use gmphd::extract::{StateExtractor, WeightThresholdExtractor};
use gmphd::tracks::{TrackError, TrackManager, TrackManagerConfig};
use gmphd::{GaussianMixture, Label};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const P_DETECT: f64 = 0.8;
const P_SURVIVE: f64 = 0.99;
/// `p_D g(z|x) / κ` for a detection of the object: a well-separated return.
const LIKELIHOOD_RATIO: f64 = 50.0;

/// The weight a GM-PHD update gives one isolated object: `(1 − p_D) w` on a
/// miss, `r w / (1 + r w)` on a detection (the clutter intensity dominates the rest).
fn updated_weight(predicted: f64, detected: bool) -> f64 {
    if detected {
        LIKELIHOOD_RATIO * predicted / (1.0 + LIKELIHOOD_RATIO * predicted)
    } else {
        (1.0 - P_DETECT) * predicted
    }
}

/// Two cameras alternate sets every 50 ms, each detecting the object with p_D 0.8.
/// Per-set extraction (w > 0.5) loses the object after every miss; the manager's
/// confirmed track stays.
#[test]
fn alternating_cameras_flicker_per_set_but_not_as_tracks() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    let extractor = WeightThresholdExtractor::default();
    let mut weight = 0.0;
    let (mut extraction_dropouts, mut track_dropouts, mut extraction_reappearances) = (0, 0, 0);
    let mut extracted_before = false;
    let sets = 400;
    for set in 0..sets {
        let time = set as f64 * 0.05;
        // A birth component seeds the object at the first set.
        let predicted = if set == 0 { 0.2 } else { P_SURVIVE * weight };
        weight = updated_weight(predicted, rng.gen_bool(P_DETECT));
        let mixture = mixture_of(&[(1, weight)]);
        manager.update(time, &mixture).unwrap();
        let extracted = !extractor.extract(&mixture).unwrap().is_empty();
        // Count from the set the manager first confirmed the track.
        if manager.confirmed_tracks().count() > 0 || track_dropouts > 0 {
            if !extracted {
                extraction_dropouts += 1;
            }
            if extracted && !extracted_before {
                extraction_reappearances += 1;
            }
            if manager.confirmed_tracks().all(|t| t.label != Label(1)) {
                track_dropouts += 1;
            }
        }
        extracted_before = extracted;
    }
    println!(
        "{sets} sets, p_D {P_DETECT}: per-set extraction missing in {extraction_dropouts} sets \
         (track reappears {extraction_reappearances} times); track manager drop-outs: {track_dropouts}"
    );
    assert!(
        extraction_dropouts > 20,
        "the per-set extraction should flicker"
    );
    assert_eq!(track_dropouts, 0);
    let track = manager.confirmed_tracks().next().unwrap();
    assert_eq!(track.first_seen, 0.0);
}

/// After the object leaves, every set is a miss: 0.99 → 0.198 → 0.039 → … The
/// weight is below 0.15 from the second miss on, and the track is deleted at the
/// K-th (6th) consecutive set below — 7 sets after the object left.
#[test]
fn deletion_after_k_consecutive_low_sets() {
    let config = TrackManagerConfig::default();
    let mut manager = TrackManager::new(config).unwrap();
    let mut weight = 0.99;
    for set in 0..5 {
        manager
            .update(set as f64 * 0.05, &mixture_of(&[(1, weight)]))
            .unwrap();
    }
    assert_eq!(manager.confirmed_tracks().count(), 1);
    let mut deleted_at = None;
    for set in 5..20 {
        weight = updated_weight(P_SURVIVE * weight, false);
        let events = manager
            .update(set as f64 * 0.05, &mixture_of(&[(1, weight)]))
            .unwrap();
        if events.deleted.contains(&Label(1)) {
            deleted_at = Some(set - 4);
            break;
        }
        assert_eq!(
            manager.tracks().count(),
            1,
            "still coasting after {} misses",
            set - 4
        );
    }
    assert_eq!(deleted_at, Some(1 + config.delete_after_sets));
    assert_eq!(manager.tracks().count(), 0);
}

/// With a slow sensor (one set per second) the time limit deletes first: the
/// weight is below the threshold from t = 11 s, and the track goes at t = 13 s,
/// max_coast_s = 2 s later, after only 3 low sets (K = 6).
#[test]
fn deletion_after_max_coast_seconds_with_slow_sets() {
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    for t in 0..10 {
        manager.update(t as f64, &mixture_of(&[(1, 0.95)])).unwrap();
    }
    // t = 10: one miss (0.19, not low yet); then 0.04, 0.008, … from t = 11.
    let mut weight = 0.95;
    for t in 10..20 {
        weight *= 1.0 - P_DETECT;
        let events = manager
            .update(t as f64, &mixture_of(&[(1, weight)]))
            .unwrap();
        if t < 13 {
            assert!(events.deleted.is_empty(), "deleted too early at t = {t}");
        } else {
            assert_eq!(events.deleted, vec![Label(1)], "t = {t}");
            let track_count = manager.tracks().count();
            assert_eq!(track_count, 0);
            return;
        }
    }
    panic!("track never deleted");
}

#[test]
fn confirmation_needs_m_hits_in_the_last_n_sets() {
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    // Label 2 hits once then stays at 0.3: tentative, dropped once no hit remains
    // in the window of N = 4 sets. Label 3 hits at sets 0 and 2: confirmed at 2.
    let sequence = [[0.6, 0.6], [0.3, 0.3], [0.3, 0.7], [0.3, 0.3], [0.3, 0.3]];
    let mut log = Vec::new();
    for (set, [w2, w3]) in sequence.iter().enumerate() {
        let events = manager
            .update(set as f64, &mixture_of(&[(2, *w2), (3, *w3)]))
            .unwrap();
        log.push((events.created, events.confirmed, events.deleted));
    }
    assert_eq!(log[0].0, vec![Label(2), Label(3)]);
    assert_eq!(log[2].1, vec![Label(3)]);
    assert!(log.iter().all(|e| !e.1.contains(&Label(2))));
    assert_eq!(log[4].2, vec![Label(2)], "window [0.3; 4] has no hit");
    assert_eq!(
        manager.recent_weights(Label(3)),
        Some(vec![0.3, 0.7, 0.3, 0.3])
    );
}

/// With `confirm_at_once_threshold`, one set above it confirms (MATLAB `trackerPHD`'s rule);
/// a label the caller marks as split off from a confirmed track still needs M hits.
#[test]
fn a_strong_single_set_confirms_at_once_unless_split_off() {
    let config = TrackManagerConfig {
        confirm_at_once_threshold: Some(0.8),
        ..TrackManagerConfig::default()
    };
    let mut manager = TrackManager::new(config).unwrap();
    let mixture = mixture_of(&[(2, 0.9), (3, 0.7), (4, 0.9)]);
    let split_off = |label: Label| label != Label(4);
    let events = manager
        .update_scoped(0.0, &mixture, &|_| true, &split_off)
        .unwrap();
    assert_eq!(events.created, vec![Label(2), Label(3), Label(4)]);
    assert_eq!(
        events.confirmed,
        vec![Label(2)],
        "0.7 is no strong set, 4 split off"
    );
    let events = manager
        .update_scoped(1.0, &mixture, &|_| true, &split_off)
        .unwrap();
    assert_eq!(events.confirmed, vec![Label(3), Label(4)], "second hits");

    // Off by default: two hits needed.
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    let events = manager.update(0.0, &mixture_of(&[(2, 0.99)])).unwrap();
    assert!(events.confirmed.is_empty());

    for bad in [0.3, f64::NAN, f64::INFINITY] {
        let config = TrackManagerConfig {
            confirm_at_once_threshold: Some(bad),
            ..TrackManagerConfig::default()
        };
        assert!(
            matches!(TrackManager::new(config), Err(TrackError::InvalidConfig(_))),
            "{bad} below confirm_threshold 0.5 or not finite"
        );
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let bad = TrackManagerConfig {
        confirm_hits: 5,
        confirm_window: 4,
        ..TrackManagerConfig::default()
    };
    assert!(matches!(
        TrackManager::new(bad),
        Err(TrackError::InvalidConfig(_))
    ));
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    manager.update(1.0, &mixture_of(&[(1, 0.9)])).unwrap();
    assert_eq!(
        manager.update(0.5, &mixture_of(&[(1, 0.9)])),
        Err(TrackError::TimeWentBackwards {
            previous: 1.0,
            now: 0.5
        })
    );
    assert!(matches!(
        manager.update(f64::NAN, &GaussianMixture::new()),
        Err(TrackError::NonFiniteTime(_))
    ));
    assert!(matches!(
        manager.update(2.0, &mixture_of(&[(1, -1.0)])),
        Err(TrackError::InvalidWeight { label: 1, .. })
    ));
    // A rejected update leaves the state as it was.
    assert_eq!(manager.last_time(), Some(1.0));
}

#[test]
fn state_survives_a_checkpoint_round_trip() {
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    for (set, w) in [0.9, 0.95, 0.1, 0.05].iter().enumerate() {
        manager
            .update(set as f64 * 0.1, &mixture_of(&[(4, *w)]))
            .unwrap();
    }
    let json = serde_json::to_string(&manager).unwrap();
    let mut restored: TrackManager = serde_json::from_str(&json).unwrap();
    assert_eq!(restored, manager);
    // Both continue identically.
    let next = mixture_of(&[(4, 0.02)]);
    assert_eq!(
        restored.update(0.4, &next).unwrap(),
        manager.update(0.4, &next).unwrap()
    );
    assert_eq!(restored, manager);
}
