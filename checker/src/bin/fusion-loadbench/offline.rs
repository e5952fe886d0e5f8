//! The engine alone, without Zenoh, on one core: what a set costs in order and when sensors are
//! late (rollbacks), and how the cost and the memory grow with targets and sensors.

use fusion_server::config::ServerConfig;
use fusion_server::engine::Engine;
use protocol::{MeasurementSet, SensorDescriptor};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use simulator::Scenario;

use crate::heap;

/// How sets reach the server.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arrival {
    /// In stamp order, at once.
    InOrder,
    /// The first sensor 0.4 s late, the second late by a random 0–1 s, the others on time.
    Delayed,
}

/// What one offline run measured.
#[derive(Debug, Clone, Copy)]
pub struct Cost {
    /// Sets processed.
    pub sets: usize,
    /// Scenario seconds.
    pub seconds: f64,
    /// CPU seconds of processing (one thread).
    pub cpu_s: f64,
    /// Rollbacks and sets re-processed.
    pub rollbacks: u64,
    /// Sets processed again after rollbacks.
    pub reprocessed: u64,
    /// Sets refused as late.
    pub late: u64,
    /// Peak heap bytes held by the engine during the run (above what was allocated before).
    pub peak_bytes: usize,
    /// CPU microseconds of one snapshot of the whole tracker state at the end of the run (what
    /// the timeline takes every `ingest.snapshot_interval_s` of stamps).
    pub snapshot_us: f64,
}

impl Cost {
    /// Microseconds of CPU per set.
    pub fn per_set_us(&self) -> f64 {
        self.cpu_s / self.sets.max(1) as f64 * 1e6
    }

    /// How many times faster than the sets arrive.
    pub fn real_time_multiple(&self) -> f64 {
        self.seconds / self.cpu_s
    }
}

/// The scenario's descriptors and sets, stamped from `start`.
pub fn scenario_sets(
    scenario: &Scenario,
    seconds: f64,
    start: f64,
) -> anyhow::Result<(Vec<SensorDescriptor>, Vec<MeasurementSet>)> {
    let mut scenario = scenario.clone();
    scenario.start = Some(start);
    Ok(simulator::descriptors_and_sets(&scenario, 1, seconds)?)
}

/// When each set arrives under `arrival`, in order of arrival.
pub fn arrivals(
    descriptors: &[SensorDescriptor],
    sets: &[MeasurementSet],
    arrival: Arrival,
) -> Vec<(f64, MeasurementSet)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut out: Vec<(f64, MeasurementSet)> = sets
        .iter()
        .map(|set| {
            let index = descriptors.iter().position(|d| d.sensor == set.sensor);
            let delay = match (arrival, index) {
                (Arrival::Delayed, Some(0)) => 0.4,
                (Arrival::Delayed, Some(1)) => rng.gen_range(0.0..1.0),
                _ => 0.0,
            };
            (set.stamp + delay, set.clone())
        })
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// The server's default configuration for the dense scenario's volume.
pub fn dense_config(max_components: usize) -> ServerConfig {
    let mut config = ServerConfig::default();
    config.site.name = "dense".into();
    config.site.volume_min = [0.0, 0.0, 0.0];
    config.site.volume_max = [40.0, 40.0, 10.0];
    config.filter.birth_grid = [8, 8, 2];
    config.filter.max_components = max_components;
    config
}

/// An offline engine that knows `descriptors`.
fn engine_for(
    config: &ServerConfig,
    start: f64,
    descriptors: &[SensorDescriptor],
) -> anyhow::Result<Engine> {
    let mut engine = Engine::new(config.clone(), start, false)?;
    for d in descriptors {
        engine
            .learn_descriptor(d.clone(), false)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    Ok(engine)
}

/// Runs the engine over `scenario` for `seconds` under `arrival`, one set per step as the live
/// server does when it keeps up, on a one-thread pool.
pub fn engine_cost(
    config: &ServerConfig,
    scenario: &Scenario,
    seconds: f64,
    arrival: Arrival,
) -> anyhow::Result<Cost> {
    let start = 1_763_700_000.0;
    let (descriptors, sets) = scenario_sets(scenario, seconds, start)?;
    let arrivals = arrivals(&descriptors, &sets, arrival);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| {
        heap::reset_peak();
        let before = heap::current();
        let mut engine = engine_for(config, start, &descriptors)?;
        let began = thread_cpu_s();
        for (arrived, set) in &arrivals {
            // Refusals are counted in the status and reported below.
            let _ = engine.admit_decoded(None, set.clone(), *arrived);
            engine.step(*arrived);
        }
        let cpu_s = thread_cpu_s() - began;
        let snapshot_us = snapshot_cost_us(&engine);
        let status = engine.status(start + seconds);
        let sum = |f: fn(&protocol::SensorStatus) -> u64| status.sensors.iter().map(f).sum();
        Ok(Cost {
            sets: arrivals.len(),
            seconds,
            cpu_s,
            rollbacks: sum(|s| s.rollbacks),
            reprocessed: sum(|s| s.reprocessed),
            late: sum(|s| s.late),
            peak_bytes: heap::peak().saturating_sub(before),
            snapshot_us,
        })
    })
}

/// CPU microseconds of one copy of the engine's tracker state (the median of 101).
fn snapshot_cost_us(engine: &Engine) -> f64 {
    let mut times: Vec<f64> = (0..101)
        .map(|_| {
            let began = thread_cpu_s();
            std::hint::black_box(engine.checkpoint());
            (thread_cpu_s() - began) * 1e6
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// CPU time of the calling thread, in seconds.
fn thread_cpu_s() -> f64 {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes one timespec through the pointer it is given.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    assert_eq!(status, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    now.tv_sec as f64 + now.tv_nsec as f64 * 1e-9
}

/// Wall-clock seconds the engine takes over `scenario` in order on a pool of `threads` threads
/// (the filter parallelises its larger updates).
pub fn engine_wall(
    config: &ServerConfig,
    scenario: &Scenario,
    seconds: f64,
    threads: usize,
) -> anyhow::Result<f64> {
    let start = 1_763_700_000.0;
    let (descriptors, sets) = scenario_sets(scenario, seconds, start)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    pool.install(|| {
        let mut engine = engine_for(config, start, &descriptors)?;
        let began = std::time::Instant::now();
        for set in &sets {
            let _ = engine.admit_decoded(None, set.clone(), set.stamp);
            engine.step(set.stamp);
        }
        Ok(began.elapsed().as_secs_f64())
    })
}
