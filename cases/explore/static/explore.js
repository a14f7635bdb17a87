// coinwall explore: the page.  Plain JavaScript and inline SVG, no library (it must work offline).
//
// Every request goes through `call(channel, ...)`: a newer call of the same channel aborts the older one
// (AbortController) and a reply that is not the newest is ignored, so the latest slider move wins; the
// server also drops stale requests that have not started (409 "superseded", ignored here).
"use strict";

const $ = (id) => document.getElementById(id);
const state = {
  wall: null,          // the wall spec the server knows: {expression, params} | {case} | {upload}
  b0: -0.3,
  bc: null,
  body: null,          // the last body drawn
  beam: null,          // the last beam (trajectories) and its animation
  sectionColour: 0,
};
window.exploreTimings = [];  // slider input -> outline updated (ms), read by the browser tests

const controllers = {};
const latest = {};

async function call(channel, url, payload, raw) {
  if (controllers[channel]) controllers[channel].abort();
  const controller = new AbortController();
  controllers[channel] = controller;
  const id = (latest[channel] || 0) + 1;
  latest[channel] = id;
  try {
    const response = await fetch(url, raw ? {method: "POST", body: payload, signal: controller.signal}
      : payload === undefined ? {signal: controller.signal}
        : {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(payload),
          signal: controller.signal});
    if (latest[channel] !== id || response.status === 409) return {stale: true};
    const type = response.headers.get("content-type") || "";
    if (response.ok && !type.startsWith("application/json") || url === "/api/export" && response.ok) {
      return {blob: await response.blob(), response};
    }
    if (!type.startsWith("application/json")) return {error: `the server answered ${response.status}`};
    const data = await response.json();  // reading the body can be aborted too: inside the try
    if (latest[channel] !== id) return {stale: true};
    if (!response.ok && !data.error) data.error = `the server answered ${response.status}`;
    return data;
  } catch (err) {
    if (err.name === "AbortError" || latest[channel] !== id) return {stale: true};
    return {error: "the server does not answer (is coinwall explore still running?)"};
  }
}

// ---------------------------------------------------------------------------------------------- messages
const FIELD_BOX = {wall: "wall-error", params: "wall-error", case: "wall-error", upload: "upload-error",
  b0: "b0-error", H: "billiard-error", beam: "billiard-error", kappa: "download-error", format: "download-error"};

function showError(data, fallback) {
  const box = $(FIELD_BOX[data.field] || fallback || "status-error");
  box.textContent = data.error;
  if (box.id === "wall-error") $("wall").classList.add("invalid");
}

function clearError(...ids) {
  for (const id of ids) $(id).textContent = "";
  if (ids.includes("wall-error")) $("wall").classList.remove("invalid");
}

function fmt(x, digits = 6) {
  if (x === null || x === undefined) return "—";
  return Number(x).toPrecision(digits).replace(/\.?0+(e|$)/, "$1");
}

// ---------------------------------------------------------------------------------------------- the wall
function wallSpec() {
  return Object.assign({}, state.wall);
}

function typedWall() {
  return {expression: $("wall").value, params: $("params").value};
}

let wallTimer = null;
function wallTyped() {
  clearTimeout(wallTimer);
  $("case").value = "";
  wallTimer = setTimeout(() => loadWall(typedWall(), null), 250);
}

async function loadWall(spec, b0) {
  const data = await call("wall", "/api/wall", Object.assign({}, spec, {b0: b0 === null ? state.b0 : b0}));
  if (data.stale) return;
  if (data.error) { showError(data, "wall-error"); return; }
  clearError("wall-error", "upload-error", "status-error");
  state.wall = spec;
  setCritical(data);
  setRange(data.range, b0 === null ? data.b0 : b0);
  await updateBody(null);
  refreshTable();
}

function setCritical(data) {
  state.bc = data.b_c_infinite ? Infinity : data.b_c;
  $("bc").textContent = data.b_c_text;
  $("bc").title = data.b_c_infinite ? "a concave kink: no convex body for any b0" : "b_c = −min(b + b″)";
}

function setRange(range, b0) {
  const slider = $("b0");
  const lo = Math.min(range[0], b0), hi = Math.max(range[1], b0);
  slider.min = lo; slider.max = hi; slider.step = "any";  // "any": a typed b0 is not rounded to a step
  slider.value = b0;
  state.b0 = b0;
  $("b0-number").value = Number(b0.toPrecision(12));
  const mark = $("bc-mark");
  if (Number.isFinite(state.bc) && state.bc >= lo && state.bc <= hi) {
    const f = (state.bc - lo) / (hi - lo);
    mark.style.left = `calc(8px + ${f} * (100% - 16px))`;
    mark.hidden = false;
  } else {
    mark.hidden = true;
  }
}

// ---------------------------------------------------------------------------------------------- the body
async function updateBody(started) {
  const data = await call("body", "/api/body", Object.assign(wallSpec(), {b0: state.b0}));
  if (data.stale) return;
  if (data.error) { showError(data, "b0-error"); return; }
  clearError("b0-error");
  drawBody(data);
  if (started !== null) {
    const ms = performance.now() - started;
    requestAnimationFrame(() => {
      const painted = performance.now() - started;
      window.exploreTimings.push({ms, painted, server: data.server_ms, solve: data.solve_ms});
      $("timing").textContent = `${ms.toFixed(0)} ms (server ${data.server_ms.toFixed(0)} ms)`;
    });
  }
  scheduleRealize();
}

function drawBody(data) {
  state.body = data;
  for (const id of ["kappa-uniform", "kappa-max", "realizable"]) $(id).textContent = "…";  // until /api/realize
  $("realizable").className = "";
  $("body-outline").setAttribute("d", data.path);
  $("lab-outline").setAttribute("d", data.path);
  const e = data.extent * 1.2;
  $("body-view").setAttribute("viewBox", `${-e} ${-e} ${2 * e} ${2 * e}`);
  $("com").setAttribute("r", 0.02 * data.extent);
  $("regime").textContent = data.regime;
  $("regime").className = `regime-${data.regime}`;
  $("body-info").textContent = `${data.points} nodes, area ${fmt(data.area, 5)}, wall error ${fmt(data.max_wall_error, 2)}`;
  const corners = $("corners"), windows = $("windows");
  corners.replaceChildren(); windows.replaceChildren();
  const ns = "http://www.w3.org/2000/svg";
  for (const c of data.corners) {
    const dot = document.createElementNS(ns, "circle");
    dot.setAttribute("cx", c.x); dot.setAttribute("cy", c.y); dot.setAttribute("r", 0.035 * data.extent);
    dot.setAttribute("class", "corner");
    const title = document.createElementNS(ns, "title");
    title.textContent = `corner at ${fmt(c.direction, 4)} rad, window ±${fmt(c.half_width, 4)}, deficit ${fmt(c.max_deficit, 3)}`;
    dot.appendChild(title);
    corners.appendChild(dot);
    const r = 0.5 * data.extent, [lo, hi] = c.window;
    const wedge = document.createElementNS(ns, "path");
    wedge.setAttribute("d", `M${c.x} ${c.y}L${c.x + r * Math.cos(lo)} ${c.y + r * Math.sin(lo)}` +
      `A${r} ${r} 0 0 1 ${c.x + r * Math.cos(hi)} ${c.y + r * Math.sin(hi)}Z`);
    wedge.setAttribute("class", "window");
    windows.appendChild(wedge);
  }
  drawCurves(data);
  const warnings = $("warnings");
  warnings.replaceChildren();
  for (const text of data.warnings) {
    const li = document.createElement("li"); li.textContent = `warning: ${text}`; warnings.appendChild(li);
  }
  updateCli();
}

function drawCurves(data) {
  const W = 400, Hh = 200, pad = 8;
  const finite = (v) => v !== null && Number.isFinite(v);
  const main = data.wall.concat(data.own_wall).filter(finite);
  let lo = Math.min(0, ...main), hi = Math.max(...main);
  const span = Math.max(hi - lo, 1e-9);
  const rho = data.rho.map((v) => (finite(v) ? Math.max(lo - span, Math.min(hi + span, v)) : null));
  for (const v of rho) if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  const x = (t) => (t / (2 * Math.PI)) * W;
  const y = (v) => Hh - pad - ((v - lo) / (hi - lo || 1)) * (Hh - 2 * pad);
  const points = (values) => values.map((v, i) => (v === null ? "" : `${x(data.theta[i]).toFixed(2)},${y(v).toFixed(2)}`))
    .filter((s) => s).join(" ");
  $("plot-wall").setAttribute("points", points(data.wall));
  $("plot-own").setAttribute("points", points(data.own_wall));
  $("plot-rho").setAttribute("points", points(rho));
  $("wall-axes").innerHTML = `<line class="zero" x1="0" x2="${W}" y1="${y(0)}" y2="${y(0)}"></line>` +
    [1, 2, 3].map((k) => `<line class="tick" x1="${k * W / 4}" x2="${k * W / 4}" y1="0" y2="${Hh}"></line>`).join("");
}

let realizeTimer = null;
function scheduleRealize() {
  // κ_max is a linear programme (~70 ms): asked for once the slider rests, not on every move
  clearTimeout(realizeTimer);
  realizeTimer = setTimeout(async () => {
    const data = await call("realize", "/api/realize", Object.assign(wallSpec(), {b0: state.b0}));
    if (data.stale) return;
    if (data.error) { showError(data, "status-error"); return; }
    $("kappa-uniform").textContent = fmt(data.kappa_uniform);
    $("kappa-max").textContent = fmt(data.kappa_max);
    const box = $("realizable");
    box.textContent = data.realizable ? "✓ some mass distribution gives it"
      : "✗ no mass distribution (κ_max < 1)";
    box.className = data.realizable ? "ok" : "bad";
  }, 200);
}

function sliderMoved() {
  const started = performance.now();
  state.b0 = Number($("b0").value);
  $("b0-number").value = Number(state.b0.toPrecision(12));
  stopBeam();
  updateBody(started);
  refreshTable();
}

function numberTyped() {
  const value = Number($("b0-number").value);
  if ($("b0-number").value.trim() === "" || !Number.isFinite(value)) {
    $("b0-error").textContent = "b0 must be a number"; return;
  }
  const slider = $("b0");
  if (value < Number(slider.min) || value > Number(slider.max)) {
    setRange([Number(slider.min), Number(slider.max)], value);
  }
  slider.value = value;
  const started = performance.now();
  state.b0 = value;
  stopBeam();
  updateBody(started);
  refreshTable();
}

// ---------------------------------------------------------------------------------------------- downloads
function updateCli() {
  const w = state.wall || {};
  let wall = w.case ? `case:${w.case}` : w.upload ? "WALL.csv" : `"${w.expression}"`;
  if (w.expression && w.params) {
    for (const p of String(w.params).split(/[,;\n]/).map((s) => s.trim()).filter((s) => s)) wall += ` --param ${p}`;
  }
  const kappa = $("kappa").value, units = $("units").value;
  const scale = kappa ? ` --kappa ${kappa} --units ${units || "mm"}` +
    ($("allow-unrealizable").checked ? " --allow-unrealizable" : "") : "";
  $("download-cli").textContent = `coinwall solve ${wall} --b0 ${Number(state.b0.toPrecision(12))} -o body.svg${scale}`;
}

async function download(format) {
  clearError("download-error");
  const kappa = $("kappa").value.trim();
  const payload = Object.assign(wallSpec(), {b0: state.b0, format, kappa: kappa === "" ? null : Number(kappa),
    units: $("units").value || null, allow_unrealizable: $("allow-unrealizable").checked});
  const data = await call("export", "/api/export", payload);
  if (data.stale) return;
  if (data.error) { showError(data, "download-error"); return; }
  const url = URL.createObjectURL(data.blob);
  const link = document.createElement("a");
  link.href = url; link.download = `body.${format}`;
  document.body.appendChild(link); link.click(); link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

// ---------------------------------------------------------------------------------------------- uploads
async function uploaded() {
  const file = $("upload").files[0];
  if (!file) return;
  clearError("upload-error");
  const data = await call("upload", `/api/upload?name=${encodeURIComponent(file.name)}`, file, true);
  if (data.stale) return;
  if (data.error) { showError(data, "upload-error"); return; }
  state.wall = {upload: data.upload};
  $("case").value = "";
  $("wall").value = `(uploaded: ${file.name})`;
  $("params").value = "";
  setCritical(data);
  setRange(data.range, data.b0);
  await updateBody(null);
  refreshTable();
}

// ---------------------------------------------------------------------------------------------- cases
let cases = {};
async function loadCases() {
  const data = await call("cases", "/api/cases");
  if (data.error || data.stale) return;
  const picker = $("case");
  for (const c of data.cases) {
    cases[c.name] = c;
    const option = document.createElement("option");
    option.value = c.name; option.textContent = `${c.name}: ${c.title}`;
    picker.appendChild(option);
  }
  picker.value = data.default;
}

function casePicked() {
  const c = cases[$("case").value];
  if (!c) return;
  if (c.H) $("H").value = c.H;
  if (c.expression) {
    $("wall").value = c.expression;
    $("params").value = Object.entries(c.params).map(([k, v]) => `${k}=${v}`).join(", ");
    loadWall(typedWall(), c.b0).then(() => { $("case").value = c.name; });
  } else {
    $("wall").value = `(case ${c.name})`; $("params").value = "";
    loadWall({case: c.name}, c.b0).then(() => { $("case").value = c.name; });
  }
}

// ---------------------------------------------------------------------------------------------- billiard
const TABLE = {W: 360, H: 200, lo: 0, hi: 1};
const tx = (theta) => (((theta % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI)) / (2 * Math.PI) * TABLE.W;
const ty = (eta) => TABLE.H - ((eta - TABLE.lo) / (TABLE.hi - TABLE.lo)) * TABLE.H;

let tableTimer = null;
function refreshTable() {
  clearTimeout(tableTimer);
  tableTimer = setTimeout(async () => {
    const data = await call("table", "/api/table", Object.assign(wallSpec(), {b0: state.b0, H: Number($("H").value)}));
    if (data.stale) return;
    if (data.error) { showError(data, "billiard-error"); return; }
    clearError("billiard-error");
    drawTable(data);
  }, 150);
}

function drawTable(data) {
  const finite = (v) => v !== null;
  const lo = Math.min(...data.lower.filter(finite)), hi = Math.max(...data.upper.filter(finite));
  const pad = 0.05 * (hi - lo);
  TABLE.lo = lo - pad; TABLE.hi = hi + pad;
  const line = (values) => values.map((v, i) => `${i ? "L" : "M"}${(data.theta[i] / (2 * Math.PI) * TABLE.W).toFixed(2)} ${ty(v).toFixed(2)}`).join("");
  $("table-lower").setAttribute("d", `${line(data.lower)}L${TABLE.W} ${TABLE.H}L0 ${TABLE.H}Z`);
  $("table-upper").setAttribute("d", `${line(data.upper)}L${TABLE.W} 0L0 0Z`);
  $("lab-ceiling").setAttribute("y1", data.H); $("lab-ceiling").setAttribute("y2", data.H);
  const reach = state.body ? state.body.extent : 1;
  const w = Math.max(data.H, 2 * reach) * 1.1;
  $("lab-view").setAttribute("viewBox", `${-w / 2} ${-data.H - 0.1 * data.H} ${w} ${1.2 * data.H}`);
  if (state.body) $("lab-outline").setAttribute("d", state.body.path);
}

async function tableClicked(event) {
  const svg = $("table-view");
  const p = svg.createSVGPoint(); p.x = event.clientX; p.y = event.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  const theta = q.x / TABLE.W * 2 * Math.PI;
  const eta = TABLE.lo + (TABLE.H - q.y) / TABLE.H * (TABLE.hi - TABLE.lo);
  const deg = Math.PI / 180;
  stopBeam();
  $("billiard-status").textContent = "computing the beam (the first beam of a new wall compiles the billiard kernel: ~10 s) …";
  const data = await call("beam", "/api/beam", Object.assign(wallSpec(), {b0: state.b0, H: Number($("H").value),
    theta, eta, rays: Number($("rays").value), direction: Number($("direction").value) * deg,
    spread: Number($("spread").value) * deg, collisions: 40, section_collisions: 4000}));
  if (data.stale) return;
  if (data.error) { showError(data, "billiard-error"); $("billiard-status").textContent = ""; return; }
  clearError("billiard-error");
  $("billiard-status").textContent = `${data.rays.length} rays from θ = ${fmt(theta, 4)}, η = ${fmt(eta, 4)}` +
    (state.body && state.body.regime === "corner" ? " (below b_c no body has this wall: the body shown is the largest under it)" : "");
  addSection(data.section);
  startBeam(data);
}

function addSection(section) {
  const ns = "http://www.w3.org/2000/svg";
  const path = document.createElementNS(ns, "path");
  let d = "";
  for (let i = 0; i < section.theta.length; i++) {
    const x = section.theta[i] / (2 * Math.PI) * 360, y = 90 - section.phi[i] / (Math.PI / 2) * 88;
    d += `M${x.toFixed(2)} ${y.toFixed(2)}h0`;
  }
  path.setAttribute("d", d);
  path.setAttribute("class", `orbit c${state.sectionColour++ % 6}`);
  $("section-points").appendChild(path);
}

function rayAt(ray, start, t) {
  // the state at time t: straight flight from the last collision before t (or from the start)
  let k = -1;
  let lo = 0, hi = ray.t.length - 1;
  while (lo <= hi) { const mid = (lo + hi) >> 1; if (ray.t[mid] <= t) { k = mid; lo = mid + 1; } else hi = mid - 1; }
  if (k < 0) return [start[0] + start[2] * t, start[1] + start[3] * t, start[2]];
  const dt = t - ray.t[k];
  return [ray.theta[k] + ray.vt[k] * dt, ray.eta[k] + ray.ve[k] * dt, ray.vt[k]];
}

function startBeam(data) {
  const end = Math.min(...data.rays.map((r) => (r.t.length ? r.t[r.t.length - 1] : 0)));
  state.beam = {data, t: 0, end, frame: null, trail: []};
  const step = () => {
    const beam = state.beam;
    if (!beam) return;
    beam.t += beam.end / 600;  // about ten seconds at 60 frames a second
    let dots = "";
    for (let i = 0; i < beam.data.rays.length; i++) {
      const [theta, eta] = rayAt(beam.data.rays[i], beam.data.start[i], beam.t);
      dots += `M${tx(theta).toFixed(1)} ${ty(eta).toFixed(1)}h0`;
    }
    $("beam-dots").setAttribute("d", dots);
    const [theta, eta] = rayAt(beam.data.rays[0], beam.data.start[0], beam.t);
    $("beam-centre").setAttribute("cx", tx(theta)); $("beam-centre").setAttribute("cy", ty(eta));
    beam.trail.push(`${beam.trail.length ? "L" : "M"}${tx(theta).toFixed(1)} ${ty(eta).toFixed(1)}`);
    if (beam.trail.length > 1 && Math.abs(tx(theta) - tx(rayAt(beam.data.rays[0], beam.data.start[0], beam.t - beam.end / 600)[0])) > 180) {
      beam.trail[beam.trail.length - 1] = beam.trail[beam.trail.length - 1].replace("L", "M");  // wrapped in θ
    }
    $("beam-trails").setAttribute("d", beam.trail.slice(-400).join("").replace(/^L/, "M"));
    // the rigid body: orientation ψ = −θ − π/2 (forward/dynamics/rigidbody.py), height η (units of κ)
    const psi = (-theta - Math.PI / 2) * 180 / Math.PI;
    $("lab-body").setAttribute("transform", `translate(0,${eta}) rotate(${psi})`);
    if (beam.t < beam.end) beam.frame = requestAnimationFrame(step);
  };
  state.beam.frame = requestAnimationFrame(step);
}

function stopBeam() {
  if (state.beam && state.beam.frame) cancelAnimationFrame(state.beam.frame);
  state.beam = null;
  $("beam-dots").setAttribute("d", "");
  $("beam-trails").setAttribute("d", "");
}

function clearBilliard() {
  stopBeam();
  $("section-points").replaceChildren();
  $("billiard-status").textContent = "";
}

// ---------------------------------------------------------------------------------------------- start
function start() {
  $("wall").addEventListener("input", wallTyped);
  $("params").addEventListener("input", wallTyped);
  $("case").addEventListener("change", casePicked);
  $("upload").addEventListener("change", uploaded);
  $("b0").addEventListener("input", sliderMoved);
  $("b0-number").addEventListener("change", numberTyped);
  $("H").addEventListener("change", () => { clearBilliard(); refreshTable(); });
  $("table-view").addEventListener("click", tableClicked);
  $("beam-clear").addEventListener("click", clearBilliard);
  $("kappa").addEventListener("input", updateCli);
  $("units").addEventListener("change", updateCli);
  $("allow-unrealizable").addEventListener("change", updateCli);
  for (const format of ["svg", "dxf", "json"]) $(`download-${format}`).addEventListener("click", () => download(format));
  loadCases();
  loadWall(typedWall(), Number($("b0-number").value)).then(() => { document.body.dataset.ready = "1"; });
}

document.addEventListener("DOMContentLoaded", start);
