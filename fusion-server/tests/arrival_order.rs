//! Exactness of out-of-order processing: whatever order the sets of the default room arrive in
//! (within the history kept), the final tracks, every settled track set and `replay`'s output
//! are bit for bit those of processing the same sets in stamp order.

use fusion_server::config::ServerConfig;
use fusion_server::engine::Engine;
use fusion_server::replay::replay;
use protocol::{MeasurementSet, ReplayLine, SensorDescriptor};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const T0: f64 = 1_763_700_000.0;

fn room(seed: u64, duration_s: f64) -> (Vec<SensorDescriptor>, Vec<MeasurementSet>) {
    let mut scenario = simulator::default_room();
    scenario.start = Some(T0);
    let mut descriptors = Vec::new();
    let mut sets = Vec::new();
    for line in simulator::replay_lines(&scenario, seed, duration_s).unwrap() {
        match line {
            ReplayLine::Descriptor(d) => descriptors.push(d),
            ReplayLine::Measurements(s) => sets.push(s),
            ReplayLine::Truth(_) => {}
        }
    }
    (descriptors, sets)
}

/// The arrival order of `sets` when each is delayed by its sensor's fixed delay plus jitter.
fn delayed(sets: &[MeasurementSet], seed: u64, max_jitter_s: f64) -> Vec<(f64, MeasurementSet)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut arrivals: Vec<(f64, MeasurementSet)> = sets
        .iter()
        .map(|set| {
            let fixed = match set.sensor.as_str().as_bytes().last() {
                Some(b'1') => 0.4,
                Some(b'2') => 1.0,
                _ => 0.0,
            };
            (
                set.stamp + fixed + rng.gen_range(0.0..max_jitter_s),
                set.clone(),
            )
        })
        .collect();
    arrivals.sort_by(|a, b| a.0.total_cmp(&b.0));
    arrivals
}

/// Runs a live-mode engine (the wall clock being the arrival time), stepping after each
/// arrival or each `batch` arrivals; returns every settled track set as JSON and the engine.
fn run(
    descriptors: &[SensorDescriptor],
    arrivals: &[(f64, MeasurementSet)],
    batch: usize,
) -> (Vec<String>, Engine) {
    run_with_change(descriptors, arrivals, batch, None)
}

/// A sensor's new descriptor, announced just before its first set stamped at or after `from`.
struct Change {
    descriptor: SensorDescriptor,
    from: f64,
}

/// [`run`], with the sensor of `change` announcing its new descriptor part-way.
fn run_with_change(
    descriptors: &[SensorDescriptor],
    arrivals: &[(f64, MeasurementSet)],
    batch: usize,
    mut change: Option<Change>,
) -> (Vec<String>, Engine) {
    let mut engine = Engine::new(ServerConfig::default(), T0, false).unwrap();
    for d in descriptors {
        engine.learn_descriptor(d.clone(), false).unwrap();
    }
    let mut settled = Vec::new();
    for chunk in arrivals.chunks(batch) {
        for (arrived, set) in chunk {
            let due = change
                .as_ref()
                .is_some_and(|c| c.descriptor.sensor == set.sensor && set.stamp >= c.from);
            if due {
                let Change { descriptor, .. } = change.take().unwrap();
                engine.learn_descriptor(descriptor, false).unwrap();
            }
            engine.admit_decoded(None, set.clone(), *arrived).unwrap();
        }
        engine.step(chunk.last().unwrap().0);
        settled.extend(engine.take_settled());
    }
    engine.flush(arrivals.last().unwrap().0);
    settled.extend(engine.settle_all());
    let json = settled
        .iter()
        .map(|t| serde_json::to_string(t).unwrap())
        .collect();
    (json, engine)
}

#[test]
fn delayed_sensors_give_the_in_order_result_bit_for_bit() {
    let (descriptors, sets) = room(11, 12.0);
    let in_order: Vec<(f64, MeasurementSet)> = sets.iter().map(|s| (s.stamp, s.clone())).collect();
    let (expected, reference) = run(&descriptors, &in_order, 1);
    assert_eq!(expected.len(), sets.len());
    for (seed, batch) in [(1, 1), (2, 3), (3, 16)] {
        let arrivals = delayed(&sets, seed, 0.3);
        let (got, engine) = run(&descriptors, &arrivals, batch);
        assert_eq!(got.len(), expected.len(), "seed {seed}");
        let first_difference = got.iter().zip(&expected).position(|(a, b)| a != b);
        assert_eq!(first_difference, None, "seed {seed}, batch {batch}");
        assert_eq!(
            engine.checkpoint(),
            reference.checkpoint(),
            "final state, seed {seed}"
        );
        let status = engine.status(T0 + 20.0);
        let rollbacks: u64 = status.sensors.iter().map(|s| s.rollbacks).sum();
        let late: u64 = status.sensors.iter().map(|s| s.late).sum();
        let processed: u64 = status.sensors.iter().map(|s| s.processed).sum();
        println!("seed {seed}, batches of {batch}: {rollbacks} rollbacks, {late} late, {processed} processed");
        assert_eq!((late, processed), (0, sets.len() as u64));
        assert!(rollbacks > 0, "the delays must cause rollbacks");
    }
}

/// A sensor that announces a new descriptor (an agent refining its clutter rate and p_D): its
/// sets admitted before keep the old one when a rollback processes them again, so the result is
/// the in-order one whatever the arrival order.
#[test]
fn a_new_descriptor_does_not_reach_back_to_sets_processed_again() {
    let (descriptors, sets) = room(11, 12.0);
    // A sensor without a fixed delay in `delayed`: the delayed cameras' sets make the filter
    // process its earlier sets again after its new descriptor has arrived.
    let mut refined = descriptors
        .iter()
        .find(|d| !matches!(d.sensor.as_str().as_bytes().last(), Some(b'1' | b'2')))
        .unwrap()
        .clone();
    refined.detection_probability *= 0.8;
    refined.clutter_rate += 0.5;
    let change = || {
        Some(Change {
            descriptor: refined.clone(),
            from: T0 + 6.0,
        })
    };
    let in_order: Vec<(f64, MeasurementSet)> = sets.iter().map(|s| (s.stamp, s.clone())).collect();
    let (expected, _) = run_with_change(&descriptors, &in_order, 1, change());
    let (unchanged, _) = run(&descriptors, &in_order, 1);
    assert_ne!(
        expected, unchanged,
        "the new descriptor must change the tracks"
    );
    let arrivals = delayed(&sets, 4, 0.3);
    let (got, _) = run_with_change(&descriptors, &arrivals, 3, change());
    let first_difference = got.iter().zip(&expected).position(|(a, b)| a != b);
    assert_eq!(first_difference, None);
    assert_eq!(got.len(), expected.len());
}

#[test]
fn replay_output_does_not_depend_on_the_order_of_the_file() {
    let (descriptors, sets) = room(5, 8.0);
    let file = |sets: &[MeasurementSet]| {
        let mut out = Vec::new();
        for d in &descriptors {
            serde_json::to_writer(&mut out, &ReplayLine::Descriptor(d.clone())).unwrap();
            out.push(b'\n');
        }
        for s in sets {
            serde_json::to_writer(&mut out, &ReplayLine::Measurements(s.clone())).unwrap();
            out.push(b'\n');
        }
        out
    };
    let mut expected = Vec::new();
    replay(
        ServerConfig::default(),
        file(&sets).as_slice(),
        &mut expected,
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for _ in 0..3 {
        // Shuffle within windows of 40 consecutive sets (about a quarter of a second).
        let mut shuffled = sets.clone();
        for window in shuffled.chunks_mut(40) {
            window.shuffle(&mut rng);
        }
        let mut got = Vec::new();
        replay(
            ServerConfig::default(),
            file(&shuffled).as_slice(),
            &mut got,
        )
        .unwrap();
        assert!(got == expected, "replay output differs for a shuffled file");
    }
}
