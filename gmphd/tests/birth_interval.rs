//! `GmPhdFilter::with_birth_interval`: static births added at most once per interval, for
//! the whole time owed, so the birth mass per second is unchanged.

use gmphd::{
    BirthTiming, ConstantVelocity, FilterConfig, GmPhdFilter, GridBirth, GridBirthConfig,
    PruneMergeCap, Survival, UnscentedParams,
};

const RATE: f64 = 0.2;

/// A 2 × 2 × 1 grid birth of `RATE` objects per second; nothing dies, nothing is pruned.
fn filter(interval_s: f64) -> Result<GmPhdFilter, gmphd::FilterError> {
    let grid = GridBirth::new(&GridBirthConfig {
        region_min: vec![0.0, 0.0, 0.0],
        region_max: vec![10.0, 10.0, 3.0],
        cells: vec![2, 2, 1],
        state_dim: 6,
        velocity_std: 1.0,
        extra_std: 0.0,
        total_rate: RATE,
        timing: BirthTiming::PerSecond,
    })?;
    GmPhdFilter::new(
        Box::new(ConstantVelocity::new(3, 0.5)?),
        Box::new(grid),
        Box::new(PruneMergeCap::new(0.0, 0.0, 100_000)?),
        FilterConfig {
            survival: Survival::PerStep(1.0),
            unscented: UnscentedParams::default(),
        },
        0.0,
    )?
    .with_birth_interval(interval_s)
}

#[test]
fn births_come_every_interval_with_the_mass_of_the_time_owed() {
    let mut every = filter(0.0).unwrap();
    let mut batched = filter(0.1).unwrap();
    let mut additions = 0;
    for step in 1..=250 {
        // 4 ms between sets: 240 sets per second among 8 sensors.
        let t = step as f64 * 0.004;
        let before = batched.intensity().len();
        every.predict_to(t).unwrap();
        batched.predict_to(t).unwrap();
        if batched.intensity().len() > before {
            additions += 1;
            assert_eq!(batched.state().birth_owed_s, 0.0);
        }
        // Mass added so far + mass still owed = the rate times the time elapsed.
        let owed = batched.state().birth_owed_s;
        assert!(owed < 0.1);
        let batched_mass = batched.expected_count() + RATE * owed;
        assert!((batched_mass - RATE * t).abs() < 1e-9, "t = {t}");
        assert!((every.expected_count() - RATE * t).abs() < 1e-9);
    }
    // One addition per 0.1 s (25 predictions of 4 ms), against one per prediction.
    assert_eq!(additions, 10);
    assert_eq!(every.intensity().len(), 250 * 4);
    assert_eq!(batched.intensity().len(), 10 * 4);
}

#[test]
fn the_time_owed_survives_a_checkpoint() {
    let mut original = filter(0.1).unwrap();
    original.predict_to(0.03).unwrap();
    let state = original.state();
    assert!((state.birth_owed_s - 0.03).abs() < 1e-12);
    let json = serde_json::to_string(&state).unwrap();
    let mut resumed = filter(0.1).unwrap();
    resumed
        .restore(serde_json::from_str(&json).unwrap())
        .unwrap();
    for filter in [&mut original, &mut resumed] {
        filter.predict_to(0.09).unwrap();
        assert!(filter.intensity().is_empty());
        filter.predict_to(0.1).unwrap();
        assert!((filter.expected_count() - RATE * 0.1).abs() < 1e-12);
    }
}

#[test]
fn a_bad_interval_is_refused() {
    for bad in [-0.1, f64::NAN, f64::INFINITY] {
        let error = filter(bad).unwrap_err().to_string();
        assert!(error.contains("birth interval"), "{error}");
    }
}
