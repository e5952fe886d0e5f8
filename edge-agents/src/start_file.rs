//! `--start-file`: the stamp of the first frame read from a file that whoever rendered or recorded the
//! input writes once it is complete (`fusion-checker render` in the compose raw profile). The agent waits
//! for the file before it reads its input, so that agents started beside the renderer begin together
//! with it, on stamps it chose, without a shell to pass `--start` along.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::error::AgentError;

/// How often the file is looked for.
const POLL: Duration = Duration::from_millis(100);
/// How often the wait is logged.
const LOG_EVERY: Duration = Duration::from_secs(10);

/// Waits until `path` exists, then reads it: one Unix time in seconds (surrounding white space allowed).
/// A file that is there but does not hold a finite number is an error: waiting would not fix it.
pub fn wait_for_start(path: &Path) -> Result<f64, AgentError> {
    let began = Instant::now();
    let mut logged = None;
    loop {
        match std::fs::read_to_string(path) {
            Ok(text) => return parse_start(path, &text),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(start_file_error(path, e.to_string())),
        }
        if logged.is_none_or(|at: Instant| at.elapsed() >= LOG_EVERY) {
            tracing::info!(file = %path.display(), waited_s = began.elapsed().as_secs(), "waiting for the start file (the input is still being written)");
            logged = Some(Instant::now());
        }
        std::thread::sleep(POLL);
    }
}

/// The start time the file's text holds.
fn parse_start(path: &Path, text: &str) -> Result<f64, AgentError> {
    let start: f64 = text.trim().parse().map_err(|_| {
        start_file_error(
            path,
            format!("{:?} is not a Unix time in seconds", text.trim()),
        )
    })?;
    if !start.is_finite() {
        return Err(start_file_error(path, format!("{start} is not finite")));
    }
    tracing::info!(file = %path.display(), start, "start read from the start file");
    Ok(start)
}

fn start_file_error(path: &Path, reason: String) -> AgentError {
    AgentError::InvalidConfig {
        key: format!("--start-file {}", path.display()),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_file_gives_its_time() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cam1.start");
        std::fs::write(&path, "1763700000.250000\n").unwrap();
        assert_eq!(wait_for_start(&path).unwrap(), 1_763_700_000.25);
    }

    #[test]
    fn the_wait_ends_when_the_file_appears() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("late.start");
        let writer = {
            let path = path.clone();
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_millis(250));
                std::fs::write(path, "12.5").unwrap();
            })
        };
        assert_eq!(wait_for_start(&path).unwrap(), 12.5);
        writer.join().unwrap();
    }

    #[test]
    fn garbage_and_non_finite_times_are_refused_with_the_file_named() {
        let dir = tempfile::tempdir().unwrap();
        for text in ["soon", "", "inf", "NaN"] {
            let path = dir.path().join("bad.start");
            std::fs::write(&path, text).unwrap();
            let error = wait_for_start(&path).unwrap_err().to_string();
            assert!(error.contains("bad.start"), "{error}");
        }
    }
}
