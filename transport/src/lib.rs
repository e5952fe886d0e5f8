//! Zenoh plumbing shared by the fusion server and the edge agents: opening a session from the
//! `[zenoh]` configuration section, and putting or replying with protocol messages in the
//! encoding the contract asks for.

pub mod session;

pub use session::{SessionError, ZenohConfig};
