// The cutdyn explorer's page: the case as inputs (one per case-file key, from /api/schema), the
// lobes redrawn as they change (/api/lobes), and a clicked point checked and simulated
// (/api/check, /api/simulate). Every number shown comes from the server, which runs the same
// jobs as the command line. Plain SVG, no libraries.
"use strict";

const PAGE = Math.random().toString(36).slice(2) + Date.now().toString(36);
const SVG = "http://www.w3.org/2000/svg";
const state = { schema: {}, case: null, lobes: null, point: null, requests: {} };
const $ = (id) => document.getElementById(id);

// ---- the API -----------------------------------------------------------------------------

// A request of `kind`; a newer one of the same kind aborts it here and (X-Cutdyn-Page) cancels
// its computation on the server. Resolves to null when aborted or cancelled.
async function api(kind, path, { body, query, text } = {}) {
  if (state.requests[kind]) state.requests[kind].abort();
  const controller = new AbortController();
  state.requests[kind] = controller;
  const url = path + (query ? "?" + new URLSearchParams(query) : "");
  const init = { headers: { "X-Cutdyn-Page": PAGE }, signal: controller.signal };
  if (body !== undefined) {
    init.method = "POST";
    init.headers["Content-Type"] = "application/json";
    init.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(url, init);
  } catch (e) {
    if (e.name === "AbortError") return null;
    throw e;
  } finally {
    if (state.requests[kind] === controller) delete state.requests[kind];
  }
  if (response.status === 409) return null;  // cancelled by a newer request
  const data = text && response.ok ? await response.text() : await response.json();
  if (!response.ok) throw new Error(data.error || response.statusText);
  return data;
}

function showError(message) {
  const box = $("error");
  box.textContent = message || "";
  box.hidden = !message;
}

// ---- the inputs ----------------------------------------------------------------------------

function schemaOf(table, key) {
  const section = state.schema[table === "" ? "(top level)" : table];
  return section && section.keys ? section.keys[key] : undefined;
}

function field(path, table, key, value) {
  const info = schemaOf(table, key) || {};
  const row = document.createElement("label");
  row.className = "field";
  const name = document.createElement("span");
  name.textContent = key + (info.unit && info.unit !== "–" ? ` (${info.unit})` : "");
  row.title = [info.label, info.rule].filter(Boolean).join(": ");
  let input;
  if (info.choices || typeof value === "boolean") {
    input = document.createElement("select");
    const choices = info.choices || ["true", "false"];
    for (const c of choices) input.add(new Option(c, c));
    input.value = String(value);
    input.dataset.type = typeof value === "boolean" ? "boolean" : "text";
  } else if (typeof value === "number") {
    input = document.createElement("input");
    input.type = "number";
    input.step = "any";
    input.value = String(value);
    input.dataset.type = "number";
  } else {
    input = document.createElement("input");
    input.type = "text";
    input.value = Array.isArray(value) ? value.join(", ") : String(value);
    input.dataset.type = Array.isArray(value) ? "numbers" : "text";
  }
  input.name = path;
  input.dataset.key = path;
  input.setAttribute("aria-label", path);
  row.append(name, input);
  return row;
}

function fieldset(legend, table, prefix, object) {
  const set = document.createElement("fieldset");
  const title = document.createElement("legend");
  title.textContent = legend;
  set.append(title);
  for (const [key, value] of Object.entries(object)) {
    if (value !== null && typeof value === "object" && !Array.isArray(value)) continue;
    if (table === "lobes" && key === "method") continue;  // the header's select
    set.append(field(prefix + key, table, key, value));
  }
  return set;
}

function buildForm(c) {
  const form = $("case-form");
  form.replaceChildren();
  const top = {};
  for (const [key, value] of Object.entries(c)) if (typeof value !== "object") top[key] = value;
  if (Object.keys(top).length) form.append(fieldset("case", "", "", top));
  const add = (table, value) => {
    if (Array.isArray(value)) {
      if (value.length && typeof value[0] === "object")
        value.forEach((item, i) => form.append(fieldset(`[[${table}]] ${i + 1}`, table,
                                                        `${table}[${i}].`, item)));
      return;
    }
    if (value === null || typeof value !== "object") return;
    form.append(fieldset(`[${table}]`, table, table + ".", value));
    for (const [key, sub] of Object.entries(value))
      if (sub !== null && typeof sub === "object" && !Array.isArray(sub)) add(`${table}.${key}`, sub);
  };
  for (const [table, value] of Object.entries(c)) add(table, value);
  const method = $("method");
  method.replaceChildren();
  const choices = (schemaOf("lobes", "method") || {}).choices || ["auto"];
  for (const m of choices) method.add(new Option(m, m));
  method.value = (c.lobes && c.lobes.method) || "auto";
  method.disabled = !c.lobes;
}

// "modes[0].natural_hz" → ["modes", 0, "natural_hz"].
function pathParts(path) {
  return path.split(".").flatMap((p) => {
    const m = p.match(/^(.*)\[(\d+)\]$/);
    return m ? [m[1], Number(m[2])] : [p];
  });
}

// The case the inputs hold, or null (inputs marked) when a number cannot be read.
function collectCase() {
  const c = structuredClone(state.case);
  let ok = true;
  for (const input of document.querySelectorAll("[data-key]")) {
    if (input.disabled) continue;
    const parts = pathParts(input.dataset.key);
    let value;
    input.classList.remove("bad");
    const type = input.dataset.type;
    if (type === "number") {
      value = input.value.trim() === "" ? null : Number(input.value);
      if (value !== null && !Number.isFinite(value)) { input.classList.add("bad"); ok = false; }
    } else if (type === "boolean") {
      value = input.value === "true";
    } else if (type === "numbers") {
      value = input.value.split(",").map((s) => Number(s.trim()));
      if (!value.every(Number.isFinite)) { input.classList.add("bad"); ok = false; }
    } else {
      value = input.value;
    }
    let target = c;
    for (const p of parts.slice(0, -1)) {
      if (target[p] === undefined) target[p] = {};
      target = target[p];
    }
    const last = parts[parts.length - 1];
    if (value === null) delete target[last]; else target[last] = value;
  }
  return ok ? c : null;
}

// ---- plots ---------------------------------------------------------------------------------

function el(name, attributes, parent) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes || {})) node.setAttribute(k, v);
  if (parent) parent.append(node);
  return node;
}

function niceTicks(lo, hi, count) {
  const span = hi - lo;
  if (!(span > 0)) return [lo];
  const step0 = span / count;
  const mag = Math.pow(10, Math.floor(Math.log10(step0)));
  const step = [1, 2, 2.5, 5, 10].map((f) => f * mag).find((s) => span / s <= count) || 10 * mag;
  const ticks = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step)
    ticks.push(Number(t.toPrecision(12)));
  return ticks;
}

// An empty plot with axes: returns {svg, x(v), y(v), invert(px, py), area}.
function axes(container, xRange, yRange, xLabel, yLabel) {
  const box = container.getBoundingClientRect();
  const W = Math.max(320, box.width || 640), H = Math.max(180, box.height || 300);
  const m = { left: 58, right: 14, top: 12, bottom: 40 };
  const svg = el("svg", { viewBox: `0 0 ${W} ${H}`, role: "img" });
  const [x0, x1] = xRange, [y0, y1] = yRange;
  const x = (v) => m.left + ((v - x0) / (x1 - x0 || 1)) * (W - m.left - m.right);
  const y = (v) => H - m.bottom - ((v - y0) / (y1 - y0 || 1)) * (H - m.top - m.bottom);
  const invert = (px, py) => [x0 + ((px - m.left) / (W - m.left - m.right)) * (x1 - x0),
                              y0 + ((H - m.bottom - py) / (H - m.top - m.bottom)) * (y1 - y0)];
  const grid = el("g", { class: "grid" }, svg);
  const axis = el("g", { class: "axis" }, svg);
  for (const t of niceTicks(x0, x1, 7)) {
    el("line", { x1: x(t), x2: x(t), y1: m.top, y2: H - m.bottom }, grid);
    el("text", { x: x(t), y: H - m.bottom + 14, "text-anchor": "middle" }, axis).textContent = t;
  }
  for (const t of niceTicks(y0, y1, 6)) {
    el("line", { x1: m.left, x2: W - m.right, y1: y(t), y2: y(t) }, grid);
    el("text", { x: m.left - 5, y: y(t) + 4, "text-anchor": "end" }, axis).textContent = t;
  }
  el("path", { d: `M${m.left},${m.top}V${H - m.bottom}H${W - m.right}`, fill: "none" }, axis);
  el("text", { x: (m.left + W - m.right) / 2, y: H - 6, "text-anchor": "middle" }, axis)
    .textContent = xLabel;
  el("text", { x: 12, y: (m.top + H - m.bottom) / 2, "text-anchor": "middle",
               transform: `rotate(-90 12 ${(m.top + H - m.bottom) / 2})` }, axis)
    .textContent = yLabel;
  container.replaceChildren(svg);
  return { svg, x, y, invert, area: { left: m.left, right: W - m.right, top: m.top,
                                      bottom: H - m.bottom } };
}

function polyline(points, attributes, parent) {
  return el("polyline", { points: points.map(([a, b]) => `${a},${b}`).join(" "), fill: "none",
                          ...attributes }, parent);
}

function drawLobes() {
  const l = state.lobes;
  if (!l) return;
  const pts = l.points;
  const rpm = pts.map((p) => p.spindle_rpm), depth = pts.map((p) => p.critical_depth_mm);
  const top = Math.min(Math.max(...depth), 6 * l.lowest.critical_depth_mm) * 1.15 ||
              Math.max(...depth) * 1.15;
  const plot = axes($("lobes-plot"), [Math.min(...rpm), Math.max(...rpm)], [0, top],
                    "spindle speed (rpm)", "critical depth (mm)");
  const { svg, x, y, area } = plot;
  // Unstable everywhere, stable under the boundary.
  el("rect", { x: area.left, y: area.top, width: area.right - area.left,
               height: area.bottom - area.top, fill: "var(--unstable)", class: "unstable" }, svg);
  // Everything drawn inside the axes: a boundary above the top leaves it.
  const clip = el("clipPath", { id: "lobes-clip" }, el("defs", {}, svg));
  el("rect", { x: area.left, y: area.top, width: area.right - area.left,
               height: area.bottom - area.top }, clip);
  const inside = el("g", { "clip-path": "url(#lobes-clip)" }, svg);
  const under = [[x(rpm[0]), y(0)], ...pts.map((p) => [x(p.spindle_rpm),
                 y(p.critical_depth_mm)]), [x(rpm[rpm.length - 1]), y(0)]];
  el("polygon", { points: under.map(([a, b]) => `${a},${b}`).join(" "), fill: "var(--stable)",
                  class: "stable" }, inside);
  // The boundary, Hopf (solid), flip (dashed) and fold (dotted) runs told apart.
  const styles = { flip: ["var(--flip)", "6 3"], fold: ["var(--fold)", "2 2"] };
  const style = (kind) => styles[kind] || ["var(--hopf)", "none"];
  let run = [];
  const flush = (kind) => {
    if (run.length > 1)
      polyline(run, { stroke: style(kind)[0], "stroke-width": 2,
                      "stroke-dasharray": style(kind)[1], class: `boundary ${kind}` }, inside);
  };
  let kind = pts[0].bifurcation;
  for (const p of pts) {
    const xy = [x(p.spindle_rpm), y(p.critical_depth_mm)];
    if (p.bifurcation !== kind) { run.push(xy); flush(kind); run = []; kind = p.bifurcation; }
    run.push(xy);
  }
  flush(kind);
  if (pts[0].conventional_depth_mm !== undefined)
    polyline(pts.map((p) => [x(p.spindle_rpm), y(p.conventional_depth_mm)]),
             { stroke: "#777", "stroke-width": 1.5, "stroke-dasharray": "2 3" }, inside);
  const legend = el("g", { class: "legend" }, svg);
  const item = (i, color, dash, text) => {
    const ly = area.top + 14 + 16 * i;
    el("line", { x1: area.right - 170, x2: area.right - 145, y1: ly, y2: ly, stroke: color,
                 "stroke-width": 2, "stroke-dasharray": dash }, legend);
    el("text", { x: area.right - 140, y: ly + 4 }, legend).textContent = text;
  };
  const items = [[...style("hopf"), "Hopf boundary"], [...style("flip"), "flip boundary"]];
  if (pts.some((p) => p.bifurcation === "fold")) items.push([...style("fold"), "fold boundary"]);
  if (pts[0].conventional_depth_mm !== undefined) items.push(["#777", "2 3", "conventional"]);
  items.forEach(([color, dash, text], i) => item(i, color, dash, text));
  if (state.point) {
    const [r, d] = state.point;
    el("circle", { cx: x(r), cy: y(Math.min(d, top)), r: 6, fill: "none", stroke: "#000",
                   "stroke-width": 2, class: "point" }, svg);
  }
  svg.addEventListener("mousemove", (e) => hover(e, plot));
  svg.addEventListener("mouseleave", () => { $("tooltip").hidden = true; });
  svg.addEventListener("click", (e) => {
    const [r, d] = toPlot(e, plot);
    if (r >= rpm[0] && r <= rpm[rpm.length - 1] && d > 0) checkPoint(r, d);
  });
  $("lobes-caption").textContent =
    `Stability lobes: ${state.name}, ${l.method}; lowest ${l.lowest.critical_depth_mm.toPrecision(4)} mm ` +
    `at ${Math.round(l.lowest.spindle_rpm)} rpm; ${pts.length} speeds in ${(1000 * l.seconds).toFixed(0)} ms. ` +
    "Green: stable; red: chatter. Click to check a point.";
}

function toPlot(e, plot) {
  const svg = plot.svg, pt = svg.createSVGPoint();
  pt.x = e.clientX;
  pt.y = e.clientY;
  const local = pt.matrixTransform(svg.getScreenCTM().inverse());
  return plot.invert(local.x, local.y);
}

function hover(e, plot) {
  const [r] = toPlot(e, plot);
  const pts = state.lobes.points;
  let best = pts[0];
  for (const p of pts) if (Math.abs(p.spindle_rpm - r) < Math.abs(best.spindle_rpm - r)) best = p;
  const tip = $("tooltip");
  tip.textContent = `${Math.round(best.spindle_rpm)} rpm: ${best.critical_depth_mm.toPrecision(4)} mm, ` +
    `chatter ${best.chatter_hz.toFixed(1)} Hz (${best.bifurcation}, lobe ${best.lobe})`;
  tip.style.left = `${e.clientX + 14}px`;
  tip.style.top = `${e.clientY + 10}px`;
  tip.hidden = false;
}

function drawSeries(container, xs, series, xLabel, yLabel) {
  const all = series.flatMap((s) => s.values);
  let lo = Math.min(...all), hi = Math.max(...all);
  if (!(hi > lo)) { hi = lo + 1; lo -= 1; }
  const { svg, x, y } = axes(container, [xs[0], xs[xs.length - 1]], [lo, hi], xLabel, yLabel);
  series.forEach((s, i) => polyline(xs.map((v, k) => [x(v), y(s.values[k])]),
                                    { stroke: s.color || ["var(--hopf)", "var(--flip)"][i],
                                      "stroke-width": 1.2, class: "series" }, svg));
  return { svg, x, y };
}

// ---- actions -------------------------------------------------------------------------------

let timer = null;
function schedule() {
  clearTimeout(timer);
  timer = setTimeout(refresh, 120);
}

// While the lobes are computed: the diagram dimmed at once, and after half a second a note
// with the seconds spent (a slow method or a large case takes tens of seconds).
let busyTimer = null, busyTicker = null;
function setBusy(on) {
  const note = $("busy");
  clearTimeout(busyTimer);
  clearInterval(busyTicker);
  $("lobes-plot").classList.toggle("busy", on);
  note.hidden = true;
  if (!on) return;
  const started = performance.now();
  const show = () => {
    note.hidden = false;
    note.textContent = `Computing the lobes… ${Math.round((performance.now() - started) / 1000)} s`;
  };
  busyTimer = setTimeout(() => {
    show();
    busyTicker = setInterval(show, 1000);
  }, 500);
}

let refreshes = 0;  // the number of the latest refresh: only it may end the busy state
async function refresh() {
  const c = collectCase();
  if (!c) return;
  const query = {};
  if (!$("method").disabled) query.method = $("method").value;
  const mine = ++refreshes;
  setBusy(true);
  try {
    const lobes = await api("lobes", "/api/lobes", { body: c, query });
    if (!lobes) return;
    state.lobes = lobes;
    showError("");
    drawLobes();
  } catch (e) {
    showError(e.message);
  } finally {
    if (mine === refreshes) setBusy(false);
  }
}

async function checkPoint(rpm, depth) {
  const c = collectCase();
  if (!c) return;
  state.point = [rpm, depth];
  drawLobes();
  const query = { rpm: rpm.toFixed(0), depth_mm: depth.toPrecision(4) };
  const verdict = $("verdict");
  verdict.textContent = `${query.rpm} rpm, ${query.depth_mm} mm: checking…`;
  try {
    const check = await api("check", "/api/check", { body: c, query });
    if (!check) return;
    const word = check.stable ? "stable" : "chatter";
    verdict.replaceChildren(`${query.rpm} rpm, ${query.depth_mm} mm: `);
    const strong = document.createElement("span");
    strong.className = word;
    strong.textContent = word;
    verdict.append(strong, ` (critical depth ${check.critical_depth_mm.toPrecision(4)} mm, ` +
      `margin ${(100 * check.margin).toFixed(0)} %, chatter at ${check.chatter_hz.toFixed(1)} Hz; ` +
      `${check.method}).`);
    const simulating = document.createTextNode(" Simulating…");
    verdict.append(simulating);
    const sim = await api("simulate", "/api/simulate", { body: c, query: { ...query, points: 1500 } });
    if (!sim) return;
    const t = sim.traces;
    const keys = t.x_um ? ["x_um", "y_um"] : ["displacement_um"];
    const rows = t.process ? t.time_s.map((_, i) => i).filter((i) => t.process[i] === t.process[0])
                           : t.time_s.map((_, i) => i);
    drawSeries($("trace-plot"), rows.map((i) => t.time_s[i]),
               keys.map((k) => ({ values: rows.map((i) => t[k][i]) })), "time (s)",
               keys.length > 1 ? "x, y (µm)" : "displacement (µm)");
    if (sim.spectrum) {
      // Up to three times the chatter frequency the check predicts (the rest is empty).
      const s = sim.spectrum;
      const top = check.chatter_hz > 0 ? 3 * check.chatter_hz : Infinity;
      const beyond = s.frequency_hz.findIndex((f) => f > top);
      const upto = (v) => (beyond < 0 ? v : v.slice(0, Math.max(8, beyond)));
      drawSeries($("spectrum-plot"), upto(s.frequency_hz),
                 keys.filter((k) => s[k]).map((k) => ({ values: upto(s[k]) })),
                 "frequency (Hz)", "amplitude (µm)");
    }
    const chattered = sim.summary ? sim.summary.chatter : sim.results && sim.results[0].chatter;
    simulating.textContent = ` Simulated: ${chattered ? "chatter" : "stable"}.`;
  } catch (e) {
    verdict.textContent = "";
    showError(e.message);
  }
}

function download(name, type, text) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

async function loadCase(query) {
  const doc = await api("case", "/api/case", { query });
  state.case = doc.case;
  state.name = doc.source;
  state.point = null;
  buildForm(doc.case);
  await refresh();
}

async function start() {
  try {
    state.schema = await api("schema", "/api/schema");
    const examples = await api("examples", "/api/examples");
    const select = $("example");
    select.add(new Option("(starting case)", ""));
    for (const name of examples.examples) select.add(new Option(name, name));
    select.addEventListener("change", () =>
      loadCase(select.value ? { example: select.value } : undefined).catch((e) => showError(e.message)));
    $("case-form").addEventListener("input", schedule);
    $("case-form").addEventListener("change", schedule);
    $("method").addEventListener("change", schedule);
    $("download-toml").addEventListener("click", async () => {
      const c = collectCase();
      if (!c) return;
      try {
        const doc = await api("toml", "/api/case", { body: c });
        if (doc) download("case.toml", "application/toml", doc.toml);
      } catch (e) { showError(e.message); }
    });
    $("download-csv").addEventListener("click", async () => {
      const c = collectCase();
      if (!c) return;
      try {
        const query = $("method").disabled ? { format: "csv" } : { format: "csv", method: $("method").value };
        const csv = await api("csv", "/api/lobes", { body: c, query, text: true });
        if (csv) download("lobes.csv", "text/csv", csv);
      } catch (e) { showError(e.message); }
    });
    window.addEventListener("resize", () => { clearTimeout(timer); timer = setTimeout(drawLobes, 150); });
    await loadCase();
  } catch (e) {
    showError(e.message);
  }
}

start();
