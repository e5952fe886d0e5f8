//! The HTTP side: one page (HTML, CSS and JavaScript compiled into the binary, nothing fetched
//! from elsewhere), the scene of a site as JSON, and a server-sent event stream of scenes.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::{Query, State};
use axum::http::header;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use futures_util::stream::{self, Stream};
use serde::Deserialize;

use crate::inputs::SharedSites;
use crate::scene::{scene, Scene};

const INDEX_HTML: &str = include_str!("../assets/index.html");
const STYLE_CSS: &str = include_str!("../assets/style.css");
const APP_JS: &str = include_str!("../assets/app.js");

/// Scenes per second on the event stream.
const SCENES_PER_S: f64 = 5.0;

/// `?site=NAME`: which site a request is about (the first known one when absent or unknown).
#[derive(Debug, Deserialize)]
pub struct SiteQuery {
    site: Option<String>,
}

/// The routes: `/` (the page), `/style.css`, `/app.js`, `/api/scene?site=`, `/events?site=`.
pub fn router(sites: SharedSites) -> Router {
    Router::new()
        .route("/", get(index))
        .route(
            "/style.css",
            get(|| async { asset("text/css; charset=utf-8", STYLE_CSS) }),
        )
        .route(
            "/app.js",
            get(|| async { asset("text/javascript; charset=utf-8", APP_JS) }),
        )
        .route("/api/scene", get(scene_json))
        .route("/events", get(events))
        .with_state(sites)
}

fn asset(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

/// The page, with the current scene of the site asked for written into it, so that the page
/// shows it as soon as it has loaded (before the first event arrives).
async fn index(State(sites): State<SharedSites>, Query(query): Query<SiteQuery>) -> Response {
    // `</` could close the script element the JSON sits in; JSON allows `<\/` for it.
    let scene = to_json(&current(&sites, query.site.as_deref())).replace("</", "<\\/");
    let page = INDEX_HTML.replacen("/*SCENE*/", &scene, 1);
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        page,
    )
        .into_response()
}

fn current(sites: &SharedSites, site: Option<&str>) -> Scene {
    let sites = sites.lock().unwrap_or_else(|p| p.into_inner());
    scene(&sites, site, fusion_server::clock::now())
}

fn to_json(scene: &Scene) -> String {
    // A scene holds only finite numbers, strings and options; JSON writes a stray NaN as null.
    serde_json::to_string(scene).unwrap_or_else(|e| format!(r#"{{"error": "{e}"}}"#))
}

async fn scene_json(State(sites): State<SharedSites>, Query(query): Query<SiteQuery>) -> Response {
    let body = to_json(&current(&sites, query.site.as_deref()));
    (
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        body,
    )
        .into_response()
}

async fn events(
    State(sites): State<SharedSites>,
    Query(query): Query<SiteQuery>,
) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / SCENES_PER_S));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let stream = stream::unfold(
        (sites, query.site, tick),
        |(sites, site, mut tick)| async move {
            tick.tick().await;
            let event = Event::default()
                .event("scene")
                .data(to_json(&current(&sites, site.as_deref())));
            Some((Ok(event), (sites, site, tick)))
        },
    );
    Sse::new(stream).keep_alive(KeepAlive::default())
}
