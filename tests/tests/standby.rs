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

/// The roles of servers `ids`, polled every 0.1 s until `done` accepts them or `seconds` have
/// passed; returns the last seen.
async fn watch_roles(
    session: &zenoh::Session,
    ids: [&str; 2],
    seconds: f64,
    done: impl Fn(&[Option<ServerRole>; 2]) -> bool,
) -> [Option<ServerRole>; 2] {
    let deadline = now() + seconds;
    loop {
        let got = [
            role_of(session, ids[0]).await,
            role_of(session, ids[1]).await,
        ];
        if done(&got) || now() > deadline {
            return got;
        }
        sleep(0.1).await;
    }
}

/// Waits up to `seconds` for the roles of servers `ids` to be `want`; returns the last seen.
async fn wait_roles(
    session: &zenoh::Session,
    ids: [&str; 2],
    want: [ServerRole; 2],
    seconds: f64,
) -> [Option<ServerRole>; 2] {
    watch_roles(session, ids, seconds, |got| *got == want.map(Some)).await
}

/// Waits up to `seconds` for exactly one of `a` and `b` to be active and the other standby;
/// returns the active one's id.
async fn wait_one_active(session: &zenoh::Session, seconds: f64) -> Option<&'static str> {
    use ServerRole::{Active, Standby};
    let one_active = |got: &[Option<ServerRole>; 2]| {
        matches!(
            got,
            [Some(Active), Some(Standby)] | [Some(Standby), Some(Active)]
        )
    };
    match watch_roles(session, ["a", "b"], seconds, one_active).await {
        [Some(Active), Some(Standby)] => Some("a"),
        [Some(Standby), Some(Active)] => Some("b"),
        _ => None,
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
    // Both at once: whichever is seen first stays active (or, if each saw itself alone, the
    // split brain settles on a); either way exactly one is active.
    let a = auto_server(&hub, &dir, "a", "a.log")?;
    let b = auto_server(&hub, &dir, "b", "b.log")?;
    let first_active = wait_one_active(&hub.session, 10.0)
        .await
        .expect("exactly one of a and b active, the other standby, after starting together");
    println!("started together: {first_active} is active");
    let ((active, active_id), (standby, standby_id)) = if first_active == "a" {
        ((a, "a"), (b, "b"))
    } else {
        ((b, "b"), (a, "a"))
    };

    let start = now() + 0.5;
    let _agents = start_agents(&hub.endpoint, &dir.join("agents.log"), start, 30.0, 11)?;
    sleep(0.5 + ALL_IN_S + 2.0).await;
    takeover(&hub, &observer, &active, standby_id).await?;
    drop(active);

    // The killed one returns: the new active stays, the returning one stands by from its state.
    let log_name = format!("{active_id}2.log");
    let returned = auto_server(&hub, &dir, active_id, &log_name)?;
    let swapped = [ServerRole::Standby, ServerRole::Active];
    assert_eq!(
        wait_roles(&hub.session, [active_id, standby_id], swapped, 10.0).await,
        swapped.map(Some)
    );
    let log = std::fs::read_to_string(dir.join(&log_name))?;
    assert!(
        log.contains("standing by from the active server's filter state"),
        "{log}"
    );
    sleep(3.0).await;
    takeover(&hub, &observer, &standby, active_id).await?;
    drop(returned);
    Ok(())
}
