//! The scene of one site as the page draws it (sent as JSON): the site's extent, the tracks with
//! their trails and 2σ ellipses, every sensor's drawing and counters, the truth and live OSPA.

use nalgebra::DVector;
use protocol::{SensorModel, Site, TrackSet};
use serde::Serialize;

use crate::geometry::{camera_frustum, tdoa_hyperbola, two_sigma_ellipse, Ellipse, Point};
use crate::state::{SensorState, SiteState, Sites};

/// OSPA cut-off (metres) and order of the live score, as `fusion-checker` uses.
const OSPA_CUTOFF_M: f64 = 1.0;
const OSPA_ORDER: f64 = 1.0;
/// A truth set this close in time (seconds) to a track set is compared with it.
const TRUTH_TOLERANCE_S: f64 = 0.1;
/// A status reply older than this (seconds) is shown as stale.
const STATUS_STALE_S: f64 = 3.0;
/// Margin around what is drawn, metres.
const MARGIN_M: f64 = 0.3;
/// A track lighter than this is drawn hollow: the filter gives it less than half an object.
const WEAK_WEIGHT: f64 = 0.5;

/// Everything the page draws for one site.
#[derive(Debug, Clone, Serialize)]
pub struct Scene {
    /// The site shown.
    pub site: String,
    /// Every site known, for the selector.
    pub sites: Vec<String>,
    /// The box everything lies in, `[min, max]`.
    pub extent: [Point; 2],
    /// Stamp and sequence number of the latest track set, and its expected count.
    pub stamp: Option<f64>,
    /// See `stamp`.
    pub seq: Option<u64>,
    /// The PHD's expected number of objects.
    pub expected_count: Option<f64>,
    /// The tracks.
    pub tracks: Vec<TrackView>,
    /// The sensors.
    pub sensors: Vec<SensorView>,
    /// The latest truth near the tracks' stamp (simulations only).
    pub truth: Option<Vec<TruthPoint>>,
    /// OSPA between tracks and truth (c = 1 m, p = 1), when there is truth.
    pub ospa: Option<f64>,
    /// Whether the status reply is recent.
    pub status_fresh: bool,
    /// The server's uptime, components and latency, from the status.
    pub server: Option<ServerView>,
    /// Payloads refused by the view for this site.
    pub rejected: u64,
}

/// One track.
#[derive(Debug, Clone, Serialize)]
pub struct TrackView {
    /// Track label.
    pub id: u64,
    /// Position, metres.
    pub position: Point,
    /// Speed, m/s, when the motion model has a velocity.
    pub speed: Option<f64>,
    /// Seconds since the label was first seen.
    pub age_s: f64,
    /// The track's weight.
    pub weight: f64,
    /// Drawn hollow (weight below one half).
    pub weak: bool,
    /// 2σ ellipse in the top view (x, y) and the side view (x, z).
    pub top_ellipse: Ellipse,
    /// See `top_ellipse`.
    pub side_ellipse: Ellipse,
    /// Recent positions, oldest first.
    pub trail: Vec<Point>,
}

/// One true object.
#[derive(Debug, Clone, Serialize)]
pub struct TruthPoint {
    /// The simulation's identity.
    pub id: u64,
    /// Position, metres.
    pub position: Point,
}

/// One sensor.
#[derive(Debug, Clone, Serialize)]
pub struct SensorView {
    /// Name.
    pub sensor: String,
    /// Model kind (`camera`, `mic_pair`, …), when known.
    pub kind: Option<String>,
    /// Whether its liveliness token is held (unknown: not seen yet).
    pub alive: Option<bool>,
    /// Sets per second at the server.
    pub rate_hz: Option<f64>,
    /// Counters from the status: received, processed, late, invalid, lost.
    pub counts: Option<[u64; 5]>,
    /// Where its label goes.
    pub anchor: Option<Point>,
    /// Its body: frustum edges, microphone baseline (polylines).
    pub lines: Vec<Vec<Point>>,
    /// What its latest measurements say: TDOA hyperbolas (polylines).
    pub curves: Vec<Vec<Point>>,
    /// Range of a LIDAR or bearing–range sensor: centre and radius.
    pub range: Option<(Point, f64)>,
    /// Region of a position sensor.
    pub region: Option<[Point; 2]>,
}

/// The server's figures from its status.
#[derive(Debug, Clone, Serialize)]
pub struct ServerView {
    /// Seconds since it started.
    pub uptime_s: f64,
    /// Gaussian components in the intensity.
    pub components: u64,
    /// Arrival-to-publication latency percentiles, ms.
    pub latency_ms: [Option<f64>; 2],
}

/// The scene of `site` (the first known one when `None` or unknown) at wall-clock `now`.
pub fn scene(sites: &Sites, site: Option<&str>, now: f64) -> Scene {
    let names: Vec<String> = sites.sites.keys().map(|s| s.as_str().to_string()).collect();
    let chosen = site
        .and_then(|s| Site::new(s).ok())
        .filter(|s| sites.sites.contains_key(s))
        .or_else(|| sites.sites.keys().next().cloned());
    let empty = SiteState::default();
    let state = chosen
        .as_ref()
        .and_then(|s| sites.sites.get(s))
        .unwrap_or(&empty);
    let sensors = state
        .sensors
        .iter()
        .map(|(name, s)| sensor_view(name.as_str(), s, state))
        .collect();
    let mut scene = Scene {
        site: chosen.map_or_else(String::new, |s| s.as_str().to_string()),
        sites: names,
        extent: [[0.0; 3]; 2],
        stamp: state.tracks.as_ref().map(|t| t.stamp),
        seq: state.tracks.as_ref().map(|t| t.seq),
        expected_count: state.tracks.as_ref().map(|t| t.expected_count),
        tracks: state
            .tracks
            .as_ref()
            .map(|t| track_views(t, state))
            .unwrap_or_default(),
        sensors,
        truth: None,
        ospa: None,
        status_fresh: state
            .status
            .as_ref()
            .is_some_and(|(_, at)| now - at < STATUS_STALE_S),
        server: state.status.as_ref().map(|(s, _)| ServerView {
            uptime_s: s.uptime_s,
            components: s.components,
            latency_ms: [s.latency_ms.p50, s.latency_ms.p99],
        }),
        rejected: state.rejected,
    };
    if let Some(tracks) = &state.tracks {
        if let Some(truth) = state.truth_near(tracks.stamp, TRUTH_TOLERANCE_S) {
            scene.truth = Some(
                truth
                    .objects
                    .iter()
                    .map(|o| TruthPoint {
                        id: o.id,
                        position: o.position,
                    })
                    .collect(),
            );
            scene.ospa = ospa(tracks, truth.objects.iter().map(|o| o.position));
        }
    }
    scene.extent = extent(&scene);
    scene
}

fn track_views(set: &TrackSet, state: &SiteState) -> Vec<TrackView> {
    set.tracks
        .iter()
        .map(|t| {
            let c = &t.position_covariance;
            TrackView {
                id: t.id,
                position: t.position,
                speed: t
                    .velocity
                    .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()),
                age_s: (set.stamp - t.first_seen).max(0.0),
                weight: t.weight,
                weak: t.weight < WEAK_WEIGHT,
                top_ellipse: two_sigma_ellipse(c[0][0], c[0][1], c[1][1]),
                side_ellipse: two_sigma_ellipse(c[0][0], c[0][2], c[2][2]),
                trail: state
                    .trails
                    .get(&t.id)
                    .map(|trail| trail.iter().map(|(_, p)| *p).collect())
                    .unwrap_or_default(),
            }
        })
        .collect()
}

fn ospa(tracks: &TrackSet, truth: impl Iterator<Item = Point>) -> Option<f64> {
    let points = |p: Point| DVector::from_column_slice(&p);
    let estimates: Vec<DVector<f64>> = tracks.tracks.iter().map(|t| points(t.position)).collect();
    let truth: Vec<DVector<f64>> = truth.map(points).collect();
    let params = gmphd::metrics::MetricParams::new(OSPA_CUTOFF_M, OSPA_ORDER).ok()?;
    gmphd::metrics::ospa(&estimates, &truth, params)
        .ok()
        .map(|o| o.distance)
}

fn sensor_view(name: &str, sensor: &SensorState, state: &SiteState) -> SensorView {
    let status = state
        .status
        .as_ref()
        .and_then(|(s, _)| s.sensors.iter().find(|e| e.sensor.as_str() == name));
    let mut view = SensorView {
        sensor: name.to_string(),
        kind: sensor
            .descriptor
            .as_ref()
            .map(|d| d.model.kind_name().to_string())
            .or_else(|| status.map(|s| s.kind.name().to_string())),
        // The view's own liveliness subscription first; the server's word when it has none.
        alive: sensor.alive.or_else(|| status.map(|s| s.alive)),
        rate_hz: sensor.rate_hz,
        counts: status.map(|s| [s.received, s.processed, s.late, s.invalid, s.lost]),
        anchor: None,
        lines: Vec::new(),
        curves: Vec::new(),
        range: None,
        region: None,
    };
    if let Some(descriptor) = &sensor.descriptor {
        draw_model(&descriptor.model, sensor, &mut view);
    }
    view
}

fn draw_model(model: &SensorModel, sensor: &SensorState, view: &mut SensorView) {
    match model {
        SensorModel::Camera(camera) => {
            if let Some(f) = camera_frustum(&camera.projection, camera.image_size, 0.0) {
                view.anchor = Some(f.centre);
                view.lines = f
                    .corners
                    .iter()
                    .map(|corner| vec![f.centre, *corner])
                    .collect();
                let mut rim = f.corners.to_vec();
                rim.push(f.corners[0]);
                view.lines.push(rim);
            }
        }
        SensorModel::MicPair(pair) => {
            view.anchor = Some(pair.mics[0]);
            view.lines = vec![pair.mics.to_vec()];
            if let Some((_, taus)) = &sensor.latest_taus {
                // Drawn over a generous box; the page clips to its view.
                let (lo, hi) = ([-20.0, -20.0], [20.0, 20.0]);
                view.curves = taus
                    .iter()
                    .flat_map(|tau| tdoa_hyperbola(&pair.mics, pair.speed_of_sound, *tau, lo, hi))
                    .collect();
            }
        }
        SensorModel::Lidar(lidar) => {
            view.anchor = Some(lidar.position);
            view.range = Some((lidar.position, lidar.max_range));
        }
        SensorModel::BearingRange(br) => {
            view.anchor = Some(br.position);
            view.range = Some((br.position, br.max_range));
        }
        SensorModel::Position(position) => {
            view.anchor = Some(position.region.min);
            view.region = Some([position.region.min, position.region.max]);
        }
    }
}

/// The box holding the sensors' bodies, the tracks and the truth, the floor included, with a
/// margin; a 3 m × 2 m × 2.5 m room when there is nothing yet.
fn extent(scene: &Scene) -> [Point; 2] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut add = |p: &Point| {
        if p.iter().all(|v| v.is_finite()) {
            for ((low, high), v) in lo.iter_mut().zip(hi.iter_mut()).zip(p) {
                *low = low.min(*v);
                *high = high.max(*v);
            }
        }
    };
    for sensor in &scene.sensors {
        sensor.anchor.iter().for_each(&mut add);
        sensor
            .lines
            .iter()
            .flatten()
            .filter(|_| sensor.kind.as_deref() != Some("camera"))
            .for_each(&mut add);
        sensor.region.iter().flatten().for_each(&mut add);
    }
    scene.tracks.iter().for_each(|t| add(&t.position));
    scene.truth.iter().flatten().for_each(|t| add(&t.position));
    if lo[0] > hi[0] {
        return [[0.0, 0.0, 0.0], [3.0, 2.0, 2.5]];
    }
    lo[2] = lo[2].min(0.0);
    [
        [lo[0] - MARGIN_M, lo[1] - MARGIN_M, lo[2]],
        [hi[0] + MARGIN_M, hi[1] + MARGIN_M, hi[2] + MARGIN_M],
    ]
}
