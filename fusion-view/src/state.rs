//! What the view knows of every site it can reach, fed by the Zenoh inputs: the latest track
//! set and each track's recent trail, the sensors (descriptor, liveliness, latest microphone-pair
//! measurements, counters from the status queryable), the latest truth, and the site's extent.
//! Everything is bounded: at most [`MAX_SITES`] sites of [`MAX_SENSORS`] sensors, trails of
//! `trail_s` seconds sampled at most every [`TRAIL_STEP_S`], a few seconds of truth.

use std::collections::{BTreeMap, VecDeque};

use protocol::{SensorDescriptor, SensorId, SensorModel, Site, Status, TrackSet, TruthSet};

use crate::geometry::Point;

/// Most sites kept; sets of further sites are ignored (and counted).
pub const MAX_SITES: usize = 32;
/// Most sensors kept per site.
pub const MAX_SENSORS: usize = 256;
/// Trail points are kept at most this often, seconds of stamp.
pub const TRAIL_STEP_S: f64 = 0.1;
/// Seconds of truth kept to pair with track sets.
const TRUTH_KEPT_S: f64 = 2.0;

/// The sensor as the view knows it.
#[derive(Debug, Clone, Default)]
pub struct SensorState {
    /// Its published descriptor, once received.
    pub descriptor: Option<SensorDescriptor>,
    /// Whether its agent's liveliness token is held (as this view sees it).
    pub alive: Option<bool>,
    /// The latest measurement set of a microphone pair (for its TDOA hyperbolas).
    pub latest_taus: Option<(f64, Vec<f64>)>,
    /// Sets per second received by the server, from two status replies.
    pub rate_hz: Option<f64>,
    received_at: Option<(u64, f64)>,
}

/// One site's state.
#[derive(Debug, Clone, Default)]
pub struct SiteState {
    /// The latest track set received.
    pub tracks: Option<TrackSet>,
    /// Each track's recent positions `(stamp, position)`, in stamp order.
    pub trails: BTreeMap<u64, VecDeque<(f64, Point)>>,
    /// The sensors by name.
    pub sensors: BTreeMap<SensorId, SensorState>,
    /// The latest status reply and the wall-clock time it arrived.
    pub status: Option<(Status, f64)>,
    /// Recent truth sets in stamp order.
    pub truth: VecDeque<TruthSet>,
    /// Payloads of this site that could not be decoded or failed validation.
    pub rejected: u64,
    /// Whether the history of tracks was asked for already.
    pub history_asked: bool,
}

/// Every site the view knows.
#[derive(Debug, Clone)]
pub struct Sites {
    /// Sites by name.
    pub sites: BTreeMap<Site, SiteState>,
    /// Seconds of trail kept per track.
    pub trail_s: f64,
    /// Payloads ignored because [`MAX_SITES`] sites are known already.
    pub ignored: u64,
}

impl Sites {
    /// No site yet; trails of `trail_s` seconds.
    pub fn new(trail_s: f64) -> Self {
        Self {
            sites: BTreeMap::new(),
            trail_s,
            ignored: 0,
        }
    }

    /// The state of `site`, created when there is room.
    pub fn site_mut(&mut self, site: &Site) -> Option<&mut SiteState> {
        if !self.sites.contains_key(site) && self.sites.len() >= MAX_SITES {
            self.ignored += 1;
            return None;
        }
        Some(self.sites.entry(site.clone()).or_default())
    }

    /// A received track set: the latest one, and a point of each of its tracks' trails.
    pub fn on_tracks(&mut self, set: TrackSet) {
        let trail_s = self.trail_s;
        let Some(state) = self.site_mut(&set.site.clone()) else {
            return;
        };
        state.add_to_trails(&set, trail_s);
        let newest = state.trails_newest();
        state
            .trails
            .retain(|_, trail| trail.back().is_some_and(|(t, _)| *t >= newest - trail_s));
        state.tracks = Some(set);
    }

    /// Track sets from the history (any order): trail points only.
    pub fn on_history(&mut self, site: &Site, sets: &[TrackSet]) {
        let trail_s = self.trail_s;
        if let Some(state) = self.site_mut(site) {
            for set in sets {
                state.add_to_trails(set, trail_s);
            }
        }
    }

    /// A validated descriptor.
    pub fn on_descriptor(&mut self, descriptor: SensorDescriptor) {
        if let Some(sensor) = self.sensor_mut(&descriptor.site.clone(), &descriptor.sensor.clone())
        {
            sensor.descriptor = Some(descriptor);
        }
    }

    /// A liveliness token appeared or went away.
    pub fn on_alive(&mut self, site: &Site, sensor: &SensorId, alive: bool) {
        if let Some(sensor) = self.sensor_mut(site, sensor) {
            sensor.alive = Some(alive);
        }
    }

    /// Whether `sensor` of `site` is a microphone pair (whose sets the view draws).
    pub fn is_mic_pair(&self, site: &Site, sensor: &SensorId) -> bool {
        self.sites
            .get(site)
            .and_then(|s| s.sensors.get(sensor))
            .and_then(|s| s.descriptor.as_ref())
            .is_some_and(|d| matches!(d.model, SensorModel::MicPair(_)))
    }

    /// The latest measurement set of a microphone pair.
    pub fn on_mic_set(&mut self, site: &Site, sensor: &SensorId, stamp: f64, taus: Vec<f64>) {
        if let Some(sensor) = self.sensor_mut(site, sensor) {
            sensor.latest_taus = Some((stamp, taus));
        }
    }

    /// A status reply received at wall-clock `now`: the sensors' rates from the change of their
    /// `received` counters since the previous reply.
    pub fn on_status(&mut self, status: Status, now: f64) {
        let Some(state) = self.site_mut(&status.site.clone()) else {
            return;
        };
        for entry in &status.sensors {
            if !state.sensors.contains_key(&entry.sensor) && state.sensors.len() >= MAX_SENSORS {
                continue;
            }
            let sensor = state.sensors.entry(entry.sensor.clone()).or_default();
            if let Some((before, at)) = sensor.received_at {
                if now > at && entry.received >= before {
                    sensor.rate_hz = Some((entry.received - before) as f64 / (now - at));
                }
            }
            sensor.received_at = Some((entry.received, now));
        }
        state.status = Some((status, now));
    }

    /// A truth set of a simulation.
    pub fn on_truth(&mut self, site: &Site, truth: TruthSet) {
        if let Some(state) = self.site_mut(site) {
            let at = state.truth.partition_point(|t| t.stamp <= truth.stamp);
            state.truth.insert(at, truth);
            let newest = state.truth.back().map_or(0.0, |t| t.stamp);
            while state
                .truth
                .front()
                .is_some_and(|t| t.stamp < newest - TRUTH_KEPT_S)
            {
                state.truth.pop_front();
            }
        }
    }

    /// Counts a payload of `site` that was refused.
    pub fn on_rejected(&mut self, site: &Site) {
        if let Some(state) = self.site_mut(site) {
            state.rejected += 1;
        }
    }

    fn sensor_mut(&mut self, site: &Site, sensor: &SensorId) -> Option<&mut SensorState> {
        let state = self.site_mut(site)?;
        if !state.sensors.contains_key(sensor) && state.sensors.len() >= MAX_SENSORS {
            state.rejected += 1;
            return None;
        }
        Some(state.sensors.entry(sensor.clone()).or_default())
    }
}

impl SiteState {
    fn add_to_trails(&mut self, set: &TrackSet, trail_s: f64) {
        if !set.stamp.is_finite() {
            return;
        }
        for track in &set.tracks {
            let trail = self.trails.entry(track.id).or_default();
            let at = trail.partition_point(|(t, _)| *t < set.stamp);
            let near = |i: usize| {
                trail
                    .get(i)
                    .is_some_and(|(t, _)| (t - set.stamp).abs() < TRAIL_STEP_S)
            };
            // One point per step: a newer answer for about the same stamp replaces the old one.
            if near(at) {
                trail[at] = (set.stamp, track.position);
            } else if at > 0 && near(at - 1) {
                if at == trail.len() {
                    continue;
                }
                trail[at - 1] = (set.stamp, track.position);
            } else {
                trail.insert(at, (set.stamp, track.position));
            }
            let newest = trail.back().map_or(set.stamp, |(t, _)| *t);
            while trail.front().is_some_and(|(t, _)| *t < newest - trail_s) {
                trail.pop_front();
            }
        }
    }

    fn trails_newest(&self) -> f64 {
        self.trails
            .values()
            .filter_map(|t| t.back().map(|(s, _)| *s))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The truth set nearest to `stamp` in time, within `tolerance` seconds.
    pub fn truth_near(&self, stamp: f64, tolerance: f64) -> Option<&TruthSet> {
        self.truth
            .iter()
            .filter(|t| (t.stamp - stamp).abs() <= tolerance)
            .min_by(|a, b| (a.stamp - stamp).abs().total_cmp(&(b.stamp - stamp).abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::Track;

    fn track(id: u64, x: f64) -> Track {
        Track {
            id,
            position: [x, 1.0, 1.7],
            velocity: Some([0.5, 0.0, 0.0]),
            position_covariance: [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]],
            weight: 0.9,
            first_seen: 0.0,
        }
    }

    fn set(seq: u64, stamp: f64, tracks: Vec<Track>) -> TrackSet {
        TrackSet {
            version: 1,
            site: Site::default(),
            seq,
            stamp,
            expected_count: tracks.len() as f64,
            tracks,
        }
    }

    #[test]
    fn trails_keep_a_bounded_sampled_past_and_drop_tracks_that_are_gone() {
        let mut sites = Sites::new(2.0);
        for i in 0..100 {
            let t = i as f64 * 0.04;
            let mut tracks = vec![track(1, t)];
            if i < 20 {
                tracks.push(track(2, 0.0));
            }
            sites.on_tracks(set(i, 100.0 + t, tracks));
        }
        let state = &sites.sites[&Site::default()];
        let trail = &state.trails[&1];
        assert!(trail.len() <= 21, "{} points", trail.len());
        assert!(trail.back().unwrap().0 - trail.front().unwrap().0 <= 2.0);
        assert!(trail
            .iter()
            .zip(trail.iter().skip(1))
            .all(|(a, b)| a.0 < b.0));
        assert!(!state.trails.contains_key(&2), "track 2 ended 3 s ago");

        // The history arrives late: its older points go before the live ones, in order.
        let history: Vec<TrackSet> = (0..10)
            .map(|i| set(i, 102.0 + i as f64 * 0.1, vec![track(1, 0.0)]))
            .collect();
        sites.on_history(&Site::default(), &history);
        let trail = &sites.sites[&Site::default()].trails[&1];
        assert!(trail
            .iter()
            .zip(trail.iter().skip(1))
            .all(|(a, b)| a.0 < b.0));
    }

    #[test]
    fn rates_come_from_two_status_replies_and_sites_are_bounded() {
        let mut sites = Sites::new(5.0);
        let status = |received: u64| -> Status {
            serde_json::from_value(serde_json::json!({
                "version": 1, "site": "default", "uptime_s": 1.0, "stamp": 1.0,
                "components": 1, "tracks": 0,
                "sensors": [{"sensor": "cam1", "kind": "camera", "alive": true, "last_stamp": null,
                              "received": received, "processed": 0, "late": 0, "invalid": 0, "lost": 0}],
                "rejected": {"undecodable": 0, "unknown_sensor": 0, "invalid": 0, "late": 0},
                "latency_ms": {"p50": null, "p99": null}}))
            .expect("status")
        };
        sites.on_status(status(100), 10.0);
        sites.on_status(status(150), 12.0);
        let cam1 = &sites.sites[&Site::default()].sensors[&SensorId::new("cam1").unwrap()];
        assert_eq!(cam1.rate_hz, Some(25.0));

        for i in 0..MAX_SITES + 5 {
            let site = Site::new(format!("s{i}")).unwrap();
            sites.on_rejected(&site);
        }
        assert_eq!(sites.sites.len(), MAX_SITES);
        assert!(sites.ignored >= 5);
    }
}
