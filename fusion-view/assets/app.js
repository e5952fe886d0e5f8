// fusion-view's page: draws the scenes the server streams (server-sent events on /events) in a
// top and a side view, and lists the tracks and sensors. Plain JavaScript, no dependencies.
"use strict";

const SVG_NS = "http://www.w3.org/2000/svg";
// World metres are drawn as centimetres of SVG user space, so text and dots get sensible sizes.
const CM = 100;

const ui = {
  site: document.getElementById("site"),
  pause: document.getElementById("pause"),
  follow: document.getElementById("follow"),
  summary: document.getElementById("summary"),
  top: document.getElementById("top"),
  side: document.getElementById("side"),
  tracks: document.querySelector("#tracks tbody"),
  sensors: document.querySelector("#sensors tbody"),
  trackCount: document.getElementById("track-count"),
  sensorCount: document.getElementById("sensor-count"),
};

const view = {
  site: new URLSearchParams(location.search).get("site") || "",
  paused: false,
  selected: null,
  latest: null,
  events: null,
};

// The two projections: which world axes go right and up.
const PLANES = {
  top: { h: 0, v: 1, ellipse: "top_ellipse" },
  side: { h: 0, v: 2, ellipse: "side_ellipse" },
};

function colour(id) {
  return `hsl(${(id * 137.508) % 360}, 70%, 42%)`;
}

function el(name, attrs, parent) {
  const node = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  if (parent) parent.appendChild(node);
  return node;
}

function fmt(value, digits) {
  return value === null || value === undefined || !Number.isFinite(value) ? "–" : value.toFixed(digits);
}

// SVG coordinates of a world point in a plane: right is +h, up is +v.
function at(plane, p) {
  return [p[plane.h] * CM, -p[plane.v] * CM];
}

function points(plane, line) {
  return line.map((p) => at(plane, p).map((c) => c.toFixed(1)).join(",")).join(" ");
}

// The part of the world a view shows: the site's extent, or around the followed track.
function frame(scene, plane) {
  const [lo, hi] = scene.extent;
  let x0 = lo[plane.h], x1 = hi[plane.h], y0 = lo[plane.v], y1 = hi[plane.v];
  const followed = ui.follow.checked && scene.tracks.find((t) => t.id === view.selected);
  if (followed) {
    const w = Math.max((x1 - x0) / 2, 1.5), h = Math.max((y1 - y0) / 2, 1.2);
    const c = followed.position;
    x0 = c[plane.h] - w / 2; x1 = x0 + w;
    y0 = c[plane.v] - h / 2; y1 = y0 + h;
  }
  return { x0, x1, y0, y1 };
}

function drawGrid(svg, f) {
  const g = el("g", {}, svg);
  for (let x = Math.ceil(f.x0); x <= f.x1; x += 1) {
    el("line", { class: "grid", x1: x * CM, x2: x * CM, y1: -f.y0 * CM, y2: -f.y1 * CM }, g);
    el("text", { class: "axis-label", x: x * CM + 2, y: -f.y0 * CM - 3 }, g).textContent = `${x}`;
  }
  for (let y = Math.ceil(f.y0); y <= f.y1; y += 1) {
    el("line", { class: "grid", x1: f.x0 * CM, x2: f.x1 * CM, y1: -y * CM, y2: -y * CM }, g);
    el("text", { class: "axis-label", x: f.x0 * CM + 2, y: -y * CM - 3 }, g).textContent = `${y}`;
  }
}

function drawSensor(svg, plane, sensor) {
  const g = el("g", { class: sensor.alive === false ? "sensor dead" : "sensor", "data-sensor": sensor.sensor }, svg);
  if (sensor.range) {
    const [c, r] = sensor.range;
    const [cx, cy] = at(plane, c);
    el("circle", { class: "range", cx, cy, r: r * CM }, g);
  }
  if (sensor.region) {
    const [lo, hi] = sensor.region;
    const [x0, y0] = at(plane, lo), [x1, y1] = at(plane, hi);
    el("rect", { class: "range", x: Math.min(x0, x1), y: Math.min(y0, y1), width: Math.abs(x1 - x0), height: Math.abs(y1 - y0) }, g);
  }
  for (const line of sensor.lines) el("polyline", { class: "sensor-body", points: points(plane, line) }, g);
  if (plane === PLANES.top) {
    for (const curve of sensor.curves) el("polyline", { class: "tdoa", points: points(plane, curve) }, g);
  }
  if (sensor.anchor) {
    const [x, y] = at(plane, sensor.anchor);
    el("circle", { class: "sensor-dot", cx: x, cy: y, r: 4 }, g);
    el("text", { class: "sensor-label", x: x + 6, y: y - 5 }, g).textContent = sensor.sensor;
  }
}

// In the side view people stand at much the same height, so labels beside the dots would overlap:
// there they stand above the dot, staggered by the track's rank.
function drawTrack(svg, plane, track, rank) {
  const c = colour(track.id);
  const g = el("g", { class: "track", "data-track": track.id }, svg);
  if (track.trail.length > 1) el("polyline", { class: "trail", stroke: c, points: points(plane, track.trail) }, g);
  const [x, y] = at(plane, track.position);
  const e = track[plane.ellipse];
  // SVG angles turn clockwise (y down): the world's counter-clockwise angle is negated.
  el("ellipse", {
    class: "ellipse", cx: x, cy: y, rx: Math.max(e.major * CM, 1), ry: Math.max(e.minor * CM, 1),
    stroke: c, fill: c, transform: `rotate(${(-e.angle * 180) / Math.PI} ${x} ${y})`,
  }, g);
  if (track.id === view.selected) el("circle", { class: "selected-ring", cx: x, cy: y, r: 11 }, g);
  el("circle", { cx: x, cy: y, r: 6, fill: track.weak ? "#fff" : c, stroke: c, "stroke-width": 2 }, g);
  const label = plane === PLANES.top ? { x: x + 8, y: y + 14 } : { x: x - 12, y: y - 12 - 16 * rank };
  el("text", { class: "track-label", ...label, fill: c }, g).textContent = `#${track.id}`;
  g.addEventListener("click", () => select(track.id));
}

function drawTruth(svg, plane, truth) {
  for (const object of truth || []) {
    const [x, y] = at(plane, object.position);
    el("path", { class: "truth", d: `M${x - 5},${y - 5}L${x + 5},${y + 5}M${x - 5},${y + 5}L${x + 5},${y - 5}` }, svg);
  }
}

function drawView(svg, plane, scene) {
  const f = frame(scene, plane);
  const pad = 12;
  svg.setAttribute("viewBox", `${f.x0 * CM - pad} ${-f.y1 * CM - pad} ${(f.x1 - f.x0) * CM + 2 * pad} ${(f.y1 - f.y0) * CM + 2 * pad}`);
  svg.setAttribute("preserveAspectRatio", "xMidYMid meet");
  svg.replaceChildren();
  drawGrid(svg, f);
  const [lo, hi] = scene.extent;
  const [vx0, vy0] = at(plane, lo), [vx1, vy1] = at(plane, hi);
  el("rect", { class: "volume", x: vx0, y: vy1, width: vx1 - vx0, height: vy0 - vy1 }, svg);
  for (const sensor of scene.sensors) drawSensor(svg, plane, sensor);
  drawTruth(svg, plane, scene.truth);
  scene.tracks.forEach((track, rank) => drawTrack(svg, plane, track, rank));
}

function cell(row, text, cls) {
  const td = document.createElement("td");
  td.textContent = text;
  if (cls) td.className = cls;
  row.appendChild(td);
  return td;
}

function trackRows(scene) {
  const rows = scene.tracks.map((t) => {
    const row = document.createElement("tr");
    row.dataset.trackId = String(t.id);
    row.dataset.position = t.position.map((v) => v.toFixed(3)).join(",");
    if (t.id === view.selected) row.className = "selected";
    const id = cell(row, "");
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = colour(t.id);
    id.append(swatch, `#${t.id}`);
    cell(row, t.position.map((v) => v.toFixed(2)).join(", "));
    cell(row, t.speed === null ? "–" : `${t.speed.toFixed(2)} m/s`);
    cell(row, `${t.age_s.toFixed(1)} s`);
    cell(row, t.weight.toFixed(2));
    row.addEventListener("click", () => select(t.id));
    return row;
  });
  ui.tracks.replaceChildren(...rows);
  ui.trackCount.textContent = `(${rows.length})`;
}

function sensorRows(scene) {
  const rows = scene.sensors.map((s) => {
    const row = document.createElement("tr");
    row.dataset.sensor = s.sensor;
    row.dataset.alive = String(s.alive === true);
    cell(row, s.sensor);
    cell(row, s.kind || "?");
    cell(row, s.alive === null ? "?" : s.alive ? "yes" : "no");
    cell(row, s.rate_hz === null ? "–" : `${s.rate_hz.toFixed(1)} Hz`);
    const counts = s.counts || [null, null, null, null, null];
    for (const n of counts) cell(row, n === null ? "–" : String(n));
    return row;
  });
  ui.sensors.replaceChildren(...rows);
  const alive = scene.sensors.filter((s) => s.alive === true).length;
  ui.sensorCount.textContent = `(${alive} of ${rows.length} alive)`;
}

function siteOptions(scene) {
  const names = scene.sites;
  const current = Array.from(ui.site.options).map((o) => o.value);
  if (names.join("\n") !== current.join("\n")) {
    ui.site.replaceChildren(...names.map((n) => new Option(n, n)));
  }
  ui.site.value = scene.site;
  ui.site.disabled = names.length < 2;
}

function summary(scene) {
  if (!scene.site) return "waiting for a site to publish…";
  const parts = [`seq ${scene.seq ?? "–"}`, `${scene.tracks.length} tracks`, `expected ${fmt(scene.expected_count, 2)}`];
  if (scene.stamp) parts.push(new Date(scene.stamp * 1000).toISOString().slice(11, 23) + " UTC");
  if (scene.ospa !== null) parts.push(`OSPA ${scene.ospa.toFixed(3)} m`);
  if (scene.server) parts.push(`${scene.server.components} components, p50 ${fmt(scene.server.latency_ms[0], 1)} ms`);
  if (!scene.status_fresh) parts.push("no status");
  if (view.paused) parts.push("PAUSED");
  return parts.join(" · ");
}

function render(scene) {
  view.latest = scene;
  if (view.paused) return;
  siteOptions(scene);
  drawView(ui.top, PLANES.top, scene);
  drawView(ui.side, PLANES.side, scene);
  trackRows(scene);
  sensorRows(scene);
  ui.summary.textContent = summary(scene);
}

function select(id) {
  view.selected = view.selected === id ? null : id;
  if (view.latest && !view.paused) render(view.latest);
}

function query() {
  return view.site ? `?site=${encodeURIComponent(view.site)}` : "";
}

function connect() {
  if (view.events) view.events.close();
  view.events = new EventSource(`/events${query()}`);
  view.events.addEventListener("scene", (e) => render(JSON.parse(e.data)));
  view.events.onerror = () => { ui.summary.textContent = "connection lost, retrying…"; };
}

ui.site.addEventListener("change", () => {
  view.site = ui.site.value;
  history.replaceState(null, "", `/${query()}`);
  fetch(`/api/scene${query()}`).then((r) => r.json()).then(render).catch(() => {});
  connect();
});
ui.pause.addEventListener("click", () => {
  view.paused = !view.paused;
  ui.pause.setAttribute("aria-pressed", String(view.paused));
  ui.pause.textContent = view.paused ? "Resume" : "Pause";
  if (!view.paused && view.latest) render(view.latest);
  else ui.summary.textContent += " · PAUSED";
});
ui.follow.addEventListener("change", () => {
  if (ui.follow.checked && view.selected === null && view.latest && view.latest.tracks.length) {
    view.selected = view.latest.tracks[0].id;
  }
  if (view.latest && !view.paused) render(view.latest);
});

// Draw the scene served with the page at once, then follow the stream.
try {
  render(JSON.parse(document.getElementById("initial-scene").textContent));
} catch (e) {
  ui.summary.textContent = "waiting for the first scene…";
}
connect();
