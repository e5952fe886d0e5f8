//! Hot standby: two servers of role `auto` on one site. Started at once, exactly one ends up
//! active; the active one is killed (SIGKILL) and the standby takes over within a moment with
//! the same track ids and no set lost; the killed one returns as standby from the new active's
//! state, and takes over in its turn with the ids still unchanged.

mod support;

use std::collections::BTreeMap;
use std::process::Command;
use std::time::Duration;

use checker::processes::Managed;
use checker::Observer;
use protocol::{keys, InstanceId, ServerRole, Site, Status, TrackSet};
use support::{now, scratch, sleep, start_agents, start_server, Hub};

/// The room's third person enters at 4.5 s; tracks are confirmed well within 2 s after.
const ALL_IN_S: f64 = 6.5;

fn auto_server(hub: &Hub, dir: &std::path::Path, id: &str, log: &str) -> anyhow::Result<Managed> {
    start_server(
        &hub.endpoint,
        &dir.join(log),
        &[
            ("FUSION__SERVER__ROLE", "auto".into()),
            ("FUSION__SERVER__INSTANCE_ID", id.into()),
        ],
    )
}

/// One server's own status, `None` when it does not answer.
async fn instance_status(session: &zenoh::Session, id: &str) -> Option<Status> {
    let key = keys::server_status_key(&Site::default(), &InstanceId::new(id).ok()?);
    let replies = session
        .get(format!("{key}?format=json"))
        .timeout(Duration::from_secs(2))
        .await
        .ok()?;
    let sample = replies.recv_async().await.ok()?.into_result().ok()?;
    serde_json::from_slice(&sample.payload().to_bytes()).ok()
}

async fn role_of(session: &zenoh::Session, id: &str) -> Option<ServerRole> {
    instance_status(session, id).await.map(|s| s.role)
}

/// Waits up to `seconds` for the roles of `a` and `b` to be `want`.
async fn wait_roles(
    session: &zenoh::Session,
    want: (Option<ServerRole>, Option<ServerRole>),
    seconds: f64,
) -> (Option<ServerRole>, Option<ServerRole>) {
    let deadline = now() + seconds;
    loop {
        let got = (role_of(session, "a").await, role_of(session, "b").await);
        if got == want || now() > deadline {
            return got;
        }
        sleep(0.1).await;
    }
}

fn kill(server: &Managed) {
    let pid = server.id().expect("running").to_string();
    let _ = Command::new("kill").args(["-KILL", &pid]).status();
}

/// Track id → position in the first track set received 0.2 s or more after `since` (what the
/// killed server had in flight has arrived by then), waiting up to 2 s after `since` for one;
/// also returns how long after `since` it came.
async fn tracks_after(observer: &Observer, since: f64) -> Option<(f64, BTreeMap<u64, [f64; 3]>)> {
    sleep(0.2).await;
    let received = observer.snapshot().tracks.len();
    loop {
        let observed = observer.snapshot().tracks;
        if observed.len() > received {
            let latest: &TrackSet = observed.last()?;
            let ids = latest.tracks.iter().map(|t| (t.id, t.position)).collect();
            return Some((now() - since, ids));
        }
        if now() - since > 2.0 {
            return None;
        }
        sleep(0.01).await;
    }
}

fn ids_of(observer: &Observer) -> BTreeMap<u64, [f64; 3]> {
    let latest = observer.latest_tracks().expect("tracks published");
    latest.tracks.iter().map(|t| (t.id, t.position)).collect()
}

/// The same ids, each within `max_moved` metres of where it was.
fn same_people(before: &BTreeMap<u64, [f64; 3]>, after: &BTreeMap<u64, [f64; 3]>) -> bool {
    before.len() == after.len()
        && before.iter().all(|(id, p)| {
            after.get(id).is_some_and(|q| {
                let d2: f64 = p.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum();
                d2.sqrt() < 1.0
            })
        })
}

/// Kills `active`, then checks that `standby_id` publishes again within 2 s with the same ids,
/// having lost no set.
async fn takeover(
    hub: &Hub,
    observer: &Observer,
    active: &Managed,
    standby_id: &str,
) -> anyhow::Result<()> {
    let before = ids_of(observer);
    assert_eq!(
        before.len(),
        3,
        "three people tracked before the kill: {before:?}"
    );
    let killed = now();
    kill(active);
    let (resumed, after) = tracks_after(observer, killed)
        .await
        .expect("tracks resume within 2 s of the kill");
    println!(
        "killed the active server; {standby_id} published again within {resumed:.3} s \
         (sets looked for from 0.2 s after the kill on)"
    );
    println!("  ids before {:?}, after {:?}", before.keys(), after.keys());
    assert!(
        same_people(&before, &after),
        "ids changed: {before:?} -> {after:?}"
    );
    sleep(0.5).await;
    let status = instance_status(&hub.session, standby_id)
        .await
        .expect("the new active answers");
    assert_eq!(status.role, ServerRole::Active);
    for sensor in &status.sensors {
        assert_eq!(sensor.lost, 0, "no set lost: {sensor:?}");
        assert!(sensor.processed > 0, "{sensor:?}");
    }
    Ok(())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_standby_takes_over_with_the_same_ids_and_hands_its_state_back() -> anyhow::Result<()> {
    let dir = scratch("standby");
    let hub = Hub::start().await?;
    let observer = Observer::start(&hub.session, &Site::default()).await?;
    // Both at once: each may see itself alone and become active; the split brain settles on a.
    let a = auto_server(&hub, &dir, "a", "a.log")?;
    let b = auto_server(&hub, &dir, "b", "b.log")?;
    let settled = (Some(ServerRole::Active), Some(ServerRole::Standby));
    let roles = wait_roles(&hub.session, settled, 10.0).await;
    assert_eq!(
        roles, settled,
        "a active, b standby after starting together"
    );

    let start = now() + 0.5;
    let _agents = start_agents(&hub.endpoint, &dir.join("agents.log"), start, 30.0, 11)?;
    sleep(0.5 + ALL_IN_S + 2.0).await;
    takeover(&hub, &observer, &a, "b").await?;
    drop(a);

    // a returns: b stays active, a stands by from b's state.
    let a = auto_server(&hub, &dir, "a", "a2.log")?;
    let swapped = (Some(ServerRole::Standby), Some(ServerRole::Active));
    assert_eq!(wait_roles(&hub.session, swapped, 10.0).await, swapped);
    let log = std::fs::read_to_string(dir.join("a2.log"))?;
    assert!(
        log.contains("standing by from the active server's filter state"),
        "{log}"
    );
    sleep(3.0).await;
    takeover(&hub, &observer, &b, "a").await?;
    drop(a);
    Ok(())
}
