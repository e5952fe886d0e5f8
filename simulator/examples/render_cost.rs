//! What rendering the default room's raw signals costs: CPU seconds per second of scenario for
//! each sensor, measured as this thread's CPU time (so other load on the host does not count),
//! without writing any file. One core keeps up with the room live while the sum stays below 1.
//!
//! `cargo run --release -p simulator --example render_cost [SECONDS]` (default 10).

use std::time::Duration;

use protocol::SensorModel;
use simulator::render::camera::{CameraRenderer, CameraRoom};
use simulator::render::{
    render_lidar_scan, render_mic_pair, AcousticRoom, LidarScene, ScanPattern,
};

/// CPU time of the calling thread.
fn thread_cpu() -> Duration {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to write into.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seconds: f64 = std::env::args().nth(1).map_or(Ok(10.0), |s| s.parse())?;
    let scenario = simulator::default_room();
    let seed = 1;
    let mut total = 0.0;
    for spec in &scenario.sensors {
        let name = spec.sensor.as_str();
        let began = thread_cpu();
        match &spec.model {
            SensorModel::Camera(_) => {
                let mut renderer =
                    CameraRenderer::new(&scenario, name, &CameraRoom::default(), seed)?;
                for k in 0..spec.frame_count(seconds) {
                    std::hint::black_box(renderer.render(spec.frame_time(k)));
                }
            }
            SensorModel::MicPair(_) => {
                std::hint::black_box(render_mic_pair(
                    &scenario,
                    name,
                    &AcousticRoom::default(),
                    seed,
                    seconds,
                )?);
            }
            SensorModel::Lidar(model) => {
                let (scene, pattern) = (LidarScene::default_room(), ScanPattern::ceiling(model));
                for k in 0..spec.frame_count(seconds) {
                    std::hint::black_box(render_lidar_scan(
                        &scenario,
                        name,
                        &scene,
                        &pattern,
                        seed,
                        spec.frame_time(k),
                    )?);
                }
            }
            _ => continue,
        }
        let per_second = (thread_cpu() - began).as_secs_f64() / seconds;
        total += per_second;
        println!("{name:8} {:6.3} CPU s per scenario second", per_second);
    }
    println!("all      {total:6.3} CPU s per scenario second (one core keeps up live below 1)");
    Ok(())
}
