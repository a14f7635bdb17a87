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
  b0Step: 0.001,       // the slider's resolution (a thousandth of its range)
  bc: null,
  body: null,          // the last body drawn
  table: null,         // the last billiard table drawn
  beam: null,          // the last beam (trajectories) and its animation
  sections: [],        // the Poincaré sections of the clicks, in their colours
  params: [],          // the expression's parameters, in order: {name, value, min, max}
};
const MAX_UPLOAD_BYTES = 16 * 2 ** 20;  // the server's limit (app.py): a larger file is refused before sending
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

// the number in an <input type="number">: null when empty, undefined (with the error shown in `box`) when the
// browser could not read what was typed ("1_0", "1,5": its value is then "", which must not mean "no value")
function numberInput(id, label, box, required = true) {
  const el = $(id);
  const empty = el.value.trim() === "";
  if ((el.validity && el.validity.badInput) || (required && empty)) {
    showError({error: `${label} must be a decimal number such as 2.5 or 1e-3`}, box);
    return undefined;
  }
  return empty ? null : Number(el.value);
}

function clearError(...ids) {
  for (const id of ids) $(id).textContent = "";
  if (ids.includes("wall-error")) $("wall").classList.remove("invalid");
}

// a number with at most `digits` significant digits, trailing zeros of the fraction dropped
function fmt(x, digits = 6) {
  if (x === null || x === undefined || !Number.isFinite(Number(x))) return "—";
  const text = Number(x).toPrecision(digits);
  const [mantissa, exponent] = text.split("e");
  const trimmed = mantissa.includes(".") ? mantissa.replace(/0+$/, "").replace(/\.$/, "") : mantissa;
  return exponent === undefined ? trimmed : `${trimmed}e${Number(exponent)}`;
}

// a value shown at the precision of `step` (the slider's resolution): no 0.30000000000000004
function atStep(x, step) {
  const decimals = Math.max(0, Math.min(12, -Math.floor(Math.log10(step))));
  return Number(Number(x).toFixed(decimals));
}

// ---------------------------------------------------------------------------------------------- plots
// Every plot is drawn in pixels (its viewBox is its size on the screen), so ticks and labels keep their size;
// world coordinates go through the scales x(), y() that frame() returns.
const NS = "http://www.w3.org/2000/svg";

function svgEl(name, attrs, parent, text) {
  const node = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  if (parent) parent.appendChild(node);
  return node;
}

function niceStep(span, count) {
  const raw = span / Math.max(1, count);
  const power = 10 ** Math.floor(Math.log10(raw));
  const f = raw / power;
  return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * power;
}

function ticks(lo, hi, count) {
  const step = niceStep(hi - lo || 1, count), out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) out.push(atStep(v, step));
  return {values: out, step};
}

const THETA_TICKS = [[0, "0"], [Math.PI / 2, "π/2"], [Math.PI, "π"], [1.5 * Math.PI, "3π/2"], [2 * Math.PI, "2π"]];

// Axes with ticks and labels.  opts: {x: [lo, hi], y: [lo, hi], xlabel, ylabel, theta (θ ticks on x), equal
// (same scale on both axes, centred), margin}.  Returns {x, y, left, top, width, height, scale}.
function frame(svg, axes, opts) {
  const W = Math.max(50, svg.clientWidth), H = Math.max(50, svg.clientHeight);
  svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
  const m = Object.assign({left: 42, right: 8, top: 8, bottom: 30}, opts.margin || {});
  let [x0, x1] = opts.x, [y0, y1] = opts.y;
  const width = W - m.left - m.right, height = H - m.top - m.bottom;
  if (opts.equal) {  // one unit is as long on both axes: widen the shorter range
    const s = Math.min(width / (x1 - x0), height / (y1 - y0));
    const cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    [x0, x1] = [cx - width / s / 2, cx + width / s / 2];
    [y0, y1] = [cy - height / s / 2, cy + height / s / 2];
  }
  const x = (v) => m.left + (v - x0) / (x1 - x0) * width;
  const y = (v) => m.top + (y1 - v) / (y1 - y0) * height;
  axes.replaceChildren();
  const xt = opts.theta ? THETA_TICKS.map(([v, t]) => [v, t])
    : (({values, step}) => values.map((v) => [v, fmt(atStep(v, step), 6)]))(ticks(x0, x1, Math.max(2, width / 70)));
  const yt = ticks(y0, y1, Math.max(2, height / 40));
  for (const [v, label] of xt) {
    if (v < x0 - 1e-12 || v > x1 + 1e-12) continue;
    svgEl("line", {class: "grid", x1: x(v), x2: x(v), y1: m.top, y2: m.top + height}, axes);
    svgEl("line", {class: "axis", x1: x(v), x2: x(v), y1: m.top + height, y2: m.top + height + 4}, axes);
    svgEl("text", {x: x(v), y: m.top + height + 14, "text-anchor": "middle"}, axes, label);
  }
  for (const v of yt.values) {
    svgEl("line", {class: "grid", x1: m.left, x2: m.left + width, y1: y(v), y2: y(v)}, axes);
    svgEl("line", {class: "axis", x1: m.left - 4, x2: m.left, y1: y(v), y2: y(v)}, axes);
    svgEl("text", {x: m.left - 6, y: y(v) + 3, "text-anchor": "end"}, axes, fmt(atStep(v, yt.step), 6));
  }
  if (y0 < 0 && y1 > 0 && opts.zero !== false) {
    svgEl("line", {class: "zero", x1: m.left, x2: m.left + width, y1: y(0), y2: y(0)}, axes);
  }
  svgEl("path", {class: "frame", d: `M${m.left} ${m.top}h${width}v${height}h${-width}Z`}, axes);
  if (opts.xlabel) {
    svgEl("text", {class: "label", x: m.left + width, y: H - 3, "text-anchor": "end"}, axes, opts.xlabel);
  }
  if (opts.ylabel) {
    svgEl("text", {class: "label", x: 11, y: m.top + height / 2, "text-anchor": "middle",
      transform: `rotate(-90 11 ${m.top + height / 2})`}, axes, opts.ylabel);
  }
  return {x, y, left: m.left, top: m.top, width, height, scale: width / (x1 - x0), x0, x1, y0, y1};
}

// ---------------------------------------------------------------------------------------------- parameters
// Every free name of the expression has a slider with a number box; its range is shown at both ends and can be
// typed.  The server says which names the expression uses (/api/wall answers "params"); names no longer used
// disappear, new ones start at the server's value.
function paramValues() {
  return Object.fromEntries(state.params.map((p) => [p.name, p.value]));
}

function paramRange(value) {
  if (value === 0) return [-1, 1];
  return value > 0 ? [0, 2 * value] : [2 * value, 0];
}

function setParams(list) {
  const old = Object.fromEntries(state.params.map((p) => [p.name, p]));
  state.params = list.map(([name, value]) => {
    if (old[name] && old[name].value === value) return old[name];
    const [min, max] = old[name] && value >= old[name].min && value <= old[name].max
      ? [old[name].min, old[name].max] : paramRange(value);
    return {name, value, min, max};
  });
  const box = $("params");
  const keep = new Set(state.params.map((p) => p.name));
  for (const row of [...box.children]) if (!keep.has(row.dataset.name)) row.remove();
  state.params.forEach((p, index) => {
    let row = box.querySelector(`.param[data-name="${p.name}"]`);
    if (!row) row = paramRow(p);
    if (box.children[index] !== row) box.insertBefore(row, box.children[index] || null);
    showParam(p);
  });
}

function paramRow(p) {
  const row = document.createElement("div");
  row.className = "param"; row.dataset.name = p.name;
  row.innerHTML = `<div class="head"><label for="param-${p.name}-value"></label>` +
    `<input id="param-${p.name}-value" type="number" step="any" aria-label="value"></div>` +
    `<div class="track"><input id="param-${p.name}-min" type="number" step="any" aria-label="smallest">` +
    `<input id="param-${p.name}" type="range" step="any">` +
    `<input id="param-${p.name}-max" type="number" step="any" aria-label="largest"></div>`;
  row.querySelector("label").textContent = `${p.name} =`;
  const find = (suffix) => row.querySelector(`#param-${CSS.escape(p.name)}${suffix}`);
  const current = () => state.params.find((q) => q.name === p.name);
  find("").addEventListener("input", (event) => {
    const q = current(); q.value = atStep(Number(event.target.value), (q.max - q.min) / 1000);
    find("-value").value = q.value;
    paramChanged();
  });
  find("-value").addEventListener("change", (event) => {
    const q = current(), value = Number(event.target.value);
    if (event.target.value.trim() === "" || !Number.isFinite(value)) { find("-value").value = q.value; return; }
    q.value = value;
    if (value < q.min) q.min = value;
    if (value > q.max) q.max = value;
    showParam(q);
    paramChanged();
  });
  for (const end of ["min", "max"]) {
    find(`-${end}`).addEventListener("change", (event) => {
      const q = current(), value = Number(event.target.value);
      if (event.target.value.trim() !== "" && Number.isFinite(value)) q[end] = value;
      if (q.min > q.max) [q.min, q.max] = [q.max, q.min];
      if (q.min === q.max) q.max = q.min + 1;
      const clamped = Math.min(q.max, Math.max(q.min, q.value));
      const moved = clamped !== q.value;
      q.value = clamped;
      showParam(q);
      if (moved) paramChanged();
    });
  }
  return row;
}

function showParam(p) {
  const id = `param-${p.name}`;
  const slider = document.getElementById(id);
  slider.min = p.min; slider.max = p.max; slider.step = niceStep(p.max - p.min, 1000); slider.value = p.value;
  document.getElementById(`${id}-value`).value = p.value;
  document.getElementById(`${id}-min`).value = p.min;
  document.getElementById(`${id}-max`).value = p.max;
}

let paramTimer = null;
function paramChanged() {
  // the same wall with another parameter value: b0 and H stay, b_c and the body follow
  clearTimeout(paramTimer);
  $("case").value = "";
  paramTimer = setTimeout(() => loadWall(typedWall(), {b0: state.b0, keep: true}), 60);
}

// ---------------------------------------------------------------------------------------------- the wall
function wallSpec() {
  return Object.assign({}, state.wall);
}

function typedWall() {
  return {expression: $("wall").value, params: paramValues()};
}

let wallTimer = null;
function wallTyped() {
  clearTimeout(wallTimer);
  $("case").value = "";
  wallTimer = setTimeout(() => loadWall(typedWall(), {}), 250);
}

// Load a wall: a new one starts at the b0 the server proposes (0, a case's b0) and its H; {keep: true} (a
// parameter moved) keeps b0 and H.
async function loadWall(spec, how) {
  const started = performance.now();
  const keep = Boolean(how.keep);
  const b0 = how.b0 === undefined ? null : how.b0;
  const data = await call("wall", "/api/wall", Object.assign({}, spec, {b0}));
  if (data.stale) return false;
  if (data.error) { showError(data, "wall-error"); return false; }
  clearError("wall-error", "upload-error", "status-error");
  if (data.params) {
    setParams(data.params);
    spec = Object.assign({}, spec, {params: paramValues()});
  }
  state.wall = spec;
  setCritical(data);
  setRange(data.range, data.b0);
  if (!keep) {
    $("H").value = how.H || data.H;
    clearBilliard();
  }
  await updateBody(started);
  refreshTable();
  return true;
}

function setCritical(data) {
  state.bc = data.b_c_infinite ? Infinity : data.b_c;
  $("bc").textContent = data.b_c_text;
  $("critical-angles").textContent = data.critical_angles_text;
  $("bc").title = data.b_c_infinite ? "a concave kink: no convex body for any b0" : "b_c = −min(b + b″)";
}

function setRange(range, b0) {
  const slider = $("b0");
  const step = niceStep(range[1] - range[0], 1000), coarse = niceStep(range[1] - range[0], 50);
  // the ends on a round grid, inside the server's range (its low end keeps the centre of mass in the body)
  const lo = atStep(Math.min(Math.ceil(range[0] / coarse) * coarse, Math.floor(b0 / step) * step), step);
  const hi = atStep(Math.max(Math.floor(range[1] / coarse) * coarse, Math.ceil(b0 / step) * step), step);
  slider.min = lo; slider.max = hi; slider.step = step;
  slider.value = b0;
  state.b0 = b0;
  state.b0Step = step;
  $("b0-number").value = Number(b0.toPrecision(12));
  $("b0-min").textContent = fmt(lo, 4);
  $("b0-max").textContent = fmt(hi, 4);
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
// `started`: when the user's action began (performance.now()); every redraw shows its own time, a new wall's
// (its request included) as well as a slider move's
async function updateBody(started) {
  const data = await call("body", "/api/body", Object.assign(wallSpec(), {b0: state.b0}));
  if (data.stale) return;
  if (data.error) { showError(data, "b0-error"); return; }
  clearError("b0-error");
  drawBody(data);
  const ms = performance.now() - started;
  // written at once (a tab in the background runs no animation frames); the painted time follows the paint
  $("timing").textContent = `${ms.toFixed(0)} ms (server ${data.server_ms.toFixed(0)} ms)`;
  $("timing").dataset.count = String(Number($("timing").dataset.count || 0) + 1);
  requestAnimationFrame(() => {
    window.exploreTimings.push({ms, painted: performance.now() - started, server: data.server_ms,
      solve: data.solve_ms});
  });
  scheduleRealize();
}

function drawBody(data) {
  state.body = data;
  for (const id of ["kappa-uniform", "kappa-max", "realizable"]) $(id).textContent = "…";  // until /api/realize
  $("realizable").className = "";
  $("body-outline").setAttribute("d", data.path);
  $("lab-outline").setAttribute("d", data.path);
  $("regime").textContent = data.regime_decided ? data.regime : `undecided (${data.regimes.join(" / ")})`;
  $("regime").className = `regime-${data.regime}`;
  $("outline-tolerance").textContent = data.outline_tolerance === null ? "exact (a formula wall, or no band)" :
    `within ${fmt(data.outline_tolerance, 2)} κ of every body the samples allow` +
    (data.possible_corners ? `; ${data.possible_corners} possible corner(s)` : "");
  $("body-info").textContent = `${data.points} nodes, area ${fmt(data.area, 4)}, wall error ${fmt(data.max_wall_error, 2)}`;
  drawBodyView(data);
  drawCurves(data);
  const warnings = $("warnings");
  warnings.replaceChildren();
  for (const text of data.warnings) {
    const li = document.createElement("li"); li.textContent = `warning: ${text}`; warnings.appendChild(li);
  }
  updateCli();
}

function drawBodyView(data) {
  const e = data.extent * 1.15;
  const f = frame($("body-view"), $("body-axes"), {x: [-e, e], y: [-e, e], equal: true, xlabel: "x / κ",
    ylabel: "y / κ"});
  // the outline in body units (the solver's exact cubic segments), placed by one transform; y up
  $("body-world").setAttribute("transform", `translate(${f.x(0)} ${f.y(0)}) scale(${f.scale} ${-f.scale})`);
  const px = 1 / f.scale;  // one pixel in body units
  $("com").setAttribute("r", 3 * px);
  const corners = $("corners"), windows = $("windows");
  corners.replaceChildren(); windows.replaceChildren();
  for (const c of data.corners) {
    const dot = svgEl("circle", {cx: c.x, cy: c.y, r: 4 * px, class: "corner"}, corners);
    svgEl("title", {}, dot, `corner at ${fmt(c.direction, 4)} rad, window ±${fmt(c.half_width, 4)}, ` +
      `deficit ${fmt(c.max_deficit, 3)}`);
    const r = 0.5 * data.extent, [lo, hi] = c.window;
    svgEl("path", {class: "window", d: `M${c.x} ${c.y}L${c.x + r * Math.cos(lo)} ${c.y + r * Math.sin(lo)}` +
      `A${r} ${r} 0 0 1 ${c.x + r * Math.cos(hi)} ${c.y + r * Math.sin(hi)}Z`}, windows);
  }
}

function drawCurves(data) {
  const finite = (v) => v !== null && Number.isFinite(v);
  const main = data.wall.concat(data.own_wall).filter(finite);
  let lo = Math.min(0, ...main), hi = Math.max(...main);
  const span = Math.max(hi - lo, 1e-9);
  const curvature = data.rho_data;  // a sampled wall: the discrete ρ of its samples with their intervals, not b + b″
  let rho = [];
  if (curvature) {
    // the range that decides the regime: the bulk of the samples (2nd to 90th percentile), zero and b0 − b_c;
    // the edges of a polygon are spikes of ρ (edge length over the spacing): counted, not drawn off the page
    const middle = curvature.low.map((v, i) => (finite(v) && finite(curvature.high[i]) ? 0.5 * (v + curvature.high[i]) : null))
      .filter(finite).sort((a, b) => a - b);
    const at = (f) => middle[Math.min(middle.length - 1, Math.floor(f * (middle.length - 1)))];
    const pad = 0.15 * Math.max(at(0.9) - at(0.02), 1e-9 * span);
    lo = Math.min(lo, at(0.02) - pad, finite(curvature.b_c_upper) ? state.b0 - curvature.b_c_upper - pad : 0);
    hi = Math.max(hi, at(0.9) + pad);
  } else {
    rho = data.rho.map((v) => (finite(v) ? Math.max(lo - span, Math.min(hi + span, v)) : null));
    for (const v of rho) if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  }
  const pad = 0.05 * (hi - lo || 1);
  const f = frame($("wall-plot"), $("wall-axes"), {x: [0, 2 * Math.PI], y: [lo - pad, hi + pad], theta: true,
    xlabel: "θ", ylabel: "b0 + b, ρ  (κ)"});
  const points = (values) => values.map((v, i) => (v === null ? "" : `${f.x(data.theta[i]).toFixed(1)},${f.y(v).toFixed(1)}`))
    .filter((s) => s).join(" ");
  $("plot-wall").setAttribute("points", points(data.wall));
  $("plot-own").setAttribute("points", points(data.own_wall));
  $("plot-rho").setAttribute("points", curvature ? "" : points(rho));
  let bars = "", dots = "", off = 0, most = -Infinity;
  if (curvature) {
    const clip = (v) => Math.max(lo - pad, Math.min(hi + pad, v));
    const width = Math.max(1, f.width / curvature.theta.length);
    for (let i = 0; i < curvature.theta.length; i++) {
      const a = curvature.low[i], b = curvature.high[i];
      if (!finite(a) || !finite(b)) continue;
      if (b > hi + pad || a < lo - pad) { off += 1; most = Math.max(most, b); }
      const x = f.x(curvature.theta[i]).toFixed(1);
      // each sample's interval as a bar at least a pixel tall (exact data: a dot on the value)
      bars += `M${x} ${f.y(clip(a)).toFixed(1)}V${(Math.min(f.y(clip(b)), f.y(clip(a)) - 1)).toFixed(1)}`;
      if (curvature.value && finite(curvature.value[i]) && curvature.value[i] >= lo - pad && curvature.value[i] <= hi + pad) {
        dots += `M${x} ${f.y(curvature.value[i]).toFixed(1)}h0`;
      }
    }
    $("plot-rho-band").setAttribute("stroke-width", width.toFixed(1));
  }
  $("plot-rho-band").setAttribute("d", bars);
  $("plot-rho-dots").setAttribute("d", curvature && curvature.theta.length <= 400 ? dots : "");
  $("rho-key").textContent = !curvature ? "ρ = b0 + b + b″ (< 0: no convex body)"
    : `ρ of the ${curvature.samples} samples (discrete, each with the interval its rounding allows` +
      `${curvature.binned ? `; bounds per bin of θ` : ""}; < 0: no convex body)`;
  $("rho-off").textContent = off ? `${off} ${curvature.binned ? "bins" : "samples"} off scale (up to ${fmt(most, 3)})` : "";
  // the corner windows: the wall angles each corner serves (where the body's own wall leaves b0 + b)
  const windows = $("wall-windows");
  windows.replaceChildren();
  const band = (a, b) => svgEl("rect", {class: "window", x: f.x(a), y: f.top, width: Math.max(1, f.x(b) - f.x(a)),
    height: f.height}, windows);
  const TAU = 2 * Math.PI;
  for (const c of data.corners) {
    let [a, b] = c.window;
    a = ((a % TAU) + TAU) % TAU; b = a + ((((c.window[1] - c.window[0]) % TAU) + TAU) % TAU);
    if (b <= TAU) band(a, b); else { band(a, TAU); band(0, b - TAU); }
  }
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
  state.b0 = atStep(Number($("b0").value), state.b0Step || 1e-6);
  $("b0-number").value = state.b0;
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
    for (const [name, value] of Object.entries(w.params)) wall += ` --param ${name}=${value}`;
  }
  const kappa = $("kappa").value, units = $("units").value;
  const scale = kappa ? ` --kappa ${kappa} --units ${units || "mm"}` +
    ($("allow-unrealizable").checked ? " --allow-unrealizable" : "") : "";
  $("download-cli").textContent = `coinwall solve ${wall} --b0 ${Number(state.b0.toPrecision(12))} -o body.svg${scale}`;
}

async function download(format) {
  clearError("download-error");
  const kappa = numberInput("kappa", "κ", "download-error", false);
  if (kappa === undefined) return;
  const payload = Object.assign(wallSpec(), {b0: state.b0, format, kappa,
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
  const started = performance.now();
  clearError("upload-error");
  if (file.size > MAX_UPLOAD_BYTES) {  // the server would refuse it (413): say so without sending it
    showError({error: `the file is larger than ${MAX_UPLOAD_BYTES / 2 ** 20} MiB`, field: "upload"});
    return;
  }
  const data = await call("upload", `/api/upload?name=${encodeURIComponent(file.name)}`, file, true);
  if (data.stale) return;
  if (data.error) { showError(data, "upload-error"); return; }
  clearError("wall-error", "status-error");
  state.wall = {upload: data.upload};
  $("case").value = "";
  $("wall").value = `(uploaded: ${file.name})`;
  setParams([]);
  setCritical(data);
  setRange(data.range, data.b0);  // b0 = 0: a drawing comes back at its own size
  $("H").value = data.H;
  clearBilliard();
  await updateBody(started);
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
  const how = {b0: c.b0, H: c.H || undefined};
  if (c.expression) {
    $("wall").value = c.expression;
    setParams(Object.entries(c.params));
    loadWall(typedWall(), how).then(() => { $("case").value = c.name; });
  } else {
    $("wall").value = `(case ${c.name})`;
    setParams([]);
    loadWall({case: c.name}, how).then(() => { $("case").value = c.name; });
  }
}

// ---------------------------------------------------------------------------------------------- billiard
let TABLE = null;  // the table's frame: scales x(θ), y(η) and their inverses for clicks
const TAU = 2 * Math.PI;
const wrap = (theta) => ((theta % TAU) + TAU) % TAU;
const tx = (theta) => (TABLE ? TABLE.x(wrap(theta)) : 0);
const ty = (eta) => (TABLE ? TABLE.y(eta) : 0);

let tableTimer = null;
function refreshTable() {
  clearTimeout(tableTimer);
  tableTimer = setTimeout(async () => {
    const H = numberInput("H", "H", "billiard-error");
    if (H === undefined) return;
    const data = await call("table", "/api/table", Object.assign(wallSpec(), {b0: state.b0, H}));
    if (data.stale) return;
    if (data.error) { showError(data, "billiard-error"); return; }
    clearError("billiard-error");
    drawTable(data);
  }, 150);
}

function drawTable(data) {
  state.table = data;
  const finite = (v) => v !== null;
  const lo = Math.min(...data.lower.filter(finite)), hi = Math.max(...data.upper.filter(finite));
  const pad = 0.05 * (hi - lo);
  TABLE = frame($("table-view"), $("table-axes"), {x: [0, TAU], y: [lo - pad, hi + pad], theta: true, xlabel: "θ",
    ylabel: "η = y / κ", zero: false});
  const line = (values) => values.map((v, i) => `${i ? "L" : "M"}${TABLE.x(data.theta[i]).toFixed(1)} ${ty(v).toFixed(1)}`).join("");
  const [left, right, top, bottom] = [TABLE.left, TABLE.left + TABLE.width, TABLE.top, TABLE.top + TABLE.height];
  $("table-lower").setAttribute("d", `${line(data.lower)}L${right} ${bottom}L${left} ${bottom}Z`);
  $("table-upper").setAttribute("d", `${line(data.upper)}L${right} ${top}L${left} ${top}Z`);
  drawSections();
  drawLab();
}

function drawLab() {
  if (!state.table) return;
  const H = state.table.H, reach = state.body ? state.body.extent : 1;
  const w = Math.max(H, 2.2 * reach);
  const f = frame($("lab-view"), $("lab-axes"), {x: [-w / 2, w / 2], y: [-0.08 * H, 1.08 * H], equal: true,
    ylabel: "y / κ", xlabel: "x / κ", zero: false});
  $("lab-world").setAttribute("transform", `translate(${f.x(0)} ${f.y(0)}) scale(${f.scale} ${-f.scale})`);
  for (const id of ["lab-floor", "lab-ceiling"]) {  // the walls span the frame
    $(id).setAttribute("x1", f.x0); $(id).setAttribute("x2", f.x1);
  }
  $("lab-ceiling").setAttribute("y1", H); $("lab-ceiling").setAttribute("y2", H);
  $("lab-com").setAttribute("r", 3 / f.scale);
  $("lab-body").querySelector(".arrow").setAttribute("x2", 0.5 * reach);
  if (state.body) $("lab-outline").setAttribute("d", state.body.path);
  if (!state.beam) $("lab-body").setAttribute("transform", `translate(0,${H / 2})`);
}

async function tableClicked(event) {
  if (!TABLE) return;
  const svg = $("table-view");
  const p = svg.createSVGPoint(); p.x = event.clientX; p.y = event.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  if (q.x < TABLE.left || q.x > TABLE.left + TABLE.width || q.y < TABLE.top || q.y > TABLE.top + TABLE.height) return;
  const theta = TABLE.x0 + (q.x - TABLE.left) / TABLE.width * (TABLE.x1 - TABLE.x0);
  const eta = TABLE.y1 - (q.y - TABLE.top) / TABLE.height * (TABLE.y1 - TABLE.y0);
  const deg = Math.PI / 180;
  const H = numberInput("H", "H", "billiard-error"), rays = numberInput("rays", "rays", "billiard-error");
  const direction = numberInput("direction", "direction", "billiard-error");
  const spread = numberInput("spread", "spread", "billiard-error");
  if ([H, rays, direction, spread].includes(undefined)) return;
  stopBeam();
  $("billiard-status").textContent = "computing the beam (the first beam of a new wall compiles the billiard kernel: ~10 s) …";
  const data = await call("beam", "/api/beam", Object.assign(wallSpec(), {b0: state.b0, H,
    theta, eta, rays, direction: direction * deg, spread: spread * deg, collisions: 40, section_collisions: 4000}));
  if (data.stale) return;
  if (data.error) { showError(data, "billiard-error"); $("billiard-status").textContent = ""; return; }
  clearError("billiard-error");
  $("billiard-status").textContent = `${data.rays.length} rays from θ = ${fmt(theta, 4)}, η = ${fmt(eta, 4)}` +
    (state.body && state.body.regime === "corner" ? " (below b_c no body has this wall: the body shown is the largest under it)" : "");
  state.sections.push(data.section);
  drawSections();
  startBeam(data);
}

function drawSections() {
  const f = frame($("section-view"), $("section-axes"), {x: [0, TAU], y: [-Math.PI / 2, Math.PI / 2], theta: true,
    xlabel: "θc", ylabel: "φc (rad)"});
  const box = $("section-points");
  box.replaceChildren();
  state.sections.forEach((section, k) => {
    let d = "";
    for (let i = 0; i < section.theta.length; i++) {
      d += `M${f.x(section.theta[i]).toFixed(1)} ${f.y(section.phi[i]).toFixed(1)}h0`;
    }
    svgEl("path", {d, class: `orbit c${k % 6}`}, box);
  });
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
    beam.trail.push([theta, eta]);
    let trail = "";
    const recent = beam.trail.slice(-400);
    recent.forEach(([t, e], i) => {  // a jump across θ = 2π starts a new piece
      const jump = i === 0 || Math.abs(wrap(t) - wrap(recent[i - 1][0])) > Math.PI;
      trail += `${jump ? "M" : "L"}${tx(t).toFixed(1)} ${ty(e).toFixed(1)}`;
    });
    $("beam-trails").setAttribute("d", trail);
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
  $("beam-centre").setAttribute("cx", -10); $("beam-centre").setAttribute("cy", -10);
}

function clearBilliard() {
  stopBeam();
  state.sections = [];
  $("section-points").replaceChildren();
  $("billiard-status").textContent = "Click the table to send a beam; each click adds its central orbit to the " +
    "Poincaré section, and the body beside it moves as that orbit says.";
}

// ---------------------------------------------------------------------------------------------- start
let resizeTimer = null;
function resized() {  // the plots are drawn in pixels: draw them again at the new size
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(() => {
    if (state.body) { drawBodyView(state.body); drawCurves(state.body); }
    if (state.table) drawTable(state.table); else drawSections();
  }, 100);
}

function start() {
  $("wall").addEventListener("input", wallTyped);
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
  window.addEventListener("resize", resized);
  drawSections();
  setParams([["eps", 1]]);  // the Appendix wall the page opens on (its case: appendix-convex)
  loadCases();
  loadWall(typedWall(), {b0: Number($("b0-number").value)}).then(() => { document.body.dataset.ready = "1"; });
}

document.addEventListener("DOMContentLoaded", start);
