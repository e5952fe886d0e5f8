//! The clock the benchmarks measure with: wall time (criterion's default) or, with
//! `GMPHD_BENCH_CLOCK=cpu`, the CPU time of the whole process (every thread, user and
//! system), which does not grow when other processes compete for the cores — the machine
//! the published figures come from is shared and often loaded. CPU time adds up every
//! thread, so it stands for elapsed time only on one thread (`RAYON_NUM_THREADS=1`);
//! parallel speed-ups are measured in wall time.

use std::time::{Duration, Instant};

use criterion::measurement::{Measurement, ValueFormatter, WallTime};

/// Criterion's wall clock, whose formatter (durations) both clocks share.
static WALL: WallTime = WallTime;

/// Which clock a benchmark reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchClock {
    /// Elapsed (wall) time.
    Wall,
    /// CPU time of the process, all threads.
    ProcessCpu,
}

/// A reading of a [`BenchClock`].
pub enum Stamp {
    /// A wall-clock instant.
    Wall(Instant),
    /// CPU time consumed so far.
    Cpu(Duration),
}

impl BenchClock {
    /// `ProcessCpu` when `GMPHD_BENCH_CLOCK=cpu`, else `Wall`.
    pub fn from_env() -> Self {
        match std::env::var("GMPHD_BENCH_CLOCK").as_deref() {
            Ok("cpu") => Self::ProcessCpu,
            _ => Self::Wall,
        }
    }

    /// The current reading.
    pub fn now(&self) -> Stamp {
        match self {
            Self::Wall => Stamp::Wall(Instant::now()),
            Self::ProcessCpu => Stamp::Cpu(process_cpu_time()),
        }
    }

    /// Time passed on this clock since `start`.
    pub fn since(&self, start: &Stamp) -> Duration {
        match start {
            Stamp::Wall(instant) => instant.elapsed(),
            Stamp::Cpu(used) => process_cpu_time().saturating_sub(*used),
        }
    }
}

/// CPU time of this process so far (CLOCK_PROCESS_CPUTIME_ID, nanosecond resolution).
fn process_cpu_time() -> Duration {
    let mut now = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes one timespec through the pointer it is given,
    // which points at a live local.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut now) };
    assert_eq!(status, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
    Duration::new(now.tv_sec as u64, now.tv_nsec as u32)
}

impl Measurement for BenchClock {
    type Intermediate = Stamp;
    type Value = Duration;

    fn start(&self) -> Stamp {
        self.now()
    }

    fn end(&self, start: Stamp) -> Duration {
        self.since(&start)
    }

    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }

    fn zero(&self) -> Duration {
        Duration::ZERO
    }

    fn to_f64(&self, value: &Duration) -> f64 {
        value.as_nanos() as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        WALL.formatter()
    }
}
