//! The fusion server: asynchronous sequential multi-sensor GM-PHD over Zenoh.
//!
//! [`engine::Engine`] admits measurement sets, orders them by stamp in a [`reorder::ReorderBuffer`]
//! and runs the [`tracker::Tracker`] (filter + labels + track confirmation). [`service::run`] wires
//! it to Zenoh; [`replay::replay`] runs it offline over a replay file.

pub mod checkpoint;
pub mod clock;
pub mod config;
pub mod engine;
mod engine_thread;
pub mod latency;
pub mod limiter;
pub mod plot;
pub mod reorder;
pub mod replay;
pub mod sensors;
pub mod service;
pub mod tracker;
