//! Track manager: pauses in the data, sets of sensors that cannot see a track, labels that
//! vanish from the intensity, and the anchor a coasting track is predicted from.

mod common;

use common::mixture_of;
use gmphd::tracks::{TrackManager, TrackManagerConfig};
use gmphd::{Gaussian, GaussianMixture, Label};
use nalgebra::{DMatrix, DVector};

/// K so large that only the time limit (max_coast_s = 1 s) deletes.
fn time_limited() -> TrackManagerConfig {
    TrackManagerConfig {
        delete_after_sets: 100,
        max_coast_s: 1.0,
        ..TrackManagerConfig::default()
    }
}

/// A manager whose track with label 1 was confirmed by sets every 0.1 s up to t = 1.0 s.
fn confirmed(config: TrackManagerConfig) -> TrackManager {
    let mut manager = TrackManager::new(config).unwrap();
    for set in 0..=10 {
        manager
            .update(f64::from(set) * 0.1, &mixture_of(&[(1, 0.95)]))
            .unwrap();
    }
    assert!(manager.confirmed_tracks().any(|t| t.label == Label(1)));
    manager
}

/// Time of the set at which label 1's track is deleted, feeding weight `weight` at `times`.
fn deleted_at(manager: &mut TrackManager, times: &[f64], weight: f64) -> Option<f64> {
    for &t in times {
        let events = manager.update(t, &mixture_of(&[(1, weight)])).unwrap();
        if events.deleted.contains(&Label(1)) {
            return Some(t);
        }
    }
    None
}

fn every_tenth(from: f64, to: f64) -> Vec<f64> {
    let steps = ((to - from) / 0.1).round() as usize;
    (0..=steps).map(|i| from + i as f64 * 0.1).collect()
}

/// Low from t = 1.1 s. Sets keep coming: deleted max_coast_s later, at 2.1 s. The same
/// sets with a 1.5 s pause after the first low one: the pause does not count, so the
/// track is still there after it and goes at 1.1 + 1.5 + 1.0 = 3.6 s.
#[test]
fn a_pause_in_the_data_does_not_count_as_coasting() {
    let mut steady = confirmed(time_limited());
    let times = every_tenth(1.1, 4.0);
    let deleted = deleted_at(&mut steady, &times, 0.05).unwrap();
    assert!((deleted - 2.1).abs() < 1e-9, "{deleted}");

    let mut paused = confirmed(time_limited());
    let mut times = vec![1.1];
    times.extend(every_tenth(2.6, 5.0));
    let deleted = deleted_at(&mut paused, &times, 0.05).unwrap();
    assert!((deleted - 3.6).abs() < 1e-9, "{deleted}");
}

/// Labels double as x positions (`mixture_of`); the sensor sees x < 1.5 only.
#[test]
fn sets_that_cannot_see_a_track_neither_make_nor_confirm_nor_delete_it() {
    let sees_label_1 = |x: &DVector<f64>| x[0] < 1.5;
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    // Label 2 has weight but is never in view: no track, while label 1 is confirmed.
    for set in 0..5 {
        let mixture = mixture_of(&[(1, 0.9), (2, 0.9)]);
        manager
            .update_in_view(f64::from(set) * 0.1, &mixture, &sees_label_1)
            .unwrap();
    }
    let labels: Vec<Label> = manager.tracks().map(|t| t.label).collect();
    assert_eq!(labels, vec![Label(1)]);
    assert!(manager.confirmed_tracks().any(|t| t.label == Label(1)));

    // A confirmed track out of view with a low weight is not deleted however many sets
    // pass (they are not evidence); seen again with that weight, it goes after K sets.
    let config = TrackManagerConfig::default();
    let sees_nothing = |_: &DVector<f64>| false;
    for set in 0..(3 * config.delete_after_sets) {
        let t = 1.0 + set as f64 * 0.01;
        let events = manager
            .update_in_view(t, &mixture_of(&[(1, 0.01)]), &sees_nothing)
            .unwrap();
        assert!(events.deleted.is_empty(), "deleted while unseen at {t}");
    }
    let mut low_sets_seen = 0;
    loop {
        low_sets_seen += 1;
        let t = 2.0 + low_sets_seen as f64 * 0.01;
        let events = manager
            .update_in_view(t, &mixture_of(&[(1, 0.01)]), &sees_label_1)
            .unwrap();
        if events.deleted.contains(&Label(1)) {
            break;
        }
        assert!(low_sets_seen < config.delete_after_sets, "never deleted");
    }
    assert_eq!(low_sets_seen, config.delete_after_sets);
}

/// A label no component carries any more: deleted at once — except within max_coast_s
/// after a pause, when the confirmed track coasts on (with weight 0) until the usual rules
/// delete it.
#[test]
fn a_vanished_label_is_deleted_at_once_except_just_after_a_pause() {
    let other = mixture_of(&[(7, 0.01)]);
    let mut steady = confirmed(time_limited());
    let events = steady.update(1.1, &other).unwrap();
    assert_eq!(events.deleted, vec![Label(1)]);

    let mut paused = confirmed(time_limited());
    let events = paused.update(2.5, &other).unwrap();
    assert!(events.deleted.is_empty());
    let track = paused.confirmed_tracks().next().unwrap();
    assert_eq!((track.label, track.weight), (Label(1), 0.0));
    let times = every_tenth(2.6, 5.0);
    let mut deleted = None;
    for &t in &times {
        if paused
            .update(t, &other)
            .unwrap()
            .deleted
            .contains(&Label(1))
        {
            deleted = Some(t);
            break;
        }
    }
    assert!((deleted.unwrap() - 3.5).abs() < 1e-9, "{deleted:?}");
}

fn at(weight: f64, x: f64) -> GaussianMixture {
    GaussianMixture::from_components(vec![Gaussian::new(
        weight,
        DVector::from_vec(vec![x, 0.0]),
        DMatrix::identity(2, 2),
        Label(1),
    )])
}

/// The anchor follows the label while its weight is at least delete_threshold (0.15 by
/// default) and stays put below it, where the label's heaviest component may be clutter's.
#[test]
fn the_anchor_keeps_the_last_state_with_enough_weight() {
    let mut manager = TrackManager::new(TrackManagerConfig::default()).unwrap();
    manager.update(0.0, &at(0.9, 1.0)).unwrap();
    manager.update(0.1, &at(0.2, 2.0)).unwrap();
    manager.update(0.2, &at(0.01, 9.0)).unwrap();
    let anchor = manager.anchor(Label(1)).unwrap();
    assert_eq!((anchor.time_s, anchor.mean[0]), (0.1, 2.0));
    // The reported state is the latest, as before.
    let track = manager.tracks().next().unwrap();
    assert_eq!(track.mean[0], 9.0);
}
