//! Headless Chromium for the page tests: the DOM after the page's scripts ran, screenshots, and
//! reading table rows out of the serialised DOM.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

/// Chromium (Debian's `chromium` package; `CHROMIUM` overrides), when installed.
pub fn chromium() -> Option<PathBuf> {
    if let Ok(path) = std::env::var("CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            let out = Command::new("sh")
                .args(["-c", &format!("command -v {name}")])
                .output()
                .ok()?;
            let path = String::from_utf8(out.stdout).ok()?;
            let path = path.trim();
            (!path.is_empty()).then(|| PathBuf::from(path))
        })
}

fn headless(chromium: &Path, profile: &Path) -> Command {
    let mut cmd = Command::new(chromium);
    // No `--virtual-time-budget`: the page's event stream never ends, so virtual time would never
    // run out. The page draws the scene served with it before its load event, which is when
    // Chromium dumps or shoots it.
    // No sandbox: CI runs as root in a container, where Chromium's sandbox cannot start.
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
    ])
    .args(["--no-first-run", "--hide-scrollbars", "--mute-audio"])
    .arg(format!("--user-data-dir={}", profile.display()))
    .stdin(Stdio::null());
    cmd
}

/// Runs `cmd`, killing it after `limit`; its stdout.
fn run(mut cmd: Command, limit: Duration) -> anyhow::Result<String> {
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::null()).spawn()?;
    let stdout = child.stdout.take().expect("piped");
    let reader = std::thread::spawn(move || std::io::read_to_string(stdout));
    let deadline = std::time::Instant::now() + limit;
    loop {
        if let Some(status) = child.try_wait()? {
            let out = reader.join().expect("reader")?;
            anyhow::ensure!(status.success(), "chromium failed: {status}");
            return Ok(out);
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            anyhow::bail!("chromium did not finish within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The page's DOM once it has loaded (its scripts have drawn the scene served with it), serialised.
pub fn dump_dom(chromium: &Path, profile: &Path, url: &str) -> anyhow::Result<String> {
    let mut cmd = headless(chromium, profile);
    cmd.args(["--window-size=1400,900", "--dump-dom", url]);
    run(cmd, Duration::from_secs(60))
}

/// A PNG of the page at `width` × `height` CSS pixels.
pub fn screenshot(
    chromium: &Path,
    profile: &Path,
    url: &str,
    (width, height): (u32, u32),
    png: &Path,
) -> anyhow::Result<()> {
    let mut cmd = headless(chromium, profile);
    cmd.arg(format!("--window-size={width},{height}"))
        .arg(format!("--screenshot={}", png.display()))
        .arg(url);
    run(cmd, Duration::from_secs(60))?;
    anyhow::ensure!(png.exists(), "no screenshot written at {}", png.display());
    Ok(())
}

/// The attributes of each `<tr>` inside the table `id="{table}"` that has `attribute`.
pub fn rows(html: &str, table: &str, attribute: &str) -> Vec<Vec<(String, String)>> {
    let Some(start) = html.find(&format!("id=\"{table}\"")) else {
        return Vec::new();
    };
    let body = &html[start..];
    let body = &body[..body.find("</table>").unwrap_or(body.len())];
    body.split("<tr")
        .skip(1)
        .filter_map(|row| {
            let tag = &row[..row.find('>')?];
            let attrs = attributes(tag);
            attrs.iter().any(|(k, _)| k == attribute).then_some(attrs)
        })
        .collect()
}

fn attributes(tag: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = tag;
    while let Some(eq) = rest.find("=\"") {
        let name = rest[..eq]
            .rsplit(' ')
            .next()
            .unwrap_or("")
            .trim()
            .to_string();
        let value_start = eq + 2;
        let Some(len) = rest[value_start..].find('"') else {
            break;
        };
        out.push((name, rest[value_start..value_start + len].to_string()));
        rest = &rest[value_start + len + 1..];
    }
    out
}

/// The value of `name` among `attrs`.
pub fn attr<'a>(attrs: &'a [(String, String)], name: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.as_str())
}

/// Where CI collects artifacts: `target/artifacts` (`FUSION_ARTIFACTS` overrides).
pub fn artifacts_dir() -> PathBuf {
    let dir = std::env::var_os("FUSION_ARTIFACTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/artifacts"));
    std::fs::create_dir_all(&dir).expect("artifacts directory");
    dir
}
