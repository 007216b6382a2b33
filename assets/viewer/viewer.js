// proleg's 3D replay viewer: plays one or two pose streams (src/playback/stream.rs) on one
// timeline, side by side or overlaid (the second as a ghost), with orbit / zoom / pan, a
// follow camera, play / pause / scrub / speed, the ground's metre grid and the course's
// metre marks, the pads lit while pressed, and the score and a joint's angle plotted
// against the timeline. Needs the globals THREE (three.js with OrbitControls, bundled by
// scripts/dashboard-assets) and uPlot. Everything a stream names is shown as text, never
// as markup. `window.prolegReplay` answers tests (frame, time, scrub, poses).
"use strict";

(function () {
  const FORMAT = "proleg-replay 1";
  const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 5, 10];
  const COLORS = ["#0b61c4", "#d1242f"];

  // ---- decoding -----------------------------------------------------------------------

  function bytes(text) {
    const bin = atob(text);
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }
  function typed(text, Type) {
    const b = bytes(text);
    return new Type(b.buffer, 0, b.length / Type.BYTES_PER_ELEMENT);
  }

  // A stream decoded: typed arrays and counts.
  function decode(stream) {
    if (!stream || stream.format !== FORMAT) {
      throw new Error(`not a proleg replay (format ${stream && stream.format})`);
    }
    const moving = stream.scene.bodies.filter((b) => b.moves).length;
    return {
      stream,
      frames: stream.frames,
      dt: stream.frame_seconds,
      moving,
      joints: stream.scene.joints.length,
      pads: stream.scene.pads.length,
      positions: typed(stream.positions, Float32Array),
      rotations: typed(stream.rotations, Int16Array),
      angles: typed(stream.angles, Int16Array),
      contacts: typed(stream.contacts, Uint8Array),
      score: typed(stream.score, Float32Array),
      duration: Math.max(0, stream.frames - 1) * stream.frame_seconds,
    };
  }

  // ---- the scene ----------------------------------------------------------------------

  function poseOf(obj, p) {
    obj.position.set(p[0], p[1], p[2]);
    obj.quaternion.set(p[3], p[4], p[5], p[6]);
  }

  function material(color, opacity, ghost) {
    const o = ghost ? Math.min(opacity, 0.35) : opacity;
    return new THREE.MeshStandardMaterial({
      color: new THREE.Color(color[0], color[1], color[2]),
      roughness: 0.8,
      transparent: o < 0.999,
      opacity: o,
      depthWrite: o >= 0.999,
    });
  }

  function heightfield(h) {
    const steps = typed(h.heights, Uint16Array);
    const geo = new THREE.BufferGeometry();
    const pos = new Float32Array(h.nx * h.ny * 3);
    const col = new Float32Array(h.nx * h.ny * 3);
    const dx = h.nx > 1 ? (h.x[1] - h.x[0]) / (h.nx - 1) : 0;
    const dy = h.ny > 1 ? (h.y[1] - h.y[0]) / (h.ny - 1) : 0;
    let top = 0;
    for (let k = 0; k < steps.length; k++) top = Math.max(top, steps[k]);
    for (let j = 0; j < h.ny; j++) {
      for (let i = 0; i < h.nx; i++) {
        const k = j * h.nx + i;
        pos[3 * k] = h.x[0] + i * dx;
        pos[3 * k + 1] = h.y[0] + j * dy;
        pos[3 * k + 2] = h.low + h.step * steps[k];
        const t = 0.7 + 0.55 * (top > 0 ? steps[k] / top : 0);
        col[3 * k] = col[3 * k + 1] = col[3 * k + 2] = t;
      }
    }
    const index = [];
    for (let j = 0; j + 1 < h.ny; j++) {
      for (let i = 0; i + 1 < h.nx; i++) {
        const a = j * h.nx + i;
        index.push(a, a + 1, a + h.nx + 1, a, a + h.nx + 1, a + h.nx);
      }
    }
    geo.setAttribute("position", new THREE.BufferAttribute(pos, 3));
    geo.setAttribute("color", new THREE.BufferAttribute(col, 3));
    geo.setIndex(index);
    geo.computeVertexNormals();
    return geo;
  }

  function geometry(g, meshes) {
    switch (g.shape) {
      case "box": return new THREE.BoxGeometry(2 * g.half[0], 2 * g.half[1], 2 * g.half[2]);
      case "sphere": return new THREE.SphereGeometry(g.radius, 24, 16);
      case "cylinder": return new THREE.CylinderGeometry(g.radius, g.radius, g.height, 24);
      case "mesh": {
        const m = meshes[g.mesh];
        const geo = new THREE.BufferGeometry();
        geo.setAttribute("position", new THREE.BufferAttribute(typed(m.vertices, Float32Array), 3));
        geo.setIndex(new THREE.BufferAttribute(typed(m.triangles, Uint32Array), 1));
        const flat = geo.toNonIndexed();
        flat.computeVertexNormals();
        return flat;
      }
      case "heightfield": return heightfield(g);
      default: return null;
    }
  }

  // Lines every metre on a floor box's top face, in the geometry's frame.
  function floorGrid(g) {
    const [x, y, z] = g.half;
    const pts = [];
    const top = z + 0.002;
    for (let k = -Math.floor(x); k <= Math.floor(x); k++) pts.push(k, -y, top, k, y, top);
    for (let k = -Math.floor(y); k <= Math.floor(y); k++) pts.push(-x, k, top, x, k, top);
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.Float32BufferAttribute(pts, 3));
    return new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color: 0x0d1f0d, transparent: true, opacity: 0.45 }));
  }

  function label(text, size) {
    const c = document.createElement("canvas");
    c.width = 128; c.height = 64;
    const ctx = c.getContext("2d");
    ctx.fillStyle = "rgba(255, 255, 255, 0.85)";
    ctx.beginPath();
    ctx.roundRect(8, 10, 112, 44, 10);
    ctx.fill();
    ctx.font = "bold 32px system-ui, sans-serif";
    ctx.fillStyle = "#1b1f23";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    ctx.fillText(text, 64, 33);
    const map = new THREE.CanvasTexture(c);
    map.colorSpace = "srgb";
    const s = new THREE.Sprite(new THREE.SpriteMaterial({ map, depthTest: false }));
    s.scale.set(size, size / 2, 1);
    return s;
  }

  // One replay's objects: a group per body (moving ones posed every frame), pads.
  function buildReplay(r, ghost) {
    const root = new THREE.Group();
    const s = r.stream.scene;
    const bodies = [];
    const moving = [];
    for (const b of s.bodies) {
      if (ghost && !b.moves) { bodies.push(null); continue; }
      const group = new THREE.Group();
      poseOf(group, b.pose);
      for (const g of b.geoms) {
        const geo = geometry(g, s.meshes);
        if (!geo) continue;
        const mat = material(g.color, g.opacity, ghost);
        if (g.shape === "heightfield") mat.vertexColors = true;
        const mesh = new THREE.Mesh(geo, mat);
        poseOf(mesh, g.pose);
        if (g.shape === "mesh") mesh.scale.setScalar(g.scale);
        if (g.shape === "heightfield") mesh.scale.setScalar(g.scale);
        if (g.grid) mesh.add(floorGrid(g));
        group.add(mesh);
      }
      root.add(group);
      bodies.push(group);
      if (b.moves) moving.push(group);
    }
    const pressed = new THREE.MeshStandardMaterial({ color: 0xff1a0d, emissive: 0xff1a00, emissiveIntensity: 0.8 });
    const released = new THREE.MeshStandardMaterial({ color: 0x731a1a });
    const pads = s.pads.map((p) => {
      const m = new THREE.Mesh(
        new THREE.BoxGeometry(2 * p.half[0] + 0.001, 2 * p.half[1] + 0.001, 2 * p.half[2] + 0.001),
        released,
      );
      poseOf(m, p.pose);
      if (bodies[p.body]) bodies[p.body].add(m);
      return m;
    });
    return { root, moving, pads, pressed, released };
  }

  // Metre marks from the robot's start along the way it went (its start-to-end
  // direction; +x when it hardly moved), half a metre to its right, as far as it went
  // and two metres more.
  function metreMarks(r) {
    const g = new THREE.Group();
    const a = centre(r, 0);
    const b = centre(r, r.duration);
    const way = new THREE.Vector3(b.x - a.x, b.y - a.y, 0);
    const far = way.length();
    if (far < 0.5) way.set(1, 0, 0); else way.normalize();
    const right = new THREE.Vector3(way.y, -way.x, 0);
    const marks = Math.min(400, Math.ceil(far) + 2);
    const tick = [];
    for (let m = 0; m <= marks; m++) {
      const at = a.clone().addScaledVector(way, m).addScaledVector(right, 0.5);
      const s = label(`${m} m`, 0.3);
      s.position.set(at.x, at.y, a.z + 0.08);
      g.add(s);
      tick.push(at.x - 0.15 * right.x, at.y - 0.15 * right.y, a.z, at.x + 0.15 * right.x, at.y + 0.15 * right.y, a.z);
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.Float32BufferAttribute(tick, 3));
    g.add(new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color: 0x1b1f23 })));
    return g;
  }

  // ---- posing at a time ---------------------------------------------------------------

  const qa = new THREE.Quaternion();
  const qb = new THREE.Quaternion();

  // Frame index and blend at time t (s) of replay r.
  function at(r, t) {
    if (r.frames <= 1 || r.dt <= 0) return [0, 0];
    const f = Math.min(Math.max(t / r.dt, 0), r.frames - 1);
    const i = Math.min(Math.floor(f), r.frames - 2);
    return [i, f - i];
  }

  function pose(r, view, t) {
    const [i, u] = at(r, t);
    const j = Math.min(i + 1, r.frames - 1);
    for (let b = 0; b < view.moving.length; b++) {
      const ka = i * r.moving + b;
      const kb = j * r.moving + b;
      const obj = view.moving[b];
      obj.position.set(
        r.positions[3 * ka] + u * (r.positions[3 * kb] - r.positions[3 * ka]),
        r.positions[3 * ka + 1] + u * (r.positions[3 * kb + 1] - r.positions[3 * ka + 1]),
        r.positions[3 * ka + 2] + u * (r.positions[3 * kb + 2] - r.positions[3 * ka + 2]),
      );
      qa.set(r.rotations[4 * ka], r.rotations[4 * ka + 1], r.rotations[4 * ka + 2], r.rotations[4 * ka + 3]).normalize();
      qb.set(r.rotations[4 * kb], r.rotations[4 * kb + 1], r.rotations[4 * kb + 2], r.rotations[4 * kb + 3]).normalize();
      obj.quaternion.slerpQuaternions(qa, qb, u);
    }
    const near = nearest(r, t);
    for (let p = 0; p < view.pads.length; p++) {
      view.pads[p].material = r.contacts[near * r.pads + p] ? view.pressed : view.released;
    }
  }

  // The frame nearest time t.
  function nearest(r, t) {
    const [i, u] = at(r, t);
    return Math.min(u >= 0.5 ? i + 1 : i, Math.max(0, r.frames - 1));
  }

  // Where the robot is (mean of its links' positions) at time t.
  function centre(r, t) {
    const [i] = at(r, t);
    const c = new THREE.Vector3();
    const links = r.stream.scene.bodies.filter((b) => b.moves);
    let n = 0;
    links.forEach((b, k) => {
      if (b.link === null) return;
      const q = 3 * (i * r.moving + k);
      c.x += r.positions[q]; c.y += r.positions[q + 1]; c.z += r.positions[q + 2];
      n++;
    });
    return n ? c.multiplyScalar(1 / n) : c;
  }

  // ---- a view: renderer, camera, controls ---------------------------------------------

  function makeView(container) {
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    container.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xdfe8ef);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667766, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(3, -2, 6);
    scene.add(sun);
    const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 2000);
    camera.up.set(0, 0, 1);
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.enableDamping = false;
    return { container, renderer, scene, camera, controls };
  }

  function resize(view) {
    const w = Math.max(1, view.container.clientWidth);
    const h = Math.max(1, view.container.clientHeight);
    view.renderer.setSize(w, h, false);
    view.camera.aspect = w / h;
    view.camera.updateProjectionMatrix();
  }

  // ---- the player ---------------------------------------------------------------------

  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function fmt(x, d) {
    return Number.isFinite(x) ? x.toFixed(d) : "–";
  }

  // Starts the viewer in `root` on the decoded streams `streams` (one or two).
  function start(root, streams) {
    const replays = streams.map(decode);
    const duration = Math.max(...replays.map((r) => r.duration));
    const state = { t: 0, playing: true, speed: 1, follow: true, overlay: false, last: null, frames: 0, joint: 0 };

    root.replaceChildren();
    const title = el("div", { class: "replay-title" });
    replays.forEach((r, k) => {
      const line = el("div", { class: "replay-label" });
      line.append(el("span", { class: "swatch", style: `background:${COLORS[k]}` }));
      line.append(el("span", { class: "label" }, r.stream.label));
      const engine = el("span", { class: "muted", title: r.stream.engine }, ` · ${r.stream.engine.split(":")[0]} · ${fmt(r.duration, 1)} s, ${r.stream.end}`);
      line.append(engine);
      title.append(line);
    });
    const views = el("div", { class: "replay-views" });
    const bar = el("div", { class: "replay-bar" });
    const play = el("button", { type: "button", id: "replay-play", "aria-label": "play or pause" }, "pause");
    const scrub = el("input", { type: "range", id: "replay-scrub", min: "0", max: String(duration), step: String(Math.min(...replays.map((r) => r.dt)) || 0.01), value: "0", "aria-label": "time" });
    const clock = el("span", { id: "replay-time", class: "muted" });
    const speed = el("select", { id: "replay-speed", "aria-label": "speed" });
    for (const s of SPEEDS) {
      const o = el("option", { value: String(s) }, `${s}x`);
      if (s === 1) o.selected = true;
      speed.append(o);
    }
    const follow = el("label", {}, "");
    const followBox = el("input", { type: "checkbox", id: "replay-follow" });
    followBox.checked = true;
    follow.append(followBox, document.createTextNode(" follow"));
    bar.append(play, scrub, clock, speed, follow);
    let overlayBox = null;
    if (replays.length > 1) {
      const l = el("label", {}, "");
      overlayBox = el("input", { type: "checkbox", id: "replay-overlay" });
      l.append(overlayBox, document.createTextNode(" overlay (second as a ghost)"));
      bar.append(l);
    }
    const plots = el("div", { class: "replay-plots" });
    const jointPick = el("select", { id: "replay-joint", "aria-label": "joint plotted" });
    replays[0].stream.scene.joints.forEach((name, k) => jointPick.append(el("option", { value: String(k) }, name)));
    root.append(title, views, bar, plots);

    // Views: one per replay side by side, or one with both (the second a ghost).
    let active = [];
    function layout() {
      for (const v of active) { v.controls.dispose(); v.renderer.dispose(); }
      views.replaceChildren();
      active = [];
      const groups = state.overlay || replays.length === 1 ? [replays.map((r, k) => [r, k])] : replays.map((r, k) => [[r, k]]);
      for (const members of groups) {
        const box = el("div", { class: "replay-view" });
        views.append(box);
        const v = makeView(box);
        v.members = members.map(([r, k]) => {
          const built = buildReplay(r, k > 0 && members.length > 1);
          v.scene.add(built.root);
          return { r, k, built };
        });
        const first = v.members[0];
        const c0 = centre(first.r, 0);
        v.scene.add(metreMarks(first.r));
        v.camera.position.set(c0.x - 0.5, c0.y - 0.8, c0.z + 0.55);
        v.controls.target.copy(c0);
        v.controls.update();
        v.followed = c0.clone();
        resize(v);
        active.push(v);
      }
      views.dataset.views = String(active.length);
    }

    function show() {
      for (const v of active) {
        for (const m of v.members) pose(m.r, m.built, state.t);
        if (state.follow) {
          const c = centre(v.members[0].r, state.t);
          const d = c.clone().sub(v.followed);
          v.camera.position.add(d);
          v.controls.target.add(d);
          v.followed.copy(c);
          v.controls.update();
        }
        v.renderer.render(v.scene, v.camera);
      }
      scrub.value = String(state.t);
      clock.textContent = `${fmt(state.t, 2)} / ${fmt(duration, 2)} s · ` +
        replays.map((r, k) => `${replays.length > 1 ? `#${k + 1} ` : ""}${r.stream.score_name} ${fmt(r.score[nearest(r, state.t)], 3)}`).join(" · ");
      for (const p of charts) p.cursor(state.t);
      state.frames++;
    }

    // Plots: the score, and the chosen joint's angle, of every replay over time.
    const charts = [];
    function chart(titleText, series, unit) {
      const box = el("div", { class: "replay-plot" });
      box.append(el("div", { class: "muted" }, titleText));
      plots.append(box);
      if (typeof uPlot === "undefined") return;
      const r0 = replays[0];
      const xs = Array.from({ length: r0.frames }, (_, i) => i * r0.dt);
      const data = [xs, ...series.map((f) => xs.map((_, i) => f(i)))];
      const u = new uPlot({
        width: Math.max(280, Math.floor(plots.clientWidth / 2) - 40), height: 170,
        series: [{ label: "s" }, ...series.map((_, k) => ({ label: replays[k] ? `#${k + 1}` : "", stroke: COLORS[k], width: 1.5 }))],
        scales: { x: { time: false } },
        axes: [{ label: "simulated time (s)" }, { label: unit, size: 50 }],
        cursor: { show: false }, legend: { show: false },
      }, data, box);
      const line = el("div", { class: "replay-cursor" });
      u.over.append(line);
      charts.push({
        u,
        cursor(t) { line.style.left = `${u.valToPos(t, "x")}px`; },
        set(newSeries) { u.setData([xs, ...newSeries.map((f) => xs.map((_, i) => f(i)))]); },
      });
    }
    const sample = (r, arr, per, k, scale) => (i) => {
      const f = Math.min(Math.round((i * replays[0].dt) / r.dt), r.frames - 1);
      return arr[f * per + k] * scale;
    };
    chart("score over time", replays.map((r) => sample(r, r.score, 1, 0, 1)), "score");
    const angleSeries = () => replays.map((r) => sample(r, r.angles, r.joints, Math.min(state.joint, r.joints - 1), 0.01));
    if (replays[0].joints > 0) {
      chart("joint angle (°)", angleSeries(), "°");
      plots.lastChild.prepend(jointPick);
      jointPick.addEventListener("change", () => {
        state.joint = Number(jointPick.value);
        charts[1].set(angleSeries());
      });
    }

    layout();
    window.addEventListener("resize", () => { for (const v of active) resize(v); show(); });
    play.addEventListener("click", () => {
      state.playing = !state.playing;
      if (state.playing && state.t >= duration) state.t = 0;
      play.textContent = state.playing ? "pause" : "play";
      state.last = null;
    });
    scrub.addEventListener("input", () => { state.t = Number(scrub.value); show(); });
    speed.addEventListener("change", () => { state.speed = Number(speed.value); });
    followBox.addEventListener("change", () => { state.follow = followBox.checked; });
    if (overlayBox) overlayBox.addEventListener("change", () => { state.overlay = overlayBox.checked; layout(); show(); });

    function tick(now) {
      if (state.playing) {
        if (state.last !== null) state.t = Math.min(duration, state.t + ((now - state.last) / 1000) * state.speed);
        state.last = now;
        if (state.t >= duration) { state.playing = false; play.textContent = "play"; state.last = null; }
      }
      show();
      requestAnimationFrame(tick);
    }
    requestAnimationFrame(tick);

    // What tests read and drive.
    window.prolegReplay = {
      ready: true,
      duration,
      views: () => active.length,
      replays: replays.length,
      time: () => state.t,
      framesDrawn: () => state.frames,
      pause() { state.playing = false; play.textContent = "play"; state.last = null; },
      play() { state.playing = true; play.textContent = "pause"; },
      seek(t) { state.t = Math.min(Math.max(0, t), duration); show(); },
      setSpeed(s) { state.speed = s; },
      setOverlay(on) { state.overlay = on; layout(); show(); },
      setFollow(on) { state.follow = on; followBox.checked = on; },
      // World position and rotation (x, y, z, w) of moving body `b` of replay `k` as drawn.
      pose(k, b) {
        for (const v of active) {
          for (const m of v.members) {
            if (m.k !== k) continue;
            const o = m.built.moving[b];
            if (!o) return null;
            return { position: o.position.toArray(), quaternion: o.quaternion.toArray() };
          }
        }
        return null;
      },
      // Hides or shows every moving body (the empty scene, for pixel comparisons).
      showBodies(on) {
        for (const v of active) for (const m of v.members) for (const o of m.built.moving) o.visible = on;
        show();
      },
      frameSeconds: (k) => replays[k].dt,
    };
  }

  // Starts from streams already in the page (a file) or fetched (the dashboard).
  async function boot(root) {
    const say = (text) => { root.replaceChildren(el("p", { class: "replay-status", role: "status" }, text)); };
    try {
      const inline = document.getElementById("replay-streams");
      let streams;
      if (inline) {
        streams = JSON.parse(inline.textContent);
      } else {
        const urls = (window.prolegReplaySources || []);
        streams = [];
        for (const source of urls) streams.push(await source(say));
      }
      if (!streams.length) { say("nothing to replay"); return; }
      start(root, streams);
    } catch (e) {
      window.prolegReplay = { ready: false, error: String(e && e.message || e) };
      say(`the replay cannot be shown: ${e && e.message || e}`);
    }
  }

  window.ProlegViewer = { start, boot, decode };
  document.addEventListener("DOMContentLoaded", () => {
    const root = document.getElementById("replay");
    if (root) boot(root);
  });
})();
