//! `fusion-view`: a browser view of every fusion site a Zenoh client can reach — tracks with
//! trails and 2σ ellipses over a top and a side view of the site, the sensors where they are
//! (camera frusta, microphone pairs with their latest TDOA hyperbolas, LIDAR ranges; a sensor
//! whose liveliness is gone greyed out), tables of tracks and sensors, truth and live OSPA.
//!
//! [`inputs`] subscribes and queries over Zenoh into [`state::Sites`]; [`scene`] turns a site's
//! state into what the page draws; [`http`] serves the page (its files are compiled in, so it
//! works offline) and streams scenes to it as server-sent events.

pub mod geometry;
pub mod http;
pub mod inputs;
pub mod scene;
pub mod state;
