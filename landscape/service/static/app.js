// The page of `landscape serve`: every number comes from the service's /api (the library computes it); this
// script only asks and draws. A token given as #token=T in the address is kept for this tab and sent as
// "Authorization: Bearer T"; links opened in a new tab (a sweep's report) cannot send that header, so the page
// asks the service for a link cookie (POST /api/link-access: HttpOnly, for report pages only, one hour) and renews
// it while it is open.
"use strict";

const $ = (id) => document.getElementById(id);
const state = { robot: "builtin", model: "", sets: {}, seq: 0, shown: 0, robotShown: 0, timer: null, info: null };
const LINK_RENEW_MS = 10 * 60 * 1000;  // the link cookie lasts an hour

(function keepToken() {
  const m = /token=([^&]+)/.exec(location.hash);
  if (m) {
    sessionStorage.setItem("landscape-token", decodeURIComponent(m[1]));
    history.replaceState(null, "", location.pathname + location.search);
  }
})();

async function api(path, opts = {}) {
  const headers = Object.assign({}, opts.headers || {});
  const token = sessionStorage.getItem("landscape-token");
  if (token) headers["Authorization"] = "Bearer " + token;
  const resp = await fetch(path, Object.assign({}, opts, { headers }));
  const text = await resp.text();
  let body = null;
  try { body = text ? JSON.parse(text) : null; } catch (e) { body = text; }
  if (!resp.ok) {
    const detail = body && body.detail ? body.detail : resp.status + " " + resp.statusText;
    const err = new Error(detail);
    err.status = resp.status;
    throw err;
  }
  return { status: resp.status, body };
}

function say(text, isError = false) {
  const s = $("status");
  s.textContent = text;
  s.className = isError ? "error" : "";
}

const fmt = (x, digits = 3) => (x === null || x === undefined ? "none" : Number(x).toFixed(digits));
// The digits of `landscape compute`'s table: energies (mJ) and CoM heights (mm) 3, angles (degrees) 2.
const DEG_DIGITS = 2;

async function renewLinkAccess() {
  if (!sessionStorage.getItem("landscape-token")) return;
  try { await api("/api/link-access", { method: "POST" }); } catch (err) { say(err.message, true); }
}

// ------------------------------------------------------------------------------------------------ robots
async function loadRobots(select) {
  const { body } = await api("/api/robots");
  const sel = $("robot");
  sel.innerHTML = "";
  for (const r of body) {
    const o = document.createElement("option");
    o.value = r.id;
    o.textContent = r.id === "builtin" ? `built-in (${r.description_hash})` : `${r.name} (${r.id})`;
    sel.appendChild(o);
  }
  sel.value = select || state.robot;
  await chooseRobot(sel.value);
}

async function chooseRobot(id) {
  const { body } = await api("/api/robots/" + encodeURIComponent(id));
  state.robot = id;
  state.info = body;
  $("robot-info").textContent = `${body.name}: ${fmt(body.mass_kg * 1e3, 1)} g` +
    (body.mass_default ? " (default mass: give the mass when uploading)" : "") + `, ${body.vertices} vertices` +
    (body.has_joints ? "" : " (rigid: the sliders do nothing)") +
    ((body.warnings || []).length ? "; warning: " + body.warnings.join("; ") : "");
  applyLimits();
  requestLandscape(0);
}

function applyLimits() {
  // the joints' limits, and for a measured model set the wing commands it measured
  const body = state.info, set = state.sets[state.model];
  if (!body) return;
  for (const [key, el] of [["theta_w", $("theta-w")], ["theta_l", $("theta-l")]]) {
    const lim = body.theta_limits_deg && body.theta_limits_deg[key];
    el.disabled = !body.has_joints;
    if (lim) {
      let lo = lim[0] === null ? -180 : Math.max(lim[0], -180), hi = lim[1] === null ? 180 : Math.min(lim[1], 180);
      const cmds = key === "theta_w" && set ? set.wing_command_deg : null;
      if (cmds) { lo = Math.max(lo, cmds[0]); hi = Math.min(hi, cmds[cmds.length - 1]); }
      el.min = Math.ceil(lo);
      el.max = Math.floor(hi);
      el.value = Math.min(Math.max(Number(el.value), Number(el.min)), Number(el.max));
    }
  }
}

// ------------------------------------------------------------------------------------------------ model sets
async function loadModelSets() {
  const { body } = await api("/api/model-sets");
  const sel = $("model");
  for (const m of body) {
    state.sets[m.name] = m;
    const o = document.createElement("option");
    o.value = m.name;
    o.textContent = m.label;
    o.title = m.description;
    sel.appendChild(o);
  }
  showModelSet();
}

// "name vN (hash)" of a set a result names; "none" without one
function setLabel(name, hash) {
  if (!name) return "none";
  const m = state.sets[name];
  return m ? `${m.name} v${m.version} (${hash || m.model_set_hash})` : `${name}${hash ? " (" + hash + ")" : ""}`;
}

function showModelSet() {
  const m = state.sets[state.model];
  $("model-info").textContent = !m ? "every wing joint at θw, the robot's own CoM" :
    (m.poses_wings ? `each wing joint at its measured plateau (θw ${m.wing_command_deg[0]}–` +
      `${m.wing_command_deg[m.wing_command_deg.length - 1]}°)` : "every wing joint at θw") +
    (m.moves_com ? `, CoM moved ${fmt(m.com_offset_y_mm, 1)} mm along y` : "") + `: ${m.description}`;
  $("sweep-model").textContent = setLabel(state.model || "paper");
}

$("model").addEventListener("change", (e) => {
  state.model = e.target.value;
  showModelSet();
  applyLimits();
  requestLandscape(0);
});

$("robot").addEventListener("change", (e) => chooseRobot(e.target.value).catch((err) => say(err.message, true)));

$("upload-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  const f = $("upload-file").files[0];
  if (!f) { say("choose a file to upload first", true); return; }
  const data = new FormData(e.target);
  if (!data.get("com")) data.delete("com");
  if (!data.get("mass")) data.delete("mass");  // the service's default, said as a default
  say("uploading " + f.name + " ...");
  try {
    const { status, body } = await api("/api/robots", { method: "POST", body: data });
    const warned = (body.warnings || []).length ? "; warning: " + body.warnings.join("; ") : "";
    say((status === 201 ? "stored " : "already stored: ") + body.name + " (" + body.id + ")" + warned, !!warned);
    await loadRobots(body.id);
  } catch (err) { say(err.message, true); }
});

// ------------------------------------------------------------------------------------------------ landscape
function query() {
  const p = new URLSearchParams({
    robot: state.robot, theta_w: $("theta-w").value, theta_l: $("theta-l").value,
    method: $("method").value, step: $("step").value, grid: "1",
  });
  if (state.model) p.set("model", state.model);
  return p.toString();
}

function requestLandscape(delayMs = 60) {
  $("theta-w-value").textContent = $("theta-w").value;
  $("theta-l-value").textContent = $("theta-l").value;
  clearTimeout(state.timer);
  state.timer = setTimeout(fetchLandscape, delayMs);
}

async function fetchLandscape() {
  const seq = ++state.seq;
  say("computing ...");
  try {
    const { body } = await api("/api/landscape?" + query());
    if (seq < state.shown) return;  // an older answer arriving late
    state.shown = seq;
    showNumbers(body);
    draw(body);
    drawRobots(body, seq);
    say(`theta_w ${fmt(body.theta_w_deg, 0)}°, theta_l ${fmt(body.theta_l_deg, 0)}°: ` +
        `righting barrier ${fmt(body.barrier.righting_j === null ? null : body.barrier.righting_j * 1e3)} mJ` +
        (body.model_set ? ` (model set ${body.model_set})` : ""));
  } catch (err) {
    if (seq >= state.shown) say(err.message, true);
  }
}

function showNumbers(s) {
  const mg = s.mass_kg * s.grid.g_m_s2;
  const joints = s.wing_joints_deg ? "; wing joints " +
    Object.entries(s.wing_joints_deg).map(([k, v]) => `${k} ${fmt(v, 1)}°`).join(", ") : "";
  $("landscape-model").textContent = "model set: " + setLabel(s.model_set) + joints;
  $("minimum-mj").textContent = fmt(s.minimum.energy_j * 1e3);
  $("minimum-mm").textContent = fmt(s.minimum.height_m * 1e3);
  $("minimum-deg").textContent = `(${fmt(s.minimum.pitch_deg, DEG_DIGITS)}, ${fmt(s.minimum.roll_deg, DEG_DIGITS)})`;
  for (const k of ["righting", "pitch_wise", "roll_wise", "escape"]) {
    const x = s.paths[k];
    $(k + "-mj").textContent = x ? fmt(x.barrier_j * 1e3) : "none";
    $(k + "-mm").textContent = x ? fmt(x.barrier_j / mg * 1e3) : "none";
    $(k + "-deg").textContent = x ?
      `(${fmt(x.saddle_pitch_deg, DEG_DIGITS)}, ${fmt(x.saddle_roll_deg, DEG_DIGITS)}) ${x.direction}` : "";
  }
}

function energyAt(g, pitch, roll) {
  const step = g.pitch_deg[1] - g.pitch_deg[0];
  const wrap = (a) => ((((a + 180) % 360) + 360) % 360) - 180;
  const i = Math.round((wrap(pitch) + 180) / step), j = Math.round((wrap(roll) + 180) / step);
  return g.energy_mj[Math.min(i, g.pitch_deg.length - 1)][Math.min(j, g.roll_deg.length - 1)];
}

const hasWebGL = (() => {
  try { const c = document.createElement("canvas"); return !!(c.getContext("webgl") || c.getContext("experimental-webgl")); }
  catch (e) { return false; }
})();

// The plots' titles are the HTML captions above them; the top margin keeps plotly's mode bar clear of the plot.
const MODEBAR_PX = 36;

// A pitch-roll map has pitch on x and roll on y, as every figure of the project (landscape render's contour.png,
// the report's maps, the gallery). The grid's energy_mj[i][j] is at pitch i, roll j: plotly's z wants rows = y.
const MAP_AXES = { xaxis: { title: { text: "pitch (°)" } }, yaxis: { title: { text: "roll (°)" } } };
const transpose = (m) => m[0].map((_, j) => m.map((row) => row[j]));

function draw(s) {
  const g = s.grid;
  const minE = s.minimum.energy_j * 1e3;
  const r = s.paths.righting;
  const path = r ? r.path_deg : [];
  const saddleE = r ? minE + r.barrier_j * 1e3 : null;
  const marks = {
    min: { x: [s.minimum.pitch_deg], y: [s.minimum.roll_deg], name: "start minimum" },
    saddle: r ? { x: [r.saddle_pitch_deg], y: [r.saddle_roll_deg], name: "saddle" } : null,
    path: { x: path.map((p) => p[0]), y: path.map((p) => p[1]), name: "righting path" },
  };
  const zRollRows = transpose(g.energy_mj);
  const contour = [
    { type: "contour", x: g.pitch_deg, y: g.roll_deg, z: zRollRows, colorscale: "Viridis", ncontours: 30,
      colorbar: { title: { text: "mJ", side: "right" } } },
    Object.assign({ type: "scatter", mode: "lines", line: { color: "white", width: 2 } }, marks.path),
    Object.assign({ type: "scatter", mode: "markers", marker: { color: "cyan", size: 10, symbol: "circle" } }, marks.min),
  ];
  if (marks.saddle) {
    contour.push(Object.assign({ type: "scatter", mode: "markers", marker: { color: "red", size: 11, symbol: "x" } },
      marks.saddle));
  }
  Plotly.react("contour", contour, Object.assign({ margin: { t: MODEBAR_PX }, showlegend: false,
    uirevision: "keep" }, MAP_AXES), { responsive: true });
  if (!hasWebGL) {
    $("surface").textContent = "The 3-D surface needs WebGL, which this browser does not offer; the contour map shows the same landscape.";
    return;
  }
  const surface = [
    { type: "surface", x: g.pitch_deg, y: g.roll_deg, z: zRollRows, colorscale: "Viridis", showscale: false,
      opacity: 0.95 },
    Object.assign({ type: "scatter3d", mode: "lines", line: { color: "white", width: 6 },
      z: path.map((p) => energyAt(g, p[0], p[1])) }, marks.path),
    Object.assign({ type: "scatter3d", mode: "markers", marker: { color: "cyan", size: 5 }, z: [minE] }, marks.min),
  ];
  if (marks.saddle) {
    surface.push(Object.assign({ type: "scatter3d", mode: "markers", marker: { color: "red", size: 5 },
      z: [saddleE] }, marks.saddle));
  }
  Plotly.react("surface", surface, { margin: { t: MODEBAR_PX, l: 0, r: 0, b: 0 }, showlegend: false,
    uirevision: "keep", scene: Object.assign({ zaxis: { title: { text: "mJ" } } }, MAP_AXES) },
    { responsive: true });
}

// ------------------------------------------------------------------------------------------------ robot view
const wrapDeg = (a) => ((((a + 180) % 360) + 360) % 360) - 180;

async function fetchPose(s, pitch, roll) {
  const p = new URLSearchParams({ robot: state.robot, theta_w: s.theta_w_deg ?? 0, theta_l: s.theta_l_deg ?? 0,
    pitch: wrapDeg(pitch), roll: wrapDeg(roll) });
  if (s.model_set) p.set("model", s.model_set);  // the robot as the landscape's set models it
  return (await api("/api/robot-pose?" + p.toString())).body;
}

function robotTraces(pose) {
  const x = [], y = [], z = [], i = [], j = [], k = [];
  for (const part of pose.parts) {
    const base = x.length;
    for (const v of part.vertices_m) { x.push(v[0] * 1e3); y.push(v[1] * 1e3); z.push(v[2] * 1e3); }
    for (const f of part.faces) { i.push(base + f[0]); j.push(base + f[1]); k.push(base + f[2]); }
  }
  const c = pose.com_m.map((q) => q * 1e3);
  return [
    { type: "mesh3d", name: "robot", x, y, z, i, j, k, color: "#8094b0", opacity: 0.8, flatshading: true, hoverinfo: "skip",
      lighting: { ambient: 0.55, diffuse: 0.8, specular: 0.1 } },
    { type: "scatter3d", mode: "markers", name: "CoM", x: [c[0]], y: [c[1]], z: [c[2]],
      marker: { color: "red", size: 5 }, hovertemplate: "CoM %{z:.1f} mm above the ground<extra></extra>" },
    { type: "scatter3d", mode: "lines", name: "CoM height", x: [c[0], c[0]], y: [c[1], c[1]], z: [0, c[2]],
      line: { color: "red", width: 3, dash: "dash" }, hoverinfo: "skip" },
  ];
}

function groundTrace(box) {
  const [x0, x1] = box.x, [y0, y1] = box.y;
  return { type: "mesh3d", name: "ground", x: [x0, x1, x1, x0], y: [y0, y0, y1, y1], z: [0, 0, 0, 0],
    i: [0, 0], j: [1, 2], k: [2, 3], color: "#c9b98f", opacity: 0.55, hoverinfo: "skip" };
}

function boxOf(poses) {
  // one box for both views, so the two robots are drawn at the same scale
  let lo = [Infinity, Infinity, 0], hi = [-Infinity, -Infinity, -Infinity];
  for (const pose of poses) {
    for (const part of pose.parts) {
      for (const v of part.vertices_m) {
        for (let a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], v[a] * 1e3); hi[a] = Math.max(hi[a], v[a] * 1e3); }
      }
    }
  }
  const pad = 0.15 * Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3);
  return { x: [lo[0] - pad, hi[0] + pad], y: [lo[1] - pad, hi[1] + pad], z: [0, hi[2] + pad] };
}

function robotLayout(box) {
  const ex = box.x[1] - box.x[0], ey = box.y[1] - box.y[0], ez = box.z[1] - box.z[0];
  const m = Math.max(ex, ey, ez);
  return { margin: { t: MODEBAR_PX, l: 0, r: 0, b: 0 }, showlegend: false, uirevision: "keep",
    scene: { aspectmode: "manual", aspectratio: { x: ex / m, y: ey / m, z: ez / m },
      xaxis: { title: { text: "x (mm)" }, range: box.x }, yaxis: { title: { text: "y (mm)" }, range: box.y },
      zaxis: { title: { text: "z (mm)" }, range: box.z },
      camera: { eye: { x: 1.2, y: -1.2, z: 0.7 } } } };
}

async function drawRobots(s, seq) {
  const r = s.paths.righting;
  try {
    const [start, saddle] = await Promise.all([
      fetchPose(s, s.minimum.pitch_deg, s.minimum.roll_deg),
      r ? fetchPose(s, r.saddle_pitch_deg, r.saddle_roll_deg) : Promise.resolve(null),
    ]);
    if (seq < state.robotShown || seq < state.shown) return;  // a newer pose is drawn or on its way
    state.robotShown = seq;
    $("robot-model").textContent = "(model set: " + setLabel(start.model_set, start.model_set_hash) + ")";
    // the heights and the lift of the table (the landscape's, to the digit), which the drawn robots show
    const h0 = s.minimum.height_m * 1e3, lift = r ? r.barrier_j / (s.mass_kg * s.grid.g_m_s2) * 1e3 : null;
    $("robot-start-caption").textContent = `at the start minimum (pitch ${fmt(start.pitch_deg, DEG_DIGITS)}°, roll ` +
      `${fmt(start.roll_deg, DEG_DIGITS)}°): CoM ${fmt(h0)} mm above the ground`;
    $("robot-saddle-caption").textContent = saddle
      ? `at the righting saddle (pitch ${fmt(saddle.pitch_deg, DEG_DIGITS)}°, roll ${fmt(saddle.roll_deg, DEG_DIGITS)}°): ` +
        `CoM ${fmt(h0 + lift)} mm, lifted ${fmt(lift)} mm`
      : "no righting saddle at this pose";
    if (!hasWebGL) {
      for (const id of ["robot-start", "robot-saddle"]) {
        $(id).textContent = "The robot view needs WebGL, which this browser does not offer.";
      }
      return;
    }
    const box = boxOf(saddle ? [start, saddle] : [start]);
    Plotly.react("robot-start", [groundTrace(box), ...robotTraces(start)], robotLayout(box), { responsive: true });
    if (saddle) {
      Plotly.react("robot-saddle", [groundTrace(box), ...robotTraces(saddle)], robotLayout(box), { responsive: true });
    } else {
      Plotly.purge("robot-saddle");
    }
  } catch (err) {
    if (seq >= state.shown) say(err.message, true);
  }
}

for (const id of ["theta-w", "theta-l"]) $(id).addEventListener("input", () => requestLandscape());
for (const id of ["method", "step"]) $(id).addEventListener("change", () => requestLandscape(0));

// ------------------------------------------------------------------------------------------------ barrier map
// The barrier map has θl on x and θw on y, as `landscape barrier-map`'s barrier_map.png and the report's maps.
function drawMap(rows) {
  const ws = [...new Set(rows.map((r) => r.theta_w_deg))], ls = [...new Set(rows.map((r) => r.theta_l_deg))];
  const z = ws.map((w) => ls.map((l) => {
    const r = rows.find((q) => q.theta_w_deg === w && q.theta_l_deg === l);
    return r && r.righting_j !== null ? r.righting_j * 1e3 : null;
  }));
  Plotly.react("map", [{ type: "heatmap", x: ls, y: ws, z, colorscale: "Viridis",
    colorbar: { title: { text: "mJ", side: "right" } } }],
    { margin: { t: MODEBAR_PX },
      xaxis: { title: { text: "leg angle θl (°)" } }, yaxis: { title: { text: "wing angle θw (°)" } } },
    { responsive: true });
}

$("map-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  const f = new FormData(e.target);
  const p = new URLSearchParams({ robot: state.robot, theta_w: f.get("theta_w"), theta_l: f.get("theta_l"),
    method: $("method").value, step: $("step").value });
  const model = state.model;
  if (model) p.set("model", model);
  $("map-status").textContent = "computing ...";
  $("map-status").className = "";
  try {
    let { status, body } = await api("/api/barrier-map?" + p.toString());
    while (status === 202 || (body && body.status && body.status !== "done")) {
      const job = body.job || body;
      if (job.status === "failed" || job.status === "cancelled") throw new Error("barrier map " + job.status + ": " + (job.error || ""));
      $("map-status").textContent = `${job.done}/${job.total} poses` + (job.eta_s ? `, ETA ${job.eta_s.toFixed(0)} s` : "");
      await new Promise((res) => setTimeout(res, 1000));
      ({ status, body } = await api("/api/barrier-map/jobs/" + job.id));
    }
    const rows = Array.isArray(body) ? body : body.rows;
    // a job names its set; rows answered at once are those of the set asked for
    $("map-status").textContent = `${rows.length} poses, model set ` + setLabel(Array.isArray(body) ? model : body.model_set);
    drawMap(rows);
  } catch (err) { $("map-status").textContent = err.message; $("map-status").className = "error"; }
});

// ------------------------------------------------------------------------------------------------ sweeps
$("sweep-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  const f = new FormData(e.target);
  const req = { theta_w: f.get("theta_w"), theta_l: f.get("theta_l"), cv: f.get("cv"),
    trials: parseInt(f.get("trials"), 10), duration: parseFloat(f.get("duration")), robot: state.robot,
    engine: f.get("engine") };
  if (f.get("dt")) req.dt = parseFloat(f.get("dt"));
  if (state.model) req.model = state.model;  // none: the sweep's default set, paper
  try {
    const { body } = await api("/api/sweeps", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify(req) });
    say("sweep " + body.id + " queued: " + body.total + " trials");
    refreshSweeps();
  } catch (err) { say(err.message, true); }
});

async function refreshSweeps() {
  let jobs;
  try { ({ body: jobs } = await api("/api/sweeps")); } catch (err) { return; }
  const tb = document.querySelector("#sweeps tbody");
  tb.innerHTML = "";
  for (const j of jobs.slice().reverse()) {
    const tr = document.createElement("tr");
    const cells = [j.id, j.model_set_label || j.model_set, j.status, "", j.rate_per_s ? j.rate_per_s.toFixed(2) + "/s" : "",
      j.eta_s !== null && j.eta_s !== undefined ? j.eta_s.toFixed(0) + " s" : ""];
    for (const c of cells) { const td = document.createElement("td"); td.textContent = c; tr.appendChild(td); }
    const bar = document.createElement("progress");
    bar.max = j.total; bar.value = j.done;
    tr.children[3].appendChild(bar);
    tr.children[3].appendChild(document.createTextNode(` ${j.done}/${j.total}`));
    const act = document.createElement("td");
    if (j.status === "queued" || j.status === "running") {
      const b = document.createElement("button");
      b.textContent = "cancel";
      b.onclick = () => api("/api/sweeps/" + j.id, { method: "DELETE" }).then(refreshSweeps, (err) => say(err.message, true));
      act.appendChild(b);
    }
    if (j.done > 0) {
      const a = document.createElement("a");
      a.href = j.report_url; a.target = "_blank"; a.rel = "noopener"; a.textContent = "report";
      act.appendChild(a);
    }
    tr.appendChild(act);
    tb.appendChild(tr);
  }
}

setInterval(refreshSweeps, 2000);
setInterval(renewLinkAccess, LINK_RENEW_MS);
renewLinkAccess().then(() => loadModelSets().catch((err) => say(err.message, true))).then(() => loadRobots())
  .then(refreshSweeps).catch((err) => say(err.message, true));
