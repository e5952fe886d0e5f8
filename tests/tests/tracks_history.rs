//! The server's JSON subscription and its tracks history over Zenoh: a JSON subscriber gets
//! decodable track sets on `fusion/<site>/tracks/json`; a `_time` query returns the sets stamped
//! in its range (the newest answer per stamp), in stamp order, in either encoding, none outside
//! it; a malformed `_time` gets an error reply and the server keeps answering.

mod support;

use std::ops::Bound;
use std::sync::{Arc, Mutex};
use std::time::{Duration, UNIX_EPOCH};

use fusion_server::history::{StampRange, TrackHistory};
use protocol::{keys, Site, TrackSet, WireFormat};
use support::{now, scratch, sleep, start_agents, start_server, Hub};
use zenoh::query::ConsolidationMode;
use zenoh::sample::Sample;

/// `t` (seconds since the epoch) in RFC 3339, as Zenoh's time ranges write fixed instants.
fn rfc3339(t: f64) -> String {
    let time = UNIX_EPOCH + Duration::from_secs_f64(t);
    let secs = time.duration_since(UNIX_EPOCH).expect("after the epoch");
    let (days, rest) = (secs.as_secs() / 86_400, secs.as_secs() % 86_400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{:09}Z",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60,
        secs.subsec_nanos()
    )
}

/// Every reply to `selector`: the decoded sets, and the error replies' texts.
async fn history(
    hub: &Hub,
    selector: &str,
    format: WireFormat,
) -> anyhow::Result<(Vec<TrackSet>, Vec<String>)> {
    let replies = hub
        .session
        .get(selector)
        .consolidation(ConsolidationMode::None)
        .timeout(Duration::from_secs(5))
        .await
        .map_err(|e| anyhow::anyhow!("get {selector}: {e}"))?;
    let (mut sets, mut errors) = (Vec::new(), Vec::new());
    while let Ok(reply) = replies.recv_async().await {
        match reply.result() {
            Ok(sample) => {
                anyhow::ensure!(WireFormat::from_zenoh(sample.encoding())? == format);
                sets.push(protocol::decode(&sample.payload().to_bytes(), format)?);
            }
            Err(e) => errors.push(e.payload().try_to_string().unwrap_or_default().to_string()),
        }
    }
    Ok((sets, errors))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn json_subscriptions_and_time_range_queries() -> anyhow::Result<()> {
    let dir = scratch("history");
    let hub = Hub::start().await?;
    let site = Site::default();
    // Every JSON put, in arrival order; and how many were not JSON or did not decode.
    let received: Arc<Mutex<(Vec<TrackSet>, usize)>> = Arc::default();
    let sink = received.clone();
    let _json = hub
        .session
        .declare_subscriber(keys::tracks_json_key(&site))
        .callback(move |sample: Sample| {
            let mut got = sink.lock().unwrap_or_else(|p| p.into_inner());
            let decoded = (sample.encoding() == &zenoh::bytes::Encoding::APPLICATION_JSON)
                .then(|| serde_json::from_slice::<TrackSet>(&sample.payload().to_bytes()).ok())
                .flatten();
            match decoded {
                Some(set) => got.0.push(set),
                None => got.1 += 1,
            }
        })
        .await
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let _server = start_server(&hub.endpoint, &dir.join("server.log"), &[])?;
    sleep(1.0).await;
    let start = now() + 0.5;
    let _agents = start_agents(&hub.endpoint, &dir.join("agents.log"), start, 30.0, 3)?;
    sleep(6.0).await;

    // A range that closed a second ago, so every set in it was published and kept.
    let (t0, t1) = (now() - 3.0, now() - 1.0);
    let range = format!("[{}..{}]", rfc3339(t0), rfc3339(t1));
    let (observed, undecodable) = received.lock().unwrap_or_else(|p| p.into_inner()).clone();
    println!(
        "{} JSON track sets received, {undecodable} not decodable",
        observed.len()
    );
    assert_eq!(undecodable, 0);
    assert!(
        observed.len() > 60,
        "only {} JSON sets in 6 s",
        observed.len()
    );
    assert!(
        observed.iter().any(|s| !s.tracks.is_empty()),
        "tracks in the JSON sets"
    );

    // What the server should answer: the newest answer per stamp of what it published.
    let mut expected = TrackHistory::new(600.0, usize::MAX);
    observed.iter().cloned().for_each(|s| expected.record(s));
    let stamps = StampRange {
        start: Bound::Included(t0),
        end: Bound::Included(t1),
    };
    let expected: Vec<u64> = expected.in_range(&stamps).map(|s| s.seq).collect();
    for format in [WireFormat::Json, WireFormat::Postcard] {
        let name = if format == WireFormat::Json {
            "json"
        } else {
            "postcard"
        };
        let selector = format!("{}?_time={range};format={name}", keys::tracks_key(&site));
        let (sets, errors) = history(&hub, &selector, format).await?;
        println!("{selector}: {} sets", sets.len());
        assert!(errors.is_empty(), "{errors:?}");
        assert!(sets.len() > 20, "{} sets in 2 s of history", sets.len());
        assert!(
            sets.windows(2).all(|w| w[0].stamp < w[1].stamp),
            "stamp order"
        );
        assert!(
            sets.iter().all(|s| stamps.contains(s.stamp)),
            "none outside the range"
        );
        let seqs: Vec<u64> = sets.iter().map(|s| s.seq).collect();
        assert_eq!(seqs, expected, "the published sets stamped in the range");
        for set in &sets {
            let published = observed
                .iter()
                .find(|o| o.seq == set.seq)
                .expect("published");
            // JSON on both sides is read by the same parser; postcard's floats are exact, the
            // subscriber's JSON ones may differ in the last bit.
            if format == WireFormat::Json {
                assert_eq!(published, set, "the history holds what was published");
            } else {
                assert!((published.stamp - set.stamp).abs() < 1e-6);
                assert_eq!(published.tracks.len(), set.tracks.len());
            }
        }
    }

    // A range in the past with nothing in it, and malformed ones.
    let nothing = format!("{}?_time=[now(-900s)..now(-800s)]", keys::tracks_key(&site));
    let (sets, errors) = history(&hub, &nothing, WireFormat::Postcard).await?;
    assert!(sets.is_empty() && errors.is_empty(), "{sets:?} {errors:?}");
    for bad in [
        "yesterday",
        "[now(-30s)..",
        "[now(s)..now()]",
        "[2020-01-01T00:00:00Z;1e300]",
    ] {
        let selector = format!("{}?_time={bad}", keys::tracks_key(&site));
        let (sets, errors) = history(&hub, &selector, WireFormat::Postcard).await?;
        println!("{selector}: error reply {errors:?}");
        assert!(sets.is_empty(), "{selector} answered with sets");
        assert_eq!(errors.len(), 1, "{selector}: one error reply");
    }
    // Still answering: the current set without `_time`, and live JSON puts.
    let current = checker::query_tracks(&hub.session, &site, WireFormat::Json).await?;
    assert!(current.stamp > t1);
    let before = received.lock().unwrap_or_else(|p| p.into_inner()).0.len();
    sleep(0.5).await;
    assert!(received.lock().unwrap_or_else(|p| p.into_inner()).0.len() > before);
    Ok(())
}
