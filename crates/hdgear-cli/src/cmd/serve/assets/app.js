// hdgear explorer: sliders → /api/view → three SVG views and the verdict. Plain JS, no build
// step, no dependencies: everything is served by the hdgear binary itself.
"use strict";

// The sliders: the server writes them in place of the empty list, from the served model's
// parameter list (serve/mod.rs).
const PARAMS = /*PARAMS*/[];
const STEPS = 1000;
const state = {};
let view = null;
let latest = 0;
let controller = null;
let scheduled = false;

const $ = (id) => document.getElementById(id);
const fmt = (v, d = 4) => (v === null || v === undefined || Number.isNaN(v)) ? "–"
  : !Number.isFinite(v) ? (v > 0 ? "∞" : "−∞")
  : (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0)) ? v.toExponential(d - 1)
  : String(Number(v.toPrecision(d)));

function toPos(p, v) {
  const f = p.log ? (Math.log10(v) - Math.log10(p.min)) / (Math.log10(p.max) - Math.log10(p.min))
    : (v - p.min) / (p.max - p.min);
  return Math.round(Math.min(1, Math.max(0, f)) * STEPS);
}
function fromPos(p, pos) {
  const f = pos / STEPS;
  const v = p.log ? Math.pow(10, Math.log10(p.min) + f * (Math.log10(p.max) - Math.log10(p.min)))
    : p.min + f * (p.max - p.min);
  return Number(v.toPrecision(4));
}

function buildSliders() {
  const box = $("sliders");
  for (const p of PARAMS) {
    const row = document.createElement("div");
    row.className = "slider";
    row.innerHTML = `<label for="s-${p.key}" title="${p.hint}">${p.sym}</label>` +
      `<input type="range" id="s-${p.key}" min="0" max="${STEPS}" step="1" aria-label="${p.key}">` +
      `<input type="number" id="n-${p.key}" step="any" aria-label="${p.key} value">` +
      `<div class="hint">${p.hint}${p.log ? " (log scale)" : ""}</div>`;
    box.appendChild(row);
    $(`s-${p.key}`).addEventListener("input", (e) => set(p.key, fromPos(p, Number(e.target.value)), "slider"));
    $(`n-${p.key}`).addEventListener("change", (e) => {
      const v = Number(e.target.value);
      if (e.target.value.trim() !== "" && Number.isFinite(v)) set(p.key, v, "number");
    });
  }
}

function set(key, value, from) {
  state[key] = value;
  const p = PARAMS.find((q) => q.key === key);
  // a value beyond the slider (a physical drive's μ, say) widens it, so the slider stays usable
  if (Number.isFinite(value) && (!p.log || value > 0)) {
    if (value > p.max) p.max = p.log ? value * 3 : value + 0.25 * (value - p.min);
    if (value < p.min) p.min = p.log ? value / 3 : value - 0.25 * (p.max - value);
  }
  if (from !== "slider") $(`s-${key}`).value = toPos(p, value);
  if (from !== "number") $(`n-${key}`).value = Number(value.toPrecision(7));
  for (const b of document.querySelectorAll("[data-gamma]")) b.classList.toggle("on", Number(b.dataset.gamma) === state.gamma);
  schedule();
}

function query() {
  return PARAMS.map((p) => `${p.key}=${encodeURIComponent(state[p.key])}`).join("&");
}

// Slider storms: one request per animation frame at most; a new request aborts the one in
// flight, and a response older than the newest request is ignored.
function schedule() {
  history.replaceState(null, "", "?" + query());
  document.body.classList.add("stale");
  if (scheduled) return;
  scheduled = true;
  requestAnimationFrame(() => { scheduled = false; request(); });
}

async function request() {
  const seq = ++latest;
  if (controller) controller.abort();
  controller = new AbortController();
  const t0 = performance.now();
  try {
    const r = await fetch("/api/view?" + query(), { signal: controller.signal });
    const body = await r.json();
    if (seq !== latest) return;
    document.body.classList.remove("stale");
    if (!r.ok) { showError(body.error || r.statusText); return; }
    view = body;
    render();
    $("status").textContent = `computed in ${Math.round(performance.now() - t0)} ms`;
  } catch (e) {
    if (e.name !== "AbortError" && seq === latest) showError(String(e));
  }
}

function showError(msg) {
  document.body.classList.remove("stale");
  $("verdict").innerHTML = `<div class="err">${esc(msg)}</div>`;
  $("status").textContent = "";
}

const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]));

// ---- plotting -------------------------------------------------------------------------------

function ticks(min, max, log) {
  if (log) {
    const out = [];
    for (let e = Math.ceil(Math.log10(min)); e <= Math.floor(Math.log10(max)); e++) out.push(Math.pow(10, e));
    return out;
  }
  const span = max - min || 1;
  const step = Math.pow(10, Math.floor(Math.log10(span / 5)));
  const nice = [1, 2, 5, 10].map((m) => m * step).find((s) => span / s <= 7);
  const out = [];
  for (let v = Math.ceil(min / nice) * nice; v <= max + 1e-12 * span; v += nice) out.push(Math.abs(v) < 1e-12 * span ? 0 : v);
  return out;
}

function frame(svg, xr, yr) {
  const W = svg.clientWidth || 600, H = svg.clientHeight || 260;
  const m = { l: 54, r: 12, t: 10, b: 34 };
  const map = (r, a, b) => r.log
    ? (v) => a + (Math.log10(v) - Math.log10(r.min)) / (Math.log10(r.max) - Math.log10(r.min)) * (b - a)
    : (v) => a + (v - r.min) / ((r.max - r.min) || 1) * (b - a);
  const sx = map(xr, m.l, W - m.r), sy = map(yr, H - m.b, m.t);
  svg.setAttribute("viewBox", `0 0 ${W} ${H}`);
  let s = `<g class="grid">`;
  for (const t of ticks(yr.min, yr.max, yr.log)) s += `<line x1="${m.l}" x2="${W - m.r}" y1="${sy(t)}" y2="${sy(t)}"/>`;
  s += `</g><g class="axis"><path d="M${m.l},${m.t}V${H - m.b}H${W - m.r}" fill="none"/>`;
  for (const t of ticks(xr.min, xr.max, xr.log)) s += `<line x1="${sx(t)}" x2="${sx(t)}" y1="${H - m.b}" y2="${H - m.b + 4}"/><text x="${sx(t)}" y="${H - m.b + 15}" text-anchor="middle">${fmt(t, 3)}</text>`;
  for (const t of ticks(yr.min, yr.max, yr.log)) s += `<text x="${m.l - 5}" y="${sy(t) + 4}" text-anchor="end">${fmt(t, 3)}</text>`;
  s += `</g><text class="label" x="${(m.l + W - m.r) / 2}" y="${H - 3}" text-anchor="middle">${xr.label}</text>`;
  s += `<text class="label" transform="translate(12,${(m.t + H - m.b) / 2}) rotate(-90)" text-anchor="middle">${yr.label}</text>`;
  return { W, H, m, sx, sy, s };
}

function path(f, xs, ys, keep = () => true) {
  let d = "", pen = false;
  for (let i = 0; i < xs.length; i++) {
    const ok = Number.isFinite(xs[i]) && Number.isFinite(ys[i]) && keep(i);
    if (!ok) { pen = false; continue; }
    d += (pen ? "L" : "M") + f.sx(xs[i]).toFixed(1) + "," + f.sy(ys[i]).toFixed(1);
    pen = true;
  }
  return d;
}

function bands(f, areas, yr, fill) {
  return areas.map((a) => `<rect x="${f.sx(Math.max(a.a_min, -1))}" y="${f.sy(yr.max)}" width="${Math.max(1, f.sx(Math.min(a.a_max, 1)) - f.sx(Math.max(a.a_min, -1)))}" height="${f.sy(yr.min) - f.sy(yr.max)}" fill="${fill}"/>`).join("");
}

function range(vals, pad = 0.05) {
  const v = vals.filter(Number.isFinite);
  let lo = Math.min(...v), hi = Math.max(...v);
  if (!(hi > lo)) { lo -= 1; hi += 1; }
  const d = (hi - lo) * pad;
  return { min: lo - d, max: hi + d };
}

function drawTrace() {
  const svg = $("trace"), tr = view.trace;
  const xr = { min: tr.t[0], max: tr.t[tr.t.length - 1], log: false, label: "τ (one slow period after the transient)" };
  const yr = { ...range(tr.xdot), log: false, label: "x'" };
  const f = frame(svg, xr, yr);
  let s = f.s;
  for (const b of view.response.bursts) {
    if (b.end < xr.min || b.onset > xr.max) continue;
    const x0 = f.sx(Math.max(b.onset, xr.min)), x1 = f.sx(Math.min(b.end, xr.max));
    s += `<rect x="${x0}" y="${f.m.t}" width="${Math.max(2, x1 - x0)}" height="${f.H - f.m.t - f.m.b}" fill="var(--burst)"><title>burst: τ ${fmt(b.onset)}–${fmt(b.end)}, ${b.spikes} spikes</title></rect>`;
  }
  s += `<path id="trace-path" d="${path(f, tr.t, tr.xdot)}" fill="none" stroke="#1b1f24" stroke-width="1"/>`;
  svg.innerHTML = s;
  svg._hover = { f, xs: tr.t, text: (i) => `τ = ${fmt(tr.t[i], 6)}\na = ${fmt(tr.a[i])}\nx = ${fmt(tr.x[i])}\nx' = ${fmt(tr.xdot[i])}`, y: (i) => tr.xdot[i] };
}

// The steep part of the curve: the spiking areas and the steepest point, widened 4×.
function steepWindow(eq) {
  const pts = eq.spiking_areas.flatMap((s) => [s.a_min, s.a_max]).concat(eq.folds.map((f) => f.a));
  if (Number.isFinite(eq.max_slope.a)) pts.push(eq.max_slope.a);
  if (!pts.length) return { min: -1, max: 1 };
  const lo = Math.min(...pts), hi = Math.max(...pts), mid = (lo + hi) / 2;
  const half = Math.max(0.02, 2 * (hi - lo));
  return { min: Math.max(-1, mid - half), max: Math.min(1, mid + half) };
}

// The equilibria's facts the views mark: the study's closed forms, or for a model with terms
// (its view has `model`) the folds of its own curve and the steepest point read off the curve.
function equilibria(v) {
  if (!v.model) return v.analysis.equilibria;
  const c = v.curve;
  let k = 0;
  for (let i = 1; i < c.slope.length; i++) if (Math.abs(c.slope[i]) > Math.abs(c.slope[k])) k = i;
  const folds = v.analysis.folds;
  return {
    folds, spiking_areas: [],
    max_slope: folds.length ? { a: NaN, value: Infinity } : { a: c.a[k], value: Math.abs(c.slope[k]) },
  };
}

function drawPhase() {
  const svg = $("phase"), c = view.curve, tr = view.trace, eq = equilibria(view);
  const w = state.zoom ? steepWindow(eq) : { min: -1, max: 1 };
  const xr = { ...w, log: false, label: state.zoom ? "a = sin ωτ (the steep part)" : "a = sin ωτ" };
  const inside = (xs, ys) => ys.filter((_, i) => xs[i] >= w.min && xs[i] <= w.max);
  const yr = { ...range(inside(c.a, c.x).concat(inside(tr.a, tr.x))), log: false, label: "x" };
  const f = frame(svg, xr, yr);
  let s = f.s + `<clipPath id="clip-phase"><rect x="${f.m.l}" y="${f.m.t}" width="${f.W - f.m.l - f.m.r}" height="${f.H - f.m.t - f.m.b}"/></clipPath><g clip-path="url(#clip-phase)">`;
  s += bands(f, eq.spiking_areas, yr, "var(--spike)");
  s += `<path d="${path(f, tr.a, tr.x)}" fill="none" stroke="var(--accent)" stroke-width="1" opacity="0.75"/>`;
  s += `<path id="curve-stable" d="${path(f, c.a, c.x, (i) => c.stable[i])}" fill="none" stroke="var(--stable)" stroke-width="2"/>`;
  s += `<path d="${path(f, c.a, c.x, (i) => !c.stable[i])}" fill="none" stroke="var(--stable)" stroke-width="1.5" stroke-dasharray="5 4"/>`;
  for (const fo of eq.folds) s += `<circle cx="${f.sx(fo.a)}" cy="${f.sy(fo.x)}" r="4" fill="#fff" stroke="var(--accent)" stroke-width="2"><title>fold a = ${fmt(fo.a)}, x = ${fmt(fo.x)}</title></circle>`;
  svg.innerHTML = s + "</g>";
  svg._hover = { f, xs: c.a, text: (i) => `a = ${fmt(c.a[i])}\nx* = ${fmt(c.x[i])}\ndx/da = ${fmt(c.slope[i])}\n${c.stable[i] ? "stable" : "unstable"} (${c.branch[i]})`, y: (i) => c.x[i] };
}

function drawSlope() {
  const svg = $("slope"), c = view.curve, eq = equilibria(view);
  const abs = c.slope.map(Math.abs);
  const fin = abs.filter((v) => Number.isFinite(v) && v > 0);
  const lo = Math.min(...fin), hi = Math.max(...fin);
  const yr = { min: Math.pow(10, Math.floor(Math.log10(lo))), max: Math.pow(10, Math.ceil(Math.log10(hi * 1.01))), log: true, label: "|dx/da|" };
  const xr = { min: -1, max: 1, log: false, label: "a" };
  const f = frame(svg, xr, yr);
  let s = f.s + bands(f, eq.spiking_areas, yr, "var(--spike)");
  s += `<path id="slope-path" d="${path(f, c.a, abs, (i) => abs[i] > 0)}" fill="none" stroke="var(--stable)" stroke-width="1.6"/>`;
  const sp = eq.max_slope;
  if (Number.isFinite(sp.value)) s += `<circle cx="${f.sx(sp.a)}" cy="${f.sy(sp.value)}" r="3.5" fill="var(--accent)"><title>steepest: ${fmt(sp.value)} at a = ${fmt(sp.a)}</title></circle>`;
  svg.innerHTML = s;
  svg._hover = { f, xs: c.a, text: (i) => `a = ${fmt(c.a[i])}\n|dx/da| = ${fmt(abs[i])}`, y: (i) => abs[i] };
}

function drawVerdict() {
  const v = view, c = v.classification, r = v.response, an = v.analysis, eq = equilibria(v), sg = r.signatures;
  const yes = c.bursting;
  const sig = ["jump", "overshoot", "ringing"].filter((k) => sg[k]).join(", ") || "none";
  const items = [
    ["mode", c.mode], ["mechanism", c.mechanism], ["signatures", sig],
    ["bursts per period", fmt(r.bursts_per_period)], ["spikes per burst", fmt(r.spikes_per_burst)],
    ["peak |x'|", fmt(r.peak_abs_xdot)], ["quiescent fraction", fmt(r.quiescent_fraction, 3)],
  ];
  if (v.model) items.push(
    ["curve", `${an.min_count === an.max_count ? an.min_count : `${an.min_count}–${an.max_count}`} equilibria, ${an.folds.length} folds, max |dx/da| ${fmt(eq.max_slope.value)}`],
    ["damping at rest", fmt(an.damping_at_rest)],
    ["predicted and simulated boundaries", "the study's closed forms: not for a model with terms (hdgear boundary --config FILE traces them)"],
  );
  else items.push(
    ["curve", `${an.regime}, max |dx/da| ${fmt(eq.max_slope.value)}`],
    ["predicted boundary in γ", eq.predicted_gamma_boundary === null ? "none" : fmt(eq.predicted_gamma_boundary)],
    ["predicted boundary in ω", fmt(eq.prediction.omega_boundary)],
    ["simulated boundaries", `<span id="simulated">–</span> <button type="button" id="simulate-b" title="where the simulated verdict switches, from the prediction (under a second to a few seconds)">locate</button>`],
  );
  let s = `<div class="big ${yes ? "yes" : "no"}" id="verdict-word">${yes ? "bursting" : "not bursting"}</div>`;
  s += `<div class="small">verdict: ${esc(c.verdict)}${r.continuous_fast_motion ? " — the fast motion never settles" : ""}</div>`;
  s += `<dl>${items.map(([k, val]) => `<div><dt>${k}</dt><dd>${val.startsWith("<") ? val : esc(val)}</dd></div>`).join("")}</dl>`;
  for (const w of v.warnings) s += `<div class="warn">${esc(w)}</div>`;
  if (!c.fast_slow_domain) s += `<div class="warn">ω is not slow against the fast subsystem here: the fast-slow picture does not apply (mode not-fast-slow)</div>`;
  $("verdict").innerHTML = s;
  $("simulate-b")?.addEventListener("click", locate);
}

async function locate() {
  const out = $("simulated");
  out.textContent = "searching…";
  const q = query();
  const r = await fetch("/api/boundaries?" + q);
  const b = await r.json();
  if (q !== query()) return;
  out.textContent = r.ok ? `γ ${b.simulated_gamma === null ? "none" : fmt(b.simulated_gamma)}, ω ${b.simulated_omega === null ? "none" : fmt(b.simulated_omega)}` : b.error;
}

function render() {
  if (!view) return;
  if (view.model) $("equation").textContent = view.model.equation;
  drawVerdict();
  drawTrace();
  drawPhase();
  drawSlope();
}

// ---- hover ----------------------------------------------------------------------------------

function nearest(xs, x) {
  let lo = 0, hi = xs.length - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (xs[mid] < x) lo = mid; else hi = mid; }
  return Math.abs(xs[lo] - x) <= Math.abs(xs[hi] - x) ? lo : hi;
}

function hover(svg) {
  const tip = $("tip");
  svg.addEventListener("mousemove", (e) => {
    const h = svg._hover;
    if (!h) return;
    const box = svg.getBoundingClientRect();
    const px = (e.clientX - box.left) * (h.f.W / box.width);
    const lo = h.xs[0], hi = h.xs[h.xs.length - 1];
    const x = lo + (px - h.f.sx(lo)) / ((h.f.sx(hi) - h.f.sx(lo)) || 1) * (hi - lo);
    const i = nearest(h.xs, x);
    let dot = svg.querySelector(".hover-dot");
    if (!dot) { svg.insertAdjacentHTML("beforeend", `<circle class="hover-dot" r="4" fill="none" stroke="#000"/>`); dot = svg.querySelector(".hover-dot"); }
    const cy = h.f.sy(h.y(i));
    if (Number.isFinite(cy)) { dot.setAttribute("cx", h.f.sx(h.xs[i])); dot.setAttribute("cy", cy); }
    tip.textContent = h.text(i);
    tip.hidden = false;
    tip.style.left = Math.min(e.clientX + 14, window.innerWidth - 180) + "px";
    tip.style.top = (e.clientY + 12) + "px";
  });
  svg.addEventListener("mouseleave", () => { $("tip").hidden = true; svg.querySelector(".hover-dot")?.remove(); });
}

// ---- downloads, permalink, physical drive ----------------------------------------------------

function download(name, type, text) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
const stem = () => `hdgear-${PARAMS.map((p) => p.key + state[p.key]).join("_")}`;
function columns(obj, keys) {
  const n = obj[keys[0]].length;
  const rows = [keys.join(",")];
  for (let i = 0; i < n; i++) rows.push(keys.map((k) => obj[k][i]).join(","));
  return rows.join("\n") + "\n";
}

async function loadDrives() {
  const r = await fetch("/api/drives");
  const d = await r.json();
  $("drive").innerHTML = d.drives.map((n) => `<option${n === "CSF-20-50" ? " selected" : ""}>${n}</option>`).join("");
  $("drive-info").title = d.assumptions.join("\n");
}

async function useDrive() {
  const r = await fetch("/api/drive?name=" + encodeURIComponent($("drive").value));
  const d = await r.json();
  if (!r.ok) { showError(d.error); return; }
  const p = d.reduction.params;
  $("drive-info").innerHTML = `${esc(d.name)}: α = ${fmt(p.alpha)}, γ = ${fmt(p.gamma)}, ε = ${fmt(p.eps)}, μ = ${fmt(p.mu)}, δ = ${fmt(p.delta)}, ω = ${fmt(p.omega)} (α·ε = ${fmt(d.alpha_eps)}); τ = t / ${fmt(d.reduction.time_scale)} s, x = θ / ${fmt(d.reduction.length_scale)} rad. Stiffness from the catalogue; inertias, damping and loads assumed (hover for the assumptions).`;
  // the drive gives the study's six; a model's own parameters keep their values
  for (const q of PARAMS) if (q.key in p) set(q.key, p[q.key], "drive");
}

async function loadLaws() {
  const r = await fetch("/api/laws");
  const d = await r.json();
  $("law").innerHTML = d.laws.map((n) => `<option${n === d.default[0] ? " selected" : ""}>${n}</option>`).join("");
  const showOptions = () => { for (const l of document.querySelectorAll("#control .opt")) l.hidden = l.dataset.law !== $("law").value; };
  $("law").addEventListener("change", showOptions);
  showOptions();
}

// One assessment as table rows: the closed loop against the open one, in the measures of
// `hdgear control`.
function assessmentRows(a) {
  const word = a.unstable ? "unstable" : a.verdict;
  const cls = a.unstable || a.verdict !== "no-bursts" ? "yes" : "no";
  return [
    ["gain", fmt(a.gain)],
    ["verdict (open loop)", `<span class="${cls}">${esc(word)}</span> (${esc(a.open_verdict)})`],
    ["peak |x'| closed / open", fmt(a.peak_xdot / a.open_peak_xdot, 3)],
    ["fast energy", `${fmt(a.fast_energy_db, 3)} dB`],
    ["effort peak / rms", `${fmt(a.effort_peak)} / ${fmt(a.effort_rms)}`],
    ["shift of x at a = ±1 (÷ X)", fmt(a.static_shift)],
    ["largest shift of x (÷ X)", fmt(a.max_shift)],
  ];
}

async function runControl() {
  const out = $("control-out");
  const law = $("law").value;
  const extra = new URLSearchParams({ law });
  for (const id of ["gain", "ww", "wd", "taud"]) {
    const v = $(id).value.trim();
    if (v !== "" && (id === "gain" || $(id).closest(".opt")?.dataset.law === law)) extra.set(id, v);
  }
  out.textContent = extra.has("gain") ? "assessing…" : "tuning the least gain…";
  const q = query();
  const r = await fetch(`/api/control?${q}&${extra}`);
  const d = await r.json();
  if (q !== query()) return;
  if (!r.ok) { out.textContent = d.error; return; }
  let rows;
  if (d.assessments?.length) rows = assessmentRows(d.assessments[0]);
  else {
    const t = d.tunings[0];
    rows = [["least gain that removes the bursts", `${fmt(t.tuned.gain)} (below: ${fmt(t.below.gain)}, ${esc(t.below.unstable ? "unstable" : t.below.verdict)})`], ...assessmentRows(t.tuned).slice(1)];
  }
  out.innerHTML = `<table>${rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join("")}</table>`;
}

function init() {
  buildSliders();
  const url = new URLSearchParams(location.search);
  for (const p of PARAMS) {
    const v = Number(url.get(p.key));
    set(p.key, url.has(p.key) && Number.isFinite(v) ? v : p.def, "init");
  }
  for (const b of document.querySelectorAll("[data-gamma]")) b.addEventListener("click", () => set("gamma", Number(b.dataset.gamma), "button"));
  $("reset").addEventListener("click", () => PARAMS.forEach((p) => set(p.key, p.def, "button")));
  $("permalink").addEventListener("click", async () => {
    try { await navigator.clipboard.writeText(location.href); $("status").textContent = "link copied"; }
    catch { $("status").textContent = location.href; }
  });
  $("dl-json").addEventListener("click", () => view && download(stem() + ".json", "application/json", JSON.stringify(view)));
  $("dl-csv").addEventListener("click", () => view && download(stem() + "-trajectory.csv", "text/csv", columns(view.trace, ["t", "a", "x", "xdot"])));
  $("dl-curve").addEventListener("click", () => view && download(stem() + "-curve.csv", "text/csv", columns(view.curve, ["a", "x", "slope", "stable", "branch"])));
  for (const b of document.querySelectorAll(".svg-dl")) b.addEventListener("click", () => {
    const svg = $(b.dataset.view);
    const css = `<style>${[...document.styleSheets].flatMap((s) => [...s.cssRules].map((r) => r.cssText)).filter((t) => /^(:root|\.axis|\.grid|\.label)/.test(t)).join("\n")}</style>`;
    download(`${stem()}-${b.dataset.view}.svg`, "image/svg+xml", `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${svg.clientWidth} ${svg.clientHeight}" width="${svg.clientWidth}" height="${svg.clientHeight}" font-family="sans-serif">${css}${svg.innerHTML}</svg>`);
  });
  $("use-drive").addEventListener("click", useDrive);
  $("zoom").addEventListener("click", () => { state.zoom = !state.zoom; $("zoom").classList.toggle("on", state.zoom); render(); });
  for (const id of ["trace", "phase", "slope"]) hover($(id));
  let resize = null;
  window.addEventListener("resize", () => { clearTimeout(resize); resize = setTimeout(render, 100); });
  loadDrives().catch((e) => showError(String(e)));
  loadLaws().catch((e) => showError(String(e)));
  $("run-control").addEventListener("click", () => runControl().catch((e) => { $("control-out").textContent = String(e); }));
}

init();
