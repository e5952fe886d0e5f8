//! The camera front end on the simulator's rendered default room (`simulator::render::camera`:
//! three people crossing and occluding one another, soft shadows, illumination drift, clothes
//! close to the floor's colour): per camera, how many of the frame's head points lie near a
//! person's projected head (found), how many near nobody's (false heads), and how often a person
//! whose head is in the image has no point near it (missed).

use frontends::camera::{CameraConfig, CameraPipeline};
use protocol::SensorModel;
use simulator::render::camera::{frame_times, CameraRenderer, CameraRoom};

/// A point within this many pixels of a projected head top is that head's.
const NEAR_PX: f64 = 25.0;

#[derive(Debug, Default)]
struct Figures {
    frames: usize,
    points: usize,
    false_heads: usize,
    heads: usize,
    missed: usize,
}

fn project(p: &[[f64; 4]; 3], x: [f64; 3]) -> [f64; 2] {
    let row = |r: usize| p[r][0] * x[0] + p[r][1] * x[1] + p[r][2] * x[2] + p[r][3];
    [row(0) / row(2), row(1) / row(2)]
}

fn figures(camera: &str, seed: u64, from_s: f64, to_s: f64) -> Figures {
    let scenario = simulator::default_room();
    let (_, spec) = scenario.sensor(camera).unwrap();
    let SensorModel::Camera(model) = &spec.model else {
        panic!("{camera} is a camera")
    };
    let mut renderer =
        CameraRenderer::new(&scenario, camera, &CameraRoom::default(), seed).unwrap();
    let mut pipeline = CameraPipeline::new(CameraConfig::default()).unwrap();
    let mut out = Figures::default();
    for (index, t) in frame_times(spec, -1.0, to_s).into_iter().enumerate() {
        let image = renderer.render(t);
        let Some(detections) = pipeline.process_frame(&image, index, t, camera).unwrap() else {
            continue;
        };
        if t < from_s {
            continue;
        }
        let heads: Vec<[f64; 2]> = scenario
            .present_at(seed, t)
            .into_iter()
            .map(|(_, head)| project(&model.projection, head))
            .filter(|[u, v]| (0.0..640.0).contains(u) && (0.0..480.0).contains(v))
            .collect();
        let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= NEAR_PX;
        out.frames += 1;
        out.points += detections.points.len();
        out.false_heads += detections
            .points
            .iter()
            .filter(|&&p| !heads.iter().any(|&h| near(p, h)))
            .count();
        out.heads += heads.len();
        out.missed += heads
            .iter()
            .filter(|&&h| !detections.points.iter().any(|&p| near(p, h)))
            .count();
    }
    out
}

#[test]
fn head_points_of_the_rendered_room() {
    let figures: Vec<(&str, Figures)> = ["cam1", "cam2"]
        .into_iter()
        .map(|camera| (camera, figures(camera, 1, 6.0, 16.0)))
        .collect();
    for (camera, f) in &figures {
        println!(
            "{camera}: {} frames, {:.2} points per frame, {} false heads ({:.2} per frame), {} of {} visible heads missed ({:.1} %)",
            f.frames,
            f.points as f64 / f.frames as f64,
            f.false_heads,
            f.false_heads as f64 / f.frames as f64,
            f.missed,
            f.heads,
            100.0 * f.missed as f64 / f.heads as f64
        );
    }
    for (camera, f) in &figures {
        assert!(f.frames > 200, "{camera}");
        // Floors under today's figures (seed 1: 0.35 and 0.15 false heads per frame, 23 % and 31 %
        // of heads missed). Most misses are heads seen inside a nearer person's silhouette, which
        // a top outline cannot show; the heads found lie within 1 to 4 px of the projected truth.
        // Many of cam1's false heads stay at one place for a second or more while the people move.
        assert!(
            f.false_heads as f64 / f.frames as f64 <= 0.45,
            "{camera}: too many false heads"
        );
        assert!(
            f.missed as f64 / f.heads as f64 <= 0.35,
            "{camera}: too many heads missed"
        );
    }
}
