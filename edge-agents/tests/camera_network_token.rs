//! A network camera on Zenoh: the agent holds its liveliness token only while its source delivers. Nobody
//! serves the stream at first (no token), then ffmpeg serves a clip over HTTP (token back, sets
//! published), then the clip ends (token withdrawn again while the agent re-opens it), then SIGTERM.
//!
//! Needs the `ffmpeg` executable: skipped (saying so) without it, failed under CI.

mod live_support;

use std::process::{Command, Stdio};
use std::time::Duration;

use live_support::{have_ffmpeg, now, start_agent, terminate};
use zenoh::sample::SampleKind;

const SITE: &str = "agent-cam-test";
/// Upper bound on any wait.
const PATIENCE: Duration = Duration::from_secs(30);
/// How long the agent is watched before its stream is served: long enough for a token to show.
const QUIET: Duration = Duration::from_millis(1500);

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free loopback port")
}

/// The test's own Zenoh peer, listening on `port` of loopback.
async fn test_session(port: u16) -> zenoh::Session {
    let mut config = zenoh::Config::default();
    for (key, value) in [
        ("mode", "\"peer\"".to_owned()),
        ("listen/endpoints", format!("[\"tcp/127.0.0.1:{port}\"]")),
        ("scouting/multicast/enabled", "false".to_owned()),
    ] {
        config.insert_json5(key, &value).expect("zenoh config key");
    }
    zenoh::open(config).await.expect("test session opens")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_network_camera_holds_its_token_only_while_its_stream_delivers() {
    if !have_ffmpeg("a_network_camera_holds_its_token_only_while_its_stream_delivers") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let clip = dir.path().join("clip.mkv");
    let made = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-f", "lavfi"])
        .args(["-i", "testsrc=size=320x240:rate=10", "-t", "4"])
        .args(["-c:v", "ffv1", "-pix_fmt", "bgr0"])
        .arg(&clip)
        .status()
        .expect("ffmpeg runs");
    assert!(made.success());
    let descriptor = dir.path().join("cam.toml");
    std::fs::write(
        &descriptor,
        "sensor = \"netcam\"\ndetection_probability = 0.9\nclutter_rate = 0.5\n[model]\nkind = \"camera\"\n\
         projection = [[250, 160, 0, 0], [0, 120, -250, 500], [0, 1, 0, 0]]\n\
         image_size = [320, 240]\nnoise_std = [2.0, 2.0]\n",
    )
    .expect("write descriptor");

    let zenoh_port = free_port();
    let session = test_session(zenoh_port).await;
    let alive = session
        .liveliness()
        .declare_subscriber(format!("fusion/{SITE}/sensors/netcam/alive"))
        .history(true)
        .await
        .expect("liveliness subscriber");
    let sets = session
        .declare_subscriber(format!("fusion/{SITE}/sensors/netcam/measurements"))
        .await
        .expect("set subscriber");
    let url = format!("http://127.0.0.1:{}/live.mkv", free_port());
    let connect = format!("tcp/127.0.0.1:{zenoh_port}");
    let descriptor = descriptor.to_str().expect("utf-8 path");
    let agent = start_agent(
        &[
            "camera",
            "--descriptor",
            descriptor,
            "--site",
            SITE,
            "--video",
            &url,
            "--raw",
            "--mode",
            "peer",
            "--connect",
            &connect,
        ],
        Stdio::null(),
    );
    let next_token = || async {
        let sample = tokio::time::timeout(PATIENCE, alive.recv_async())
            .await
            .expect("a liveliness change")
            .expect("liveliness subscriber open");
        (now(), sample.kind())
    };
    // Nothing to read yet: an agent that has produced nothing holds no token.
    let quiet = tokio::time::timeout(QUIET, alive.recv_async()).await;
    assert!(
        quiet.is_err(),
        "no liveliness token while nobody serves the stream"
    );
    println!(
        "no token in the first {:.1} s: nothing to read",
        QUIET.as_secs_f64()
    );

    let mut server = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-re", "-i"])
        .arg(&clip)
        .args(["-c", "copy", "-f", "matroska", "-listen", "1", &url])
        .stdin(Stdio::null())
        .spawn()
        .expect("ffmpeg serves the clip");
    let served = now();
    let (up_at, kind) = next_token().await;
    assert_eq!(kind, SampleKind::Put, "back when the stream delivers");
    let first = tokio::time::timeout(PATIENCE, sets.recv_async())
        .await
        .expect("a set once the stream delivers")
        .expect("set subscriber open");
    println!(
        "token back {:.2} s after the server started; first set {} bytes",
        up_at - served,
        first.payload().len()
    );
    let (gone_at, kind) = next_token().await;
    assert_eq!(kind, SampleKind::Delete, "withdrawn when the stream ends");
    let _ = server.wait();
    println!(
        "token withdrawn {:.2} s after the server started (a 4 s clip)",
        gone_at - served
    );

    terminate(agent.child.id());
    let run = agent.finish(PATIENCE);
    assert!(run.success, "{}", run.log);
    assert!(
        run.log.contains("source down: sensor withdrawn"),
        "{}",
        run.log
    );
}
