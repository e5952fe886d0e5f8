//! The agent on Zenoh, over loopback: liveliness token, descriptor queryable in both forms, measurement sets
//! with consecutive `seq`, a client that starts before its router, and a clean stop on SIGTERM.
//!
//! The assertions are on what arrives, never on timing; waits only have generous upper bounds.

use std::net::TcpListener;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use protocol::{MeasurementSet, SensorDescriptor, WireFormat};
use zenoh::sample::SampleKind;
use zenoh::Session;

/// The site of these tests, apart from any other Zenoh traffic.
const SITE: &str = "agent-test";

/// Upper bound on any wait for the agent.
const PATIENCE: Duration = Duration::from_secs(30);

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free loopback port")
}

fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .expect("clock after 1970")
        .as_secs_f64()
}

/// `edge-agent sim` of one room sensor on the test's own site, connecting to the test session on `port`.
fn sim_args(sensor: &str, mode: &str, port: u16, start: &str, duration: &str) -> Vec<String> {
    let connect = format!("tcp/127.0.0.1:{port}");
    [
        "sim",
        "--site",
        SITE,
        "--sensor",
        sensor,
        "--mode",
        mode,
        "--connect",
        &connect,
        "--start",
        start,
        "--duration",
        duration,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// An agent process, killed if the test ends (or fails) before it exits.
struct Agent(Option<Child>);

impl Agent {
    /// Starts `edge-agent` with `args`; its logs go to the test's output.
    fn spawn(args: &[String]) -> Self {
        let child = Command::new(env!("CARGO_BIN_EXE_edge-agent"))
            .args(args)
            .env("RUST_LOG", "info,zenoh=error")
            .stdout(Stdio::null())
            .spawn()
            .expect("the edge-agent binary starts");
        Agent(Some(child))
    }

    fn pid(&self) -> String {
        self.0
            .as_ref()
            .map(|c| c.id().to_string())
            .unwrap_or_default()
    }

    /// Waits (off the async workers) for the agent to exit and returns whether it succeeded.
    async fn wait_success(mut self) -> bool {
        let mut child = self.0.take().expect("running agent");
        let status = tokio::task::spawn_blocking(move || child.wait())
            .await
            .expect("waiting task")
            .expect("agent exit status");
        status.success()
    }
}

impl Drop for Agent {
    fn drop(&mut self) {
        if let Some(child) = &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A session of the test itself, `mode` peer or router, listening on `port` of loopback.
async fn test_session(mode: &str, port: u16) -> Session {
    let mut config = zenoh::Config::default();
    let set = |config: &mut zenoh::Config, key: &str, value: String| {
        config.insert_json5(key, &value).expect("zenoh config key");
    };
    set(&mut config, "mode", format!("{mode:?}"));
    set(
        &mut config,
        "listen/endpoints",
        format!("[\"tcp/127.0.0.1:{port}\"]"),
    );
    set(&mut config, "scouting/multicast/enabled", "false".into());
    zenoh::open(config).await.expect("test session opens")
}

/// A subscriber of the test session, samples queued in a channel.
type SetSubscriber =
    zenoh::pubsub::Subscriber<zenoh::handlers::FifoChannelHandler<zenoh::sample::Sample>>;

/// Receives `count` sets, checking they arrive in the `expected` wire form; returns them in arrival order.
async fn receive_sets(
    subscriber: &SetSubscriber,
    count: usize,
    expected: WireFormat,
) -> Vec<MeasurementSet> {
    let mut sets = Vec::new();
    while sets.len() < count {
        let sample = tokio::time::timeout(PATIENCE, subscriber.recv_async())
            .await
            .expect("sets keep arriving")
            .expect("subscriber open");
        let format = WireFormat::from_zenoh(sample.encoding()).expect("a protocol encoding");
        assert_eq!(format, expected, "sets carry the agent's wire form");
        let set: MeasurementSet =
            protocol::decode(&sample.payload().to_bytes(), format).expect("a set decodes");
        set.validate().expect("a published set is valid");
        sets.push(set);
    }
    sets
}

/// Asks the descriptor queryable for `format` and decodes the reply.
async fn query_descriptor(session: &Session, key: &str, format: Option<&str>) -> SensorDescriptor {
    let selector = match format {
        Some(format) => format!("{key}?format={format}"),
        None => key.to_owned(),
    };
    let replies = session
        .get(selector)
        .timeout(Duration::from_secs(5))
        .await
        .expect("query sent");
    let reply = replies.recv_async().await.expect("one reply");
    let sample = reply.result().expect("a successful reply");
    let wire = WireFormat::from_zenoh(sample.encoding()).expect("a protocol encoding");
    let expected = match format {
        Some("json") => WireFormat::Json,
        _ => WireFormat::Postcard,
    };
    assert_eq!(wire, expected, "the reply's encoding says the asked form");
    protocol::decode(&sample.payload().to_bytes(), wire).expect("descriptor decodes")
}

fn assert_consecutive(sets: &[MeasurementSet]) {
    for pair in sets.windows(2) {
        assert_eq!(
            pair[1].seq,
            pair[0].seq + 1,
            "a gap in seq: {} then {}",
            pair[0].seq,
            pair[1].seq
        );
        assert!(pair[1].stamp > pair[0].stamp);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn peer_agent_announces_serves_publishes_and_leaves_cleanly() {
    let port = free_port();
    let session = test_session("peer", port).await;
    let alive = session
        .liveliness()
        .declare_subscriber("fusion/agent-test/sensors/*/alive")
        .history(true)
        .await
        .expect("liveliness subscriber");
    let sets = session
        .declare_subscriber("fusion/agent-test/sensors/cam1/measurements")
        .await
        .expect("set subscriber");
    // The first frame is due 2 s from now, time for the agent to start and connect.
    let start = format!("{:.3}", now() + 2.0);
    let args = sim_args("cam1", "peer", port, &start, "600");
    let agent = Agent::spawn(&args);

    let token = tokio::time::timeout(PATIENCE, alive.recv_async())
        .await
        .expect("the token appears")
        .expect("liveliness subscriber open");
    assert_eq!(
        token.key_expr().as_str(),
        "fusion/agent-test/sensors/cam1/alive"
    );
    assert_eq!(token.kind(), SampleKind::Put);

    let key = "fusion/agent-test/sensors/cam1/descriptor";
    let as_json = query_descriptor(&session, key, Some("json")).await;
    let as_postcard = query_descriptor(&session, key, None).await;
    assert_eq!(as_json, as_postcard);
    assert_eq!(as_json.sensor.as_str(), "cam1");
    as_json.validate().expect("the served descriptor is valid");

    let received = receive_sets(&sets, 20, WireFormat::Postcard).await;
    assert_consecutive(&received);

    // SIGTERM (what `docker stop` sends): the agent stops between frames, withdraws its token, exits 0.
    let pid = agent.pid();
    let killed = Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let gone = tokio::time::timeout(PATIENCE, alive.recv_async())
        .await
        .expect("the token is withdrawn")
        .expect("liveliness subscriber open");
    assert_eq!(gone.kind(), SampleKind::Delete);
    assert!(
        agent.wait_success().await,
        "the agent must exit 0 on SIGTERM"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn json_client_survives_its_router_coming_late_and_going_away() {
    let port = free_port();
    let start = format!("{:.3}", now() + 1.0);
    let mut args = sim_args("lidar", "client", port, &start, "12");
    args.push("--json".into());
    let agent = Agent::spawn(&args);
    // The router comes up only after the agent has failed to reach it at least once.
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let router = test_session("router", port).await;
    let key = "fusion/agent-test/sensors/lidar/measurements";
    let sets = router
        .declare_subscriber(key)
        .await
        .expect("set subscriber");
    let before = receive_sets(&sets, 5, WireFormat::Json).await;
    assert_consecutive(&before);
    assert_eq!(
        before[0].seq, 0,
        "nothing is published before the session is open"
    );

    // The router goes away for a while: the agent's puts fail or go nowhere, and it carries on.
    drop(sets);
    router.close().await.expect("router closes");
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let router = test_session("router", port).await;
    let sets = router
        .declare_subscriber(key)
        .await
        .expect("set subscriber");
    let after = receive_sets(&sets, 5, WireFormat::Json).await;
    assert_consecutive(&after);
    let last_before = before.last().expect("sets").seq;
    assert!(after[0].seq > last_before, "seq goes on across the outage");
    assert!(
        agent.wait_success().await,
        "the agent must exit 0 at the end of its duration"
    );
}
