//! Running `edge-agent` on live input: its replay lines read as they come, each with the wall time at which
//! it arrived, and its log.
// Each test binary uses a different part of this module.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::thread::JoinHandle;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// True when `ffmpeg` runs. When it does not: under CI (`CI` set, where `.ci/run` installs it) the test
/// fails; elsewhere it says it is skipped.
pub fn have_ffmpeg(test: &str) -> bool {
    let runs = Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !runs {
        assert!(
            std::env::var_os("CI").is_none(),
            "ffmpeg is not installed: .ci/run installs it before the tests"
        );
        println!("SKIPPED {test}: ffmpeg is not installed (apt-get install ffmpeg)");
    }
    runs
}

/// Seconds since the Unix epoch.
pub fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0)
}

/// A running agent whose stdout lines are collected with their arrival times.
pub struct LiveAgent {
    /// The process.
    pub child: Child,
    /// Its stdin, when it was asked for.
    pub stdin: Option<ChildStdin>,
    /// Each stdout line with the wall time it arrived.
    pub lines: Receiver<(f64, String)>,
    stdout: JoinHandle<()>,
    stderr: JoinHandle<String>,
}

/// Starts `edge-agent` with `args`, its stdin from `stdin`, its log at info level collected.
pub fn start_agent(args: &[&str], stdin: Stdio) -> LiveAgent {
    let mut child = Command::new(env!("CARGO_BIN_EXE_edge-agent"))
        .args(args)
        .env("RUST_LOG", "info")
        .env("NO_COLOR", "1")
        .stdin(stdin)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the edge-agent binary runs");
    let stdout = child.stdout.take().expect("stdout piped");
    let mut stderr = child.stderr.take().expect("stderr piped");
    let (sender, lines) = channel();
    let stdout = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            if sender.send((now(), line)).is_err() {
                break;
            }
        }
    });
    let stderr = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let stdin = child.stdin.take();
    LiveAgent {
        child,
        stdin,
        lines,
        stdout,
        stderr,
    }
}

/// What a finished agent left.
pub struct Finished {
    /// Whether it exited with 0.
    pub success: bool,
    /// Its exit status, for messages.
    pub status: String,
    /// Every stdout line with its arrival time.
    pub lines: Vec<(f64, String)>,
    /// Its log.
    pub log: String,
}

impl LiveAgent {
    /// The next stdout line, waiting at most `timeout`.
    pub fn next_line(&self, timeout: Duration) -> Option<(f64, String)> {
        self.lines.recv_timeout(timeout).ok()
    }

    /// Waits for the agent to exit (closing its stdin first), at most `timeout`, then kills it and fails.
    pub fn finish(mut self, timeout: Duration) -> Finished {
        drop(self.stdin.take());
        let deadline = std::time::Instant::now() + timeout;
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("wait for edge-agent") {
                break status;
            }
            if std::time::Instant::now() > deadline {
                let _ = self.child.kill();
                let _ = self.child.wait();
                panic!(
                    "edge-agent did not exit within {timeout:?}: {}",
                    self.stderr.join().unwrap_or_default()
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let log = self.stderr.join().unwrap_or_default();
        let _ = self.stdout.join();
        assert!(!log.contains("panicked"), "edge-agent panicked: {log}");
        Finished {
            success: status.success(),
            status: status.to_string(),
            lines: self.lines.try_iter().collect(),
            log,
        }
    }
}

/// Sends SIGTERM to `pid` (what `docker stop` sends).
pub fn terminate(pid: u32) {
    let status = Command::new("kill")
        .args(["-TERM", &pid.to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success(), "kill -TERM {pid}");
}

/// The pids of the children of `pid` (every thread's), from /proc.
pub fn children_of(pid: u32) -> Vec<u32> {
    let Ok(threads) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return Vec::new();
    };
    let mut children = Vec::new();
    for thread in threads.flatten() {
        let text = std::fs::read_to_string(thread.path().join("children")).unwrap_or_default();
        children.extend(
            text.split_whitespace()
                .filter_map(|c| c.parse::<u32>().ok()),
        );
    }
    children
}
