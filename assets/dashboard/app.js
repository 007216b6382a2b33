// proleg dashboard: the runs of a store and one run's learning curve, evaluations and best
// candidate, kept up to date by the server's event stream (no reload). Every name from the
// store goes into text nodes (textContent), never into markup.
"use strict";

const state = {
  version: 0,
  runs: [],
  run: null,          // the open run's id
  engines: [],        // the engines its candidates are scored on
  evaluations: [],    // its evaluations read so far
  sort: { key: "number", down: false },
  compare: new Set(),
  curve: null,
  comparePlot: null,
  map: null,          // the open run's MAP-Elites archive, when it keeps one
  mapCursor: null,    // the cell the keyboard points at
  evaluation: null,   // the evaluation replayed (video, data file), when one is
  media: null,        // where its video and data file are
  dataPlot: null,
  data: null,         // its data file's series
};
// For tests and the curious: what the page shows now.
window.proleg = state;

const $ = (sel) => document.querySelector(sel);
const fmt = (x, digits = 4) => (x === null || x === undefined ? "—" : Number(x).toFixed(digits));

function cell(row, text, cls) {
  const td = document.createElement("td");
  td.textContent = text;
  if (cls) td.className = cls;
  row.appendChild(td);
  return td;
}

async function getJson(url) {
  const r = await fetch(url, { credentials: "same-origin" });
  if (!r.ok) throw new Error(`${url}: ${r.status} ${await r.text()}`);
  return r.json();
}

function setStatus(text, warn) {
  const s = $("#status");
  s.textContent = text;
  s.className = warn ? "warn" : "muted";
}

// One refresh at a time: an event during a refresh asks for one more after it (two at once
// would read the same evaluations twice).
let refreshing = null, refreshAgain = false;
async function refresh() {
  if (refreshing) { refreshAgain = true; return refreshing; }
  refreshing = (async () => {
    do { refreshAgain = false; await refreshOnce(); } while (refreshAgain);
  })();
  try { await refreshing; } finally { refreshing = null; }
}

async function refreshOnce() {
  let data;
  try {
    data = await getJson("api/runs");
  } catch (e) {
    setStatus(`cannot read the dashboard: ${e.message}`, true);
    return;
  }
  state.version = data.version;
  state.runs = data.runs;
  $("#store").textContent = data.store;
  if (data.reconnecting) setStatus(`reconnecting to the store (${data.reconnecting})`, true);
  else setStatus(`live · version ${data.version}`, false);
  renderRuns();
  if (state.run !== null) await loadRun();
  if (state.compare.size >= 2) await renderCompare();
}

function renderRuns() {
  const body = $("#runs tbody");
  body.replaceChildren();
  for (const r of state.runs) {
    const tr = document.createElement("tr");
    tr.className = "run-row" + (r.id === state.run ? " selected" : "");
    tr.tabIndex = 0;
    tr.dataset.run = r.id;
    const pick = document.createElement("td");
    const box = document.createElement("input");
    box.type = "checkbox";
    box.checked = state.compare.has(r.id);
    box.setAttribute("aria-label", `compare run ${r.id}`);
    box.addEventListener("click", (ev) => ev.stopPropagation());
    box.addEventListener("change", () => {
      if (box.checked) state.compare.add(r.id); else state.compare.delete(r.id);
      renderCompare();
    });
    pick.appendChild(box);
    tr.appendChild(pick);
    cell(tr, String(r.id), "num");
    cell(tr, r.config);
    cell(tr, r.algorithm);
    cell(tr, r.engines.join(", ") || "—");
    cell(tr, r.finished ? "finished" : "running or stopped");
    cell(tr, evaluationCount(r), "num evaluations");
    cell(tr, r.pending === null ? "—" : String(liveWorkers(r).length), "num");
    cell(tr, fmt(r.best), "num");
    cell(tr, r.started);
    tr.addEventListener("click", () => openRun(r.id));
    tr.addEventListener("keydown", (ev) => { if (ev.key === "Enter") openRun(r.id); });
    body.appendChild(tr);
  }
}

// "done", and for a shared run what its queue holds.
function evaluationCount(r) {
  if (r.pending === null) return String(r.evaluations);
  return `${r.evaluations} done, ${r.pending} pending, ${r.running} claimed`;
}

// Workers whose lease still holds (by this browser's clock against the database's).
function liveWorkers(r) {
  const now = Date.now() / 1000;
  return r.workers.filter((w) => w.lease_until !== null && w.lease_until > now);
}

async function openRun(id) {
  state.run = id;
  if (location.hash !== `#run=${id}`) history.replaceState(null, "", `#run=${id}`);
  state.evaluations = [];
  if (state.curve) { state.curve.destroy(); state.curve = null; }
  state.map = null;
  $("#map-box").hidden = true;
  closeEvaluation();
  $("#run").hidden = false;
  renderRuns();
  await loadRun();
}

async function loadRun() {
  const id = state.run, from = state.evaluations.length;
  let data;
  try {
    data = await getJson(`api/runs/${id}?from=${from}`);
  } catch (e) {
    setStatus(e.message, true);
    return;
  }
  // Another run opened, or another read came first, meanwhile: this answer is stale.
  if (id !== state.run || state.evaluations.length !== from) return;
  state.evaluations.push(...data.evaluations);
  const r = data.run;
  state.engines = r.engines;
  $("#run-title").textContent = `Run ${r.id}: ${r.config}`;
  const summary = $("#run-summary");
  summary.textContent = `${r.algorithm} on ${r.engines.join(", ") || "an engine not known here"}, ` +
    `seed ${r.seed}, ${r.fitness} over ${r.duration} s episodes; ` +
    `${evaluationCount(r)} evaluations of ${r.duration} s simulated each (${fmt(r.compute_seconds, 1)} s of computing), best ${fmt(r.best)}` +
    (r.best_engines.length ? ` (${r.best_engines.map(([k, s]) => `${k} ${fmt(s)}`).join(", ")})` : "") +
    (r.rejected ? `; ${r.rejected} bodies rejected` : "") + (r.finished ? "; finished" : "");
  summary.dataset.evaluations = String(state.evaluations.length);
  $("#csv").href = `api/runs/${id}/evaluations.csv`;
  renderBest(r);
  renderCurve();
  renderEvaluations();
  renderWorkers(r);
  renderRejected();
  renderEpisodes(data.episodes);
  if (r.algorithm.includes("MAP-Elites")) await loadMap(id);
}

// Score to colour: blue (low) to red (high).
function heat(t) {
  const h = 240 * (1 - Math.min(1, Math.max(0, t)));
  return `hsl(${h}, 75%, 50%)`;
}

async function loadMap(id) {
  let map;
  try {
    map = await getJson(`api/runs/${id}/map`);
  } catch (e) {
    $("#map-box").hidden = false;
    $("#map-summary").textContent = e.message;
    return;
  }
  state.map = map;
  drawMap(map);
}

// The archive as a coloured grid; the mouse or the keyboard's cursor names a cell's elite.
function drawMap(map) {
  $("#map-box").hidden = false;
  const finite = map.cells.map((c) => c.score).filter(Number.isFinite);
  $("#map-summary").textContent = `${map.summary}; x (left to right): ${map.labels[0]}, ` +
    `y (bottom to top): ${map.labels[1]}; colour: blue ${fmt(Math.min(...finite))} to red ${fmt(Math.max(...finite))}`;
  const canvas = $("#map");
  const ctx = canvas.getContext("2d");
  const [nx, ny] = map.bins;
  const w = canvas.width / nx, h = canvas.height / ny;
  const scores = map.cells.map((c) => c.score).filter(Number.isFinite);
  const lo = Math.min(...scores), hi = Math.max(...scores);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.strokeStyle = "rgba(128,128,128,0.3)";
  for (let x = 0; x < nx; x++) for (let y = 0; y < ny; y++) ctx.strokeRect(x * w, (ny - 1 - y) * h, w, h);
  for (const c of map.cells) {
    ctx.fillStyle = heat(hi > lo ? (c.score - lo) / (hi - lo) : 1);
    ctx.fillRect(c.x * w, (ny - 1 - c.y) * h, w, h);
  }
  const describe = (x, y) => {
    const c = map.cells.find((k) => k.x === x && k.y === y);
    $("#map-hover").textContent = c
      ? `cell (${x}, ${y}): score ${fmt(c.score)}, genome ${c.genome.join(" ")}`
      : `cell (${x}, ${y}): empty`;
  };
  canvas.onmousemove = (ev) => {
    const r = canvas.getBoundingClientRect();
    const x = Math.floor(((ev.clientX - r.left) / r.width) * nx);
    const y = ny - 1 - Math.floor(((ev.clientY - r.top) / r.height) * ny);
    describe(x, y);
  };
  // The keyboard's way over the map: arrows move a cursor from cell to cell.
  const cursor = state.mapCursor || { x: 0, y: 0 };
  canvas.onkeydown = (ev) => {
    const step = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] }[ev.key];
    if (!step) return;
    ev.preventDefault();
    cursor.x = Math.min(nx - 1, Math.max(0, cursor.x + step[0]));
    cursor.y = Math.min(ny - 1, Math.max(0, cursor.y + step[1]));
    state.mapCursor = cursor;
    drawMap(map);
  };
  if (state.mapCursor) {
    ctx.strokeStyle = getComputedStyle(document.body).color;
    ctx.lineWidth = 2;
    ctx.strokeRect(cursor.x * w + 1, (ny - 1 - cursor.y) * h + 1, w - 2, h - 2);
    ctx.lineWidth = 1;
    describe(cursor.x, cursor.y);
  }
}

function renderBest(r) {
  const body = $("#best tbody");
  body.replaceChildren();
  for (const [gene, value] of r.best_values) {
    const tr = document.createElement("tr");
    cell(tr, gene);
    cell(tr, value, "num");
    body.appendChild(tr);
  }
}

// The best score so far comes with each evaluation (the store's table computes it once).
function curveData(evals) {
  return [evals.map((e) => e.number), evals.map((e) => e.best), evals.map((e) => e.score)];
}

// Axes drawn in the page's text colour (readable in the light and the dark scheme).
function axes(x, y) {
  const fg = getComputedStyle(document.body).color;
  const grid = { stroke: "rgba(128,128,128,0.25)" };
  return [{ label: x, stroke: fg, grid }, { label: y, stroke: fg, grid }];
}

function plotWidth(el) {
  // A few pixels short of the box: uPlot rounds its canvas up.
  return Math.max(300, (el.clientWidth || 800) - 4);
}

function renderCurve() {
  const el = $("#curve");
  const data = curveData(state.evaluations);
  if (!state.curve) {
    const opts = {
      title: "Learning curve",
      width: plotWidth(el), height: 280,
      scales: { x: { time: false } },
      axes: axes("evaluation", "score"),
      series: [
        { label: "evaluation" },
        { label: "best so far", stroke: "#0b61c4", width: 2 },
        { label: "each evaluation", stroke: "#9aa7b4", paths: () => null, points: { show: true, size: 4 } },
      ],
    };
    state.curve = new uPlot(opts, data, el);
  } else {
    state.curve.setData(data);
  }
}

function renderEvaluations() {
  const min = parseFloat($("#filter").value);
  const { key, down } = state.sort;
  const rows = state.evaluations
    .filter((e) => Number.isNaN(min) || (e.score !== null && e.score >= min))
    .sort((a, b) => {
      const av = a[key] ?? -Infinity, bv = b[key] ?? -Infinity;
      return down ? bv - av : av - bv;
    })
    .slice(0, 500);
  const body = $("#evaluations tbody");
  body.replaceChildren();
  for (const e of rows) {
    const tr = document.createElement("tr");
    cell(tr, String(e.number), "num");
    cell(tr, String(e.round), "num");
    cell(tr, e.rejected ? `rejected: ${e.rejected}` : fmt(e.score), "num");
    cell(tr, e.values.map((v) => fmt(v, 3)).join("  "));
    const play = document.createElement("td");
    if (!e.rejected) {
      const b = document.createElement("button");
      b.textContent = "video & data";
      b.className = "replay";
      b.dataset.number = e.number;
      b.setAttribute("aria-label", `replay evaluation ${e.number}: video and data file`);
      b.addEventListener("click", () => openEvaluation(e.number));
      play.appendChild(b);
      // The 3D replay in a page of its own: this evaluation, beside the run's best, or on
      // both engines when the run scores on both.
      const links = [[`replay?a=${state.run}/${e.number}`, "3D", `3D replay of evaluation ${e.number}`],
        [`replay?a=${state.run}/${e.number}&b=${state.run}/best`, "3D vs best", `evaluation ${e.number} beside the run's best in 3D`]];
      if ((state.engines || []).length > 1) {
        links.push([`replay?a=${state.run}/${e.number}/${state.engines[0]}&b=${state.run}/${e.number}/${state.engines[1]}`,
          "3D both engines", `evaluation ${e.number} on ${state.engines.join(" and ")} in 3D`]);
      }
      for (const [href, text, label] of links) {
        const a = document.createElement("a");
        a.href = href;
        a.target = "_blank";
        a.rel = "noopener";
        a.className = "replay3d";
        a.textContent = text;
        a.setAttribute("aria-label", label);
        play.append(" ", a);
      }
    }
    tr.appendChild(play);
    body.appendChild(tr);
  }
}

function renderWorkers(r) {
  const box = $("#workers-box");
  box.hidden = r.pending === null;
  const body = $("#workers tbody");
  body.replaceChildren();
  const now = Date.now() / 1000;
  for (const w of r.workers) {
    const tr = document.createElement("tr");
    cell(tr, w.worker);
    cell(tr, String(w.running), "num");
    cell(tr, String(w.done), "num");
    const left = w.lease_until === null ? null : w.lease_until - now;
    cell(tr, left === null ? "—" : left >= 0 ? `in ${left.toFixed(0)} s` : `${(-left).toFixed(0)} s ago`, "num");
    cell(tr, left === null ? "idle on this run" : left >= 0 ? "live" : "lease ran out");
    body.appendChild(tr);
  }
}

// Rejected bodies grouped by their reason, most frequent first.
function renderRejected() {
  const groups = new Map();
  for (const e of state.evaluations) {
    if (!e.rejected) continue;
    const g = groups.get(e.rejected) || { count: 0, first: e.number };
    g.count += 1;
    groups.set(e.rejected, g);
  }
  $("#rejected-box").hidden = groups.size === 0;
  const body = $("#rejected tbody");
  body.replaceChildren();
  for (const [reason, g] of [...groups].sort((a, b) => b[1].count - a[1].count)) {
    const tr = document.createElement("tr");
    cell(tr, reason);
    cell(tr, String(g.count), "num");
    cell(tr, String(g.first), "num");
    body.appendChild(tr);
  }
}

function renderEpisodes(episodes) {
  $("#episodes-box").hidden = episodes.length === 0;
  const body = $("#episodes tbody");
  body.replaceChildren();
  for (const e of episodes) {
    const tr = document.createElement("tr");
    cell(tr, String(e.episode), "num");
    cell(tr, String(e.seed), "num");
    cell(tr, e.draws);
    body.appendChild(tr);
  }
}

// An evaluation replayed: asks the server for its video and data file (made once, in a
// queue) and shows each when it is ready.
async function openEvaluation(number) {
  const id = state.run;
  state.evaluation = number;
  state.media = null;
  state.data = null;
  if (state.dataPlot) { state.dataPlot.destroy(); state.dataPlot = null; }
  const video = $("#eval-video");
  video.removeAttribute("src");
  video.hidden = true;
  $("#eval-data").hidden = true;
  $("#eval").hidden = false;
  $("#eval-title").textContent = `Run ${id}, evaluation ${number}, replayed`;
  $("#eval-status").textContent = "asking for its video and data file…";
  $("#eval").scrollIntoView({ block: "nearest" });
  const r = await fetch(mediaUrl(id, number), { method: "POST", headers: { "X-Proleg": "1" }, credentials: "same-origin" });
  if (!r.ok) { $("#eval-status").textContent = `${r.status} ${await r.text()}`; return; }
  await followMedia(id, number, await r.json());
}

function mediaUrl(id, number, file = "media") {
  return `api/runs/${id}/evaluations/${number}/${file}`;
}

function closeEvaluation() {
  state.evaluation = null;
  $("#eval").hidden = true;
  const video = $("#eval-video");
  video.pause();
  video.removeAttribute("src");
}

function describeMedium(what, m) {
  switch (m.state) {
    case "queued": return `${what}: queued (${m.ahead} before it)`;
    case "making": return `${what}: being made`;
    case "ready": return `${what}: ready`;
    case "failed": return `${what} failed: ${m.error}`;
    case "unavailable": return `no ${what}: ${m.error}`;
    default: return `${what}: not asked for`;
  }
}

const pending = (m) => m.state === "queued" || m.state === "making";

// Shows what is ready; asks again every second while something is still being made.
async function followMedia(id, number, media) {
  while (state.run === id && state.evaluation === number) {
    state.media = media;
    $("#eval-status").textContent = `${describeMedium("data file", media.data)} · ${describeMedium("video", media.video)}`;
    if (media.data.state === "ready" && state.data === null) await showData(id, number);
    const video = $("#eval-video");
    if (media.video.state === "ready" && !video.getAttribute("src")) {
      video.src = mediaUrl(id, number, "video.webm");
      video.hidden = false;
      video.play().catch(() => {});
    }
    if (!pending(media.data) && !pending(media.video)) return;
    await new Promise((done) => setTimeout(done, 1000));
    try {
      media = await getJson(mediaUrl(id, number));
    } catch (e) {
      $("#eval-status").textContent = e.message;
      return;
    }
  }
}

async function showData(id, number) {
  const data = await getJson(mediaUrl(id, number, "data.json"));
  if (state.run !== id || state.evaluation !== number) return;
  state.data = data;
  $("#eval-data").hidden = false;
  $("#eval-data-file").href = mediaUrl(id, number, "data.xml");
  const select = $("#eval-series");
  select.replaceChildren();
  data.titles.forEach((t, i) => {
    const o = document.createElement("option");
    o.value = String(i);
    o.textContent = t;
    o.selected = i < 4;
    select.appendChild(o);
  });
  select.onchange = renderData;
  renderData();
}

function renderData() {
  const data = state.data;
  if (!data) return;
  const picked = [...$("#eval-series").selectedOptions].map((o) => Number(o.value));
  const colours = ["#0b61c4", "#d1242f", "#1a7f37", "#8250df", "#bf8700", "#57606a"];
  const series = [{ label: "time (s)" }];
  const values = [data.time];
  picked.forEach((i, k) => {
    series.push({ label: data.titles[i], stroke: colours[k % colours.length], width: 1.5 });
    values.push(data.values[i]);
  });
  if (state.dataPlot) state.dataPlot.destroy();
  const el = $("#eval-plot");
  state.dataPlot = new uPlot({
    width: plotWidth(el), height: 240, scales: { x: { time: false } },
    axes: axes("simulated time (s)", "value"), series,
  }, values, el);
}

async function renderCompare() {
  const box = $("#compare");
  const ids = [...state.compare];
  if (ids.length < 2) {
    box.hidden = true;
    if (state.comparePlot) { state.comparePlot.destroy(); state.comparePlot = null; }
    return;
  }
  box.hidden = false;
  const runs = await Promise.all(ids.map((id) => getJson(`api/runs/${id}`)));
  const n = Math.max(...runs.map((r) => r.evaluations.length));
  const x = Array.from({ length: n }, (_, i) => i);
  const colours = ["#0b61c4", "#d1242f", "#1a7f37", "#8250df", "#bf8700", "#57606a"];
  const series = [{ label: "evaluation" }];
  const data = [x];
  runs.forEach((r, k) => {
    series.push({ label: `run ${r.run.id} (${r.run.algorithm})`, stroke: colours[k % colours.length], width: 2 });
    const best = curveData(r.evaluations)[1];
    data.push(x.map((i) => (i < best.length ? best[i] : null)));
  });
  if (state.comparePlot) state.comparePlot.destroy();
  const el = $("#compare-plot");
  state.comparePlot = new uPlot({
    width: plotWidth(el), height: 260, scales: { x: { time: false } },
    axes: axes("evaluation", "best score"), series,
  }, data, el);
}

// A fault of the page itself shows in the status line rather than nowhere.
window.addEventListener("error", (e) => setStatus(`page error: ${e.message}`, true));
window.addEventListener("unhandledrejection", (e) => setStatus(`page error: ${e.reason}`, true));

function start() {
  for (const b of document.querySelectorAll("th button[data-sort]")) {
    b.addEventListener("click", () => {
      const key = b.dataset.sort;
      state.sort = { key, down: state.sort.key === key ? !state.sort.down : key === "score" };
      renderEvaluations();
    });
  }
  $("#filter").addEventListener("input", renderEvaluations);
  // `#run=N` opens that run (a link to it, a bookmark, the back button).
  const wanted = /^#run=(\d+)$/.exec(location.hash);
  if (wanted) state.run = Number(wanted[1]);
  if (state.run !== null) $("#run").hidden = false;
  window.addEventListener("hashchange", () => {
    const asked = /^#run=(\d+)$/.exec(location.hash);
    if (asked && Number(asked[1]) !== state.run) openRun(Number(asked[1]));
  });
  refresh();
  const events = new EventSource("api/events");
  events.addEventListener("changed", (ev) => {
    if (Number(ev.data) !== state.version) refresh();
  });
  events.addEventListener("error", () => setStatus("the dashboard is not answering; trying again", true));
}

start();
