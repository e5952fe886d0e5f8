//! Scenario files, ground truth and simulated measurement sets for every sensor kind.
//!
//! A [`Scenario`] says what exists (targets and how they move) and what watches it
//! (sensors: a protocol `SensorDescriptor` body plus a frame rate and phase). A run is a
//! scenario plus a `seed` and a start time ([`Simulation`]); everything it produces is a
//! pure function of those and the instant asked for, so separate processes (one per
//! simulated sensor, say) agree bit for bit without talking to each other:
//!
//! * truth at scenario time `t` ([`truth_objects`], [`truth_set`]) never depends on other
//!   instants: random walks are built from hashed knots (see [`RandomWalk`]); with
//!   `personal_space_m` it is a joint walk stepped from time 0, computed once per (scenario, seed)
//!   ([`Scenario::position_of`]);
//! * frame `k` of sensor `s` ([`SimulatedSensor::measurement_set`]) draws from one
//!   ChaCha8 stream seeded by the hash of `(seed, s, k)`: detections with the model's
//!   `p_D(x)`, Gaussian noise through the Cholesky factor of the model's `noise_cov`,
//!   `Poisson(clutter_rate)` clutter through the model's `sample_clutter`;
//! * [`replay_lines`] writes a run as replay-file lines in stamp order.
//!
//! Built-in scenarios: [`default_room`] (three people, two cameras, four microphone
//! pairs, a LIDAR) and [`dense`] (50 targets, 8 sensors at 30 Hz, for benchmarks), also as
//! `scenarios/room.toml` and `scenarios/dense.toml`.
//!
//! [`pedestrians`] is apart from scenarios: crowds walking on a ground plane under one camera, as MOT
//! ground-truth boxes and a detector's `det.txt` (misses, false boxes, jitter), for image-plane trackers.
//!
//! # Scenario files (TOML)
//!
//! `SCENARIOS.md` next to this crate has a complete commented example. Keys (unknown keys
//! are rejected; errors name the key):
//!
//! | key | meaning |
//! |---|---|
//! | `site` | the deployment's site chunk (default `default`) |
//! | `start` | Unix time of scenario time 0; optional, default: the shared clock when the run starts |
//! | `duration_s` | length in seconds |
//! | `truth_rate_hz` | truth sets per second; truth instant `k` is at `k / truth_rate_hz` |
//! | `personal_space_m` | optional: no two present targets' heads come closer horizontally; they step aside |
//! | `[[targets]]` | `id` (unique), `appear_s` (default 0), `disappear_s` (optional), `motion` |
//! | `motion` | `kind = "constant_velocity"`: `position` (at `appear_s`), `velocity` |
//! | | `kind = "random_walk"`: `position` (at `appear_s`), `std` [m/√s per axis], `bounds = {min, max}`, `knot_interval_s` (default 1) |
//! | | `kind = "waypoints"`: `points = [[t, [x, y, z]], …]`, `t` in scenario seconds, increasing; linear between, held before and after |
//! | `[[sensors]]` | `sensor`, `detection_probability`, `clutter_rate`, `rate_hz`, `phase_s` (default 0), `model` |
//! | `model` | a protocol sensor model: `kind` (`camera`, `mic_pair`, `lidar`, `bearing_range`, `position`) and its fields as in PROTOCOL.md |
//!
//! Sensor frame `k` is taken at scenario time `phase_s + k / rate_hz` and stamped
//! `start + phase_s + k / rate_hz`, with `seq = k`. Frames and truth instants exist while
//! their scenario time is below the duration. A target is present for
//! `appear_s ≤ t < disappear_s`.
//!
//! ```
//! let scenario = simulator::Scenario::from_toml_str(r#"
//!     duration_s = 2.0
//!     truth_rate_hz = 10.0
//!     [[targets]]
//!     id = 1
//!     motion = { kind = "constant_velocity", position = [0.0, 0.0, 1.0], velocity = [1.0, 0.0, 0.0] }
//! "#)?;
//! let truth = simulator::truth_objects(&scenario, 42, 1.5);
//! assert_eq!(truth[0].position, [1.5, 0.0, 1.0]);
//! # Ok::<(), simulator::ScenarioError>(())
//! ```

#![warn(missing_docs)]

mod bounds;
mod camera_pose;
mod crowd;
mod error;
mod motion;
pub mod pedestrians;
mod presets;
mod random_walk;
pub mod render;
mod replay;
mod scenario;
mod seeding;
mod sensor_sim;
mod sensor_spec;
mod simulation;
mod target;
mod truth;
mod validate;

pub use bounds::BoundsBox;
pub use camera_pose::{look_at_projection, LookAt};
pub use error::ScenarioError;
pub use motion::{ConstantVelocity, Motion, Waypoints};
pub use presets::{default_room, dense, dense_scaled, ROOM_FLOOR, ROOM_HEIGHT};
pub use random_walk::{RandomWalk, DEFAULT_KNOT_INTERVAL_S};
pub use replay::{descriptors_and_sets, replay_lines, ReplayLines};
pub use scenario::Scenario;
pub use sensor_sim::SimulatedSensor;
pub use sensor_spec::SensorSpec;
pub use simulation::Simulation;
pub use target::Target;
pub use truth::{truth_objects, truth_set};
