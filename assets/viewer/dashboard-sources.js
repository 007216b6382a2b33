// The dashboard's 3D replay page: `replay?a=RUN/N[/ENGINE]&b=RUN/N[/ENGINE]` names one or
// two evaluations (N a number or "best"; ENGINE rapier or mujoco, else the run's first
// engine). Each is asked of the server (made once, then cached), followed until it is
// made, and handed to the viewer (viewer.js) as its pose stream.
"use strict";

(function () {
  const params = new URLSearchParams(location.search);
  const named = ["a", "b"].map((k) => params.get(k)).filter((v) => v);

  async function json(url, options) {
    const r = await fetch(url, Object.assign({ credentials: "same-origin" }, options || {}));
    if (!r.ok) throw new Error(`${url}: ${r.status} ${await r.text()}`);
    return r.json();
  }

  // RUN/N/ENGINE with N and ENGINE worked out.
  async function resolve(text) {
    const [run, n, engine] = text.split("/");
    if (!/^\d+$/.test(run || "")) throw new Error(`"${text}": give RUN/N[/ENGINE]`);
    let number = n;
    let kind = engine;
    if (number === "best" || !kind) {
      const data = await json(`api/runs/${run}`);
      if (!kind) kind = (data.run.engines && data.run.engines[0]) || "rapier";
      if (number === "best") {
        let best = null;
        for (const e of data.evaluations) {
          if (Number.isFinite(e.score) && (best === null || e.score > best.score)) best = e;
        }
        if (!best) throw new Error(`run ${run} has no scored evaluation`);
        number = String(best.number);
      }
    }
    if (!/^\d+$/.test(number || "")) throw new Error(`"${text}": the evaluation is a number or best`);
    return `api/runs/${run}/evaluations/${number}/replay/${encodeURIComponent(kind)}`;
  }

  function describe(state) {
    switch (state.state) {
      case "queued": return `waiting (${state.ahead} before it)`;
      case "making": return "replaying the episode…";
      default: return state.state;
    }
  }

  window.prolegReplaySources = named.map((text) => async (say) => {
    const base = await resolve(text);
    let state = await json(base, { method: "POST", headers: { "X-Proleg": "1" } });
    while (state.state !== "ready") {
      if (state.state === "failed" || state.state === "unavailable" || state.state === "absent") {
        throw new Error(`${text}: ${state.error || state.state}`);
      }
      say(`${text}: ${describe(state)}`);
      await new Promise((r) => setTimeout(r, 150));
      state = await json(base);
    }
    return json(`${base}/stream.json`);
  });
})();
