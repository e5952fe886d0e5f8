//! Plumbing shared by the fusion server and the edge agents: opening a Zenoh session from the
//! `[zenoh]` configuration section, rate-limited warnings, and shutdown on a signal.

pub mod log_limit;
pub mod session;
pub mod shutdown;

pub use log_limit::LogLimiter;
pub use session::{SessionError, ZenohConfig};
pub use shutdown::{wait_for_signal, Shutdown};
