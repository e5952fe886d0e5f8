//! `lidar --scans DIR --follow`: new scan files taken as they appear.
//!
//! The directory is polled every 100 ms. A `.pcd` / `.bin` file is taken once it is complete: present with a
//! non-zero size and the same size and modification time at two consecutive polls (so a writer that has
//! paused for more than 100 ms mid-file should write under a name starting with `.`, which is ignored, and
//! rename it into place). Each file is taken once, in name order among those complete at a poll, and stamped
//! with the host time at which it was taken less `--pipeline-delay-ms`. Files already there at start are
//! taken as well. A file that cannot be read is logged and skipped.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use crate::capture_clock::CaptureClock;
use crate::error::AgentError;
use crate::lidar::{read_scan, scan_format};
use crate::lidar_live::{Captured, ScanQueue};

/// Time between two looks at the directory.
const POLL: Duration = Duration::from_millis(100);

/// Starts the thread following `dir`.
pub fn start(dir: PathBuf, clock: CaptureClock, queue: ScanQueue) -> Result<(), AgentError> {
    std::fs::read_dir(&dir).map_err(|source| AgentError::Input {
        path: dir.clone(),
        source,
    })?;
    tracing::info!(dir = %dir.display(), "following the directory for new scans");
    std::thread::Builder::new()
        .name("scan-follow".into())
        .spawn(move || {
            let reason = follow(&dir, clock, &queue);
            queue.end(reason);
        })
        .map_err(|e| AgentError::Usage(format!("cannot start the directory follower: {e}")))?;
    Ok(())
}

/// Polls until the directory goes away or the run loop ends; returns why it stopped.
fn follow(dir: &Path, clock: CaptureClock, queue: &ScanQueue) -> String {
    let mut taken: HashSet<PathBuf> = HashSet::new();
    let mut seen: HashMap<PathBuf, (u64, Option<SystemTime>)> = HashMap::new();
    loop {
        let entries = match std::fs::read_dir(dir) {
            Ok(entries) => entries,
            Err(e) => return format!("{} cannot be read any more: {e}", dir.display()),
        };
        let mut ready = Vec::new();
        for entry in entries.flatten() {
            let path = entry.path();
            let hidden = path
                .file_name()
                .and_then(|n| n.to_str())
                .is_none_or(|n| n.starts_with('.'));
            if hidden || taken.contains(&path) || scan_format(&path).is_none() {
                continue;
            }
            let Ok(meta) = entry.metadata() else { continue };
            let now = (meta.len(), meta.modified().ok());
            if meta.is_file() && meta.len() > 0 && seen.get(&path) == Some(&now) {
                ready.push(path);
            } else {
                seen.insert(path, now);
            }
        }
        ready.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
        for path in ready {
            seen.remove(&path);
            taken.insert(path.clone());
            let stamp = clock.now();
            match read_scan(&path) {
                Ok(cloud) => {
                    if !queue.offer(Captured::Scan { stamp, cloud }) {
                        return "the run ended".into();
                    }
                }
                Err(error) => tracing::warn!(scan = %path.display(), %error, "scan skipped"),
            }
        }
        std::thread::sleep(POLL);
    }
}
