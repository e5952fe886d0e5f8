//! The multi-Bernoulli image tracker on the simulator's rendered default room, one camera and seed:
//! the share of the visible heads it publishes (a point within 25 px), its points near no head per
//! frame, the found heads' offset and RMS error against the published σ, and the CPU time per frame.
//!
//! ```sh
//! cargo run --release -p frontends --example image_tracker_room -- [seed] [camera] [seconds]
//! ```
//!
//! `IMAGE_TRACKER_CONFIG` may hold a TOML `[multi_bernoulli]` table's body to try other settings;
//! `IMAGE_TRACKER_DUMP=t` writes the frame at scenario time `t` and its foreground (estimates' outlines
//! in red) as PNGs into the current directory.

use std::time::Duration;

use frontends::camera::multi_bernoulli::{ImageTracker, MultiBernoulliConfig, PersonEstimate};
use frontends::camera::CameraConfig;
use image::RgbImage;
use protocol::SensorModel;
use simulator::render::camera::{frame_times, CameraRenderer, CameraRoom};

/// A published point within this many pixels of a projected head top is that head's.
const NEAR_PX: f64 = 25.0;
/// Figures count from here (everyone has walked in).
const SCORED_FROM_S: f64 = 6.0;

fn project(p: &[[f64; 4]; 3], x: [f64; 3]) -> [f64; 2] {
    let row = |r: usize| p[r][0] * x[0] + p[r][1] * x[1] + p[r][2] * x[2] + p[r][3];
    [row(0) / row(2), row(1) / row(2)]
}

/// CPU time of this process so far.
fn cpu_time() -> Duration {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for clock_gettime to fill.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
}

#[derive(Default)]
struct Figures {
    sets: usize,
    heads: usize,
    found: usize,
    false_points: usize,
    offset: [f64; 2],
    squared_error: f64,
    variance: f64,
}

impl Figures {
    fn add(&mut self, published: &[&PersonEstimate], heads: &[[f64; 2]]) {
        let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        self.sets += 1;
        self.heads += heads.len();
        for &h in heads {
            let nearest = published
                .iter()
                .min_by(|a, b| d(a.head, h).total_cmp(&d(b.head, h)));
            if let Some(p) = nearest.filter(|p| d(p.head, h) <= NEAR_PX) {
                self.found += 1;
                self.squared_error += d(p.head, h).powi(2);
                self.offset[0] += p.head[0] - h[0];
                self.offset[1] += p.head[1] - h[1];
                self.variance += 0.5 * (p.covariance[0][0] + p.covariance[1][1]);
            }
        }
        self.false_points += published
            .iter()
            .filter(|p| heads.iter().all(|&h| d(p.head, h) > NEAR_PX))
            .count();
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seed: u64 = args.get(1).map_or(1, |s| s.parse().expect("seed"));
    let camera = args.get(2).map_or("cam1", String::as_str).to_string();
    let to_s: f64 = args.get(3).map_or(30.0, |s| s.parse().expect("seconds"));
    let config: MultiBernoulliConfig = match std::env::var("IMAGE_TRACKER_CONFIG") {
        Ok(text) => toml::from_str(&text).expect("a [multi_bernoulli] table's body"),
        Err(_) => MultiBernoulliConfig::default(),
    };
    let dump_at: Option<f64> = std::env::var("IMAGE_TRACKER_DUMP")
        .ok()
        .map(|t| t.parse().expect("a time"));
    let scenario = simulator::default_room();
    let (_, spec) = scenario.sensor(&camera).expect("a camera of the room");
    let SensorModel::Camera(model) = &spec.model else {
        panic!("{camera} is not a camera")
    };
    let mut renderer =
        CameraRenderer::new(&scenario, &camera, &CameraRoom::default(), seed).expect("renderer");
    let mut tracker = ImageTracker::new(
        config.clone(),
        CameraConfig::default().background,
        model.projection,
        model.image_size,
    )
    .expect("tracker");
    let [width, height] = model.image_size.map(f64::from);
    let mut figures = Figures::default();
    let (mut cpu, mut frames) = (Duration::ZERO, 0u32);
    for t in frame_times(spec, -1.0, to_s) {
        let image = renderer.render(t);
        let before = cpu_time();
        let out = tracker.process_frame(&image, t, "frame").expect("frame");
        cpu += cpu_time() - before;
        frames += 1;
        let Some(out) = out else { continue };
        if dump_at.is_some_and(|at| (t - at).abs() < 0.02) {
            dump(
                &tracker,
                &image,
                &format!("image_tracker_{seed}_{camera}_{t:.2}"),
            );
        }
        if t < SCORED_FROM_S {
            continue;
        }
        let published: Vec<&PersonEstimate> = out
            .people
            .iter()
            .filter(|p| {
                p.reported_frames >= config.confirm_frames
                    && p.visible_head >= config.min_visible_head
            })
            .collect();
        let heads: Vec<[f64; 2]> = scenario
            .present_at(seed, t)
            .into_iter()
            .map(|(_, h)| project(&model.projection, h))
            .filter(|[u, v]| (0.0..width).contains(u) && (0.0..height).contains(v))
            .collect();
        figures.add(&published, &heads);
    }
    let f = &figures;
    let found = f.found.max(1) as f64;
    println!(
        "seed {seed} {camera}: {} sets, {:.1} % of the visible heads published, {:.2} points per set \
         near no head, offset ({:.1}, {:.1}) px, RMS error {:.1} px, published σ {:.1} px; CPU {:.1} ms \
         per frame",
        f.sets,
        100.0 * f.found as f64 / f.heads.max(1) as f64,
        f.false_points as f64 / f.sets.max(1) as f64,
        f.offset[0] / found,
        f.offset[1] / found,
        (f.squared_error / found).sqrt(),
        (f.variance / found).sqrt(),
        1e3 * cpu.as_secs_f64() / f64::from(frames.max(1)),
    );
}

/// Writes the frame and the foreground (grey) with the estimates' outlines in red.
fn dump(tracker: &ImageTracker, image: &RgbImage, stem: &str) {
    image
        .save(format!("{stem}_frame.png"))
        .expect("write frame");
    let map = tracker.foreground();
    let [w, h] = map.size();
    let mut out = RgbImage::new(w as u32, h as u32);
    for (p, &f) in out.pixels_mut().zip(map.values()) {
        let g = (f * 255.0) as u8;
        *p = image::Rgb([g, g, g]);
    }
    for region in tracker.filter().estimate_regions() {
        for s in region
            .spans
            .iter()
            .filter(|s| (0..h as i32).contains(&s.row))
        {
            for x in [s.left, s.right] {
                let c = x.round() as i64;
                if (0..w as i64).contains(&c) {
                    out.put_pixel(c as u32, s.row as u32, image::Rgb([255, 0, 0]));
                }
            }
        }
    }
    out.save(format!("{stem}_foreground.png"))
        .expect("write foreground");
}
