//! A server started before its router waits for it: it retries opening its session with a
//! growing pause, says so in its log, and serves as usual once the router is up.

mod support;

use checker::processes::free_port;
use checker::query_status;
use protocol::{Site, WireFormat};
use support::{scratch, sleep, start_server, Hub};

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_started_before_its_router_waits_for_it() -> anyhow::Result<()> {
    let dir = scratch("router-later");
    let log = dir.join("server.log");
    let endpoint = format!("tcp/127.0.0.1:{}", free_port()?);
    let mut server = start_server(&endpoint, &log, &[])?;
    sleep(2.0).await;
    assert!(server.is_running(), "the server gave up without its router");

    let hub = Hub::start_at(endpoint).await?;
    let mut status = None;
    for _ in 0..40 {
        sleep(0.25).await;
        if let Ok(s) = query_status(&hub.session, &Site::default(), WireFormat::Json).await {
            status = Some(s);
            break;
        }
    }
    let status = status.expect("the server answers once its router is up");
    assert_eq!(status.site, Site::default());
    let text = std::fs::read_to_string(&log)?;
    assert!(
        text.contains("zenoh session not open yet; retrying"),
        "the wait is logged: {text}"
    );
    Ok(())
}
