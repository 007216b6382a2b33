// proleg dashboard: the runs of a store and one run's learning curve, evaluations and best
// candidate, kept up to date by the server's event stream (no reload). Every name from the
// store goes into text nodes (textContent), never into markup.
"use strict";

const state = {
  version: 0,
  runs: [],
  run: null,          // the open run's id
  evaluations: [],    // its evaluations read so far
  sort: { key: "number", down: false },
  compare: new Set(),
  curve: null,
  comparePlot: null,
  map: null,          // the open run's MAP-Elites archive, when it keeps one
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
    cell(tr, r.finished ? "finished" : "running or stopped");
    cell(tr, String(r.evaluations), "num evaluations");
    cell(tr, fmt(r.best), "num");
    cell(tr, r.started);
    tr.addEventListener("click", () => openRun(r.id));
    tr.addEventListener("keydown", (ev) => { if (ev.key === "Enter") openRun(r.id); });
    body.appendChild(tr);
  }
}

async function openRun(id) {
  state.run = id;
  if (location.hash !== `#run=${id}`) history.replaceState(null, "", `#run=${id}`);
  state.evaluations = [];
  if (state.curve) { state.curve.destroy(); state.curve = null; }
  state.map = null;
  $("#map-box").hidden = true;
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
  $("#run-title").textContent = `Run ${r.id}: ${r.config}`;
  const summary = $("#run-summary");
  summary.textContent = `${r.algorithm}, seed ${r.seed}, ${r.fitness} over ${r.duration} s episodes; ` +
    `${state.evaluations.length} evaluations, best ${fmt(r.best)}` +
    (r.best_engines.length ? ` (${r.best_engines.map(([k, s]) => `${k} ${fmt(s)}`).join(", ")})` : "") +
    (r.rejected ? `; ${r.rejected} bodies rejected` : "") + (r.finished ? "; finished" : "");
  summary.dataset.evaluations = String(state.evaluations.length);
  $("#csv").href = `api/runs/${id}/evaluations.csv`;
  renderBest(r);
  renderCurve();
  renderEvaluations();
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
  $("#map-box").hidden = false;
  $("#map-summary").textContent = `${map.summary}; x: ${map.labels[0]}, y: ${map.labels[1]}`;
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
  canvas.onmousemove = (ev) => {
    const r = canvas.getBoundingClientRect();
    const x = Math.floor(((ev.clientX - r.left) / r.width) * nx);
    const y = ny - 1 - Math.floor(((ev.clientY - r.top) / r.height) * ny);
    const c = map.cells.find((k) => k.x === x && k.y === y);
    $("#map-hover").textContent = c
      ? `cell (${x}, ${y}): score ${fmt(c.score)}, genome ${c.genome.join(" ")}`
      : `cell (${x}, ${y}): empty`;
  };
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

function curveData(evals) {
  const x = [], every = [], best = [];
  let b = null;
  for (const e of evals) {
    x.push(e.number);
    every.push(e.score);
    if (e.score !== null && (b === null || e.score > b)) b = e.score;
    best.push(b);
  }
  return [x, best, every];
}

function plotWidth(el) {
  return Math.max(300, el.clientWidth || 800);
}

function renderCurve() {
  const el = $("#curve");
  const data = curveData(state.evaluations);
  if (!state.curve) {
    const opts = {
      title: "Learning curve",
      width: plotWidth(el), height: 280,
      scales: { x: { time: false } },
      axes: [{ label: "evaluation" }, { label: "score" }],
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
    body.appendChild(tr);
  }
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
    axes: [{ label: "evaluation" }, { label: "best score" }], series,
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
