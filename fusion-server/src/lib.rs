//! The fusion server: asynchronous sequential multi-sensor GM-PHD over Zenoh.
//!
//! [`engine::Engine`] admits measurement sets and processes each at once on a
//! [`timeline::Timeline`] (in stamp order; a late set rolls the filter back and re-processes)
//! with the [`tracker::Tracker`] (filter + labels + track confirmation). [`service::run`] wires
//! it to Zenoh; [`replay::replay`] runs it offline over a replay file and scores its output
//! against the file's truth with the `evaluation` crate.

pub mod checkpoint;
pub mod clock;
pub mod config;
pub mod engine;
mod engine_thread;
pub mod history;
pub mod latency;
pub mod pacing;
pub mod processing;
mod publisher;
mod rejection;
pub mod replay;
pub mod role;
pub mod sensors;
pub mod service;
pub mod timeline;
mod track_output;
pub mod tracker;
