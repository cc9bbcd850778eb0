#include "marsyn/core/report/report_html.hpp"

#include <fstream>
#include <stdexcept>

namespace marsyn {
namespace {

// The page. Data arrive as two JSON literals replacing the markers; everything else is static.
const char* const kPage = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>marsyn report</title>
<style>
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:0;background:#f6f7f9;color:#1d2330}
header{background:#1d2330;color:#fff;padding:14px 24px;display:flex;align-items:center;gap:16px}
header h1{font-size:20px;margin:0;font-weight:600}
.badge{padding:4px 12px;border-radius:12px;font-weight:700;font-size:14px}
.ok{background:#1f9d55}.bad{background:#cc1f1a}
main{padding:16px 24px;display:grid;grid-template-columns:minmax(420px,640px) 1fr;gap:20px}
section{background:#fff;border-radius:8px;box-shadow:0 1px 3px rgba(0,0,0,.12);padding:14px 16px}
h2{font-size:15px;margin:0 0 10px 0;color:#3d4852}
table{border-collapse:collapse;font-size:13px;width:100%}
th,td{border-bottom:1px solid #e2e8f0;padding:4px 8px;text-align:right}
th:first-child,td:first-child{text-align:left}
#att td:nth-child(3),#att td:nth-child(5),#rounds td:nth-child(2),#rounds td:nth-child(3),#rounds td:nth-child(4),#rounds td:nth-child(6){text-align:left;font-size:12px}
th{background:#f1f5f8;font-weight:600}
canvas{width:100%;border:1px solid #dae1e7;border-radius:4px;background:#fff}
.controls{display:flex;gap:8px;align-items:center;margin-top:8px;font-size:13px}
.controls input[type=range]{flex:1}
.wide{grid-column:1/3}
.legend span{display:inline-block;margin-right:14px;font-size:12px}
.legend i{display:inline-block;width:18px;height:3px;vertical-align:middle;margin-right:4px}
.muted{color:#8795a1;font-size:12px}
</style></head><body>
<header><h1 id="title"></h1><span id="badge" class="badge"></span><span id="sub"></span></header>
<main>
<section><h2>Workspace: agents, tubes, obstacles, goals</h2>
<canvas id="cv" width="640" height="640"></canvas>
<div id="side" style="display:none"><h2 style="margin-top:12px">Side view (x-z): heights of tubes, enclosures and obstacles</h2>
<canvas id="cv2" width="640" height="360"></canvas>
<h2 style="margin-top:12px">Front view (y-z)</h2>
<canvas id="cv3" width="640" height="360"></canvas></div>
<div class="controls"><button id="play">pause</button><input id="k" type="range" min="0" value="0">
<span id="kt"></span></div>
<div class="controls"><label>run <select id="run"></select></label></div>
<div class="muted">Filled boxes: each agent's eps-tube at the current sample (workspace projection, sound); outlined boxes: the certified enclosures of the closed loop between this sample and the next (continuous time); dots: the selected simulated run; thin lines: nominal plan; green dashed: goals; grey: obstacles (dotted: an obstacle of one stage while it binds nobody, labelled with the agents and steps it binds); dashed in an agent's colour: its mission stages, "order: name @visit step", filled while it is due inside.</div>
</section>
<section><h2>Per-stage figures (paper Table 2 row)</h2><table id="t2"></table>
<h2 style="margin-top:16px">Agents</h2><table id="ag"></table>
<h2 style="margin-top:16px">Guarantee and certificate</h2><table id="cert"></table>
<h2 style="margin-top:16px">Verification (closed-loop runs: evidence, not proof)</h2><table id="ver"></table>
<div id="missionbox" style="display:none"><h2 style="margin-top:16px">Mission: stages in order (docs/tasks.md)</h2><table id="mission"></table></div>
<h2 style="margin-top:16px">Open loop, per run (smallest margin and its step; below 0 = violation)</h2><table id="olr"></table></section>
<section class="wide"><h2>Distance to threshold over continuous time (smallest margin over obstacles, collisions and formation at every integration substep; below 0 = violation)</h2>
<div id="plot"></div><div class="legend" id="legend"></div></section>
<section class="wide"><h2>The outer search: its rounds (docs/search.md)</h2><p id="stop" class="muted"></p><table id="rounds"></table>
<h2 style="margin-top:16px">Attempts of the outer search</h2><table id="att"></table></section>
</main>
<script>
const R = /*RESULT*/;
const S = /*SCENE*/;
const $ = id => document.getElementById(id);
const fmt = (v, d = 3) => v === null || v === undefined ? '-' : (typeof v === 'number' ? (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(2) : v.toFixed(d)) : String(v));
$('title').textContent = 'marsyn: ' + (R.problem || '');
const verified = R.status === 'verified';
$('badge').textContent = verified ? 'VERIFIED' : R.status === 'stopped' ? 'STOPPED' : 'FAILED';
$('badge').className = 'badge ' + (verified ? 'ok' : 'bad');
const count = (n, w) => n + ' ' + w + (n === 1 ? '' : 's');
$('sub').textContent = count(R.agents ? R.agents.length : 0, 'agent') + ', total ' + fmt(R.total_time_s, 2) + ' s, guarantee: ' +
  (R.guarantee === 'sampled' ? 'sampled (t = k tau only)' : 'continuous (every t in [0, T tau])') +
  (verified || !R.failure ? '' : ' | ' + R.failure) +
  (R.partial ? ' | partial: the controllers found so far are in the folder (each sound for its own tube; the team is not verified)' : '');
const mark = (x, text) => x !== null && x !== undefined && x < 0 ? '<b style="color:#e3342f">' + text + '</b>' : text;
function table(el, head, rows) {
  el.innerHTML = '<tr>' + head.map(h => '<th>' + h + '</th>').join('') + '</tr>' +
    rows.map(r => '<tr>' + r.map(c => '<td>' + c + '</td>').join('') + '</tr>').join('');
}
const esc = x => String(x).replace(/[&<>"]/g, c => ({'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;'})[c]);
const ags = R.agents || [];
const maxBy = f => ags.reduce((m, a) => Math.max(m, f(a) || 0), 0);
const g = R.global_abcd || {};
table($('t2'), ['T_plan [s]', 'N_l', 'T_abs [s]', 'T_syn [s]', 'N_g', 'global ABCD'],
  [[fmt((R.plan || {}).time_s, 2), fmt(maxBy(a => a.tracker && a.tracker.state_input_pairs), 0),
    fmt(maxBy(a => a.tracker && a.tracker.abstraction_time_s), 2), fmt(maxBy(a => a.tracker && a.tracker.synthesis_time_s), 2),
    fmt(g.state_input_pairs, 0), g.status || '-']]);
// From which step the controller's acceptance means "safe from here" (its sets invariant).
const safeFrom = t => t.invariant_from === undefined ? '-' : t.invariant_from === 0 ? 'every step' :
  t.invariant_from <= ((R.plan || {}).horizon || Infinity) ? 'from step ' + t.invariant_from : 'no';
table($('ag'), ['agent', 'tracker', 'status', 'N_l', 'boxes', 'abs [s]', 'syn [s]', 'memory [MB]', 'start covered', 'safe from any accepted state'],
  ags.map(a => { const t = a.tracker || {}; return [a.name + (a.bodies ? '<br><span class="muted" style="white-space:nowrap">bodies ' + a.bodies.map(b => esc(b.name) + ' ' + String(+b.radius.toPrecision(3))).join(', ') + '</span>' : a.radius ? '<br><span class="muted" style="white-space:nowrap">body radius ' + String(+a.radius.toPrecision(3)) + '</span>' : '') + (a.x0_radius ? '<br><span class="muted" style="white-space:nowrap">x0 &plusmn; (' + a.x0_radius.map(r => String(+r.toPrecision(3))).join(', ') + ')</span>' : ''), esc(t.name || '-') + (t.chosen === 'auto' ? ' <span class="muted">(auto)</span>' : ''),
    t.status, fmt(t.state_input_pairs, 0), fmt(t.boxes_computed, 0),
    fmt(t.abstraction_time_s, 3), fmt(t.synthesis_time_s, 3), fmt((t.peak_memory_bytes || 0) / 1048576, 1), t.initial_state_winning ? 'yes' : 'no', safeFrom(t)]; }));
const v = R.verification || {}, ol = R.open_loop || {}, ce = R.certification || {}, pl = R.plan || {};
const cpart = p => p ? mark(p.margin, fmt(p.margin)) + ' <span class="muted">' + p.where + ', k=' + p.step + '</span>' : '-';
table($('cert'), ['', 'value'], [
  ['guarantee', R.guarantee === 'sampled' ? 'sampled: at t = k tau only (paper semantics)' : 'continuous: every t in [0, T tau]'],
  ['plan: robust margin at the samples / between them', fmt(pl.sampled_robust_margin) + ' / ' + fmt(pl.between_samples_robust_margin)],
  ['certificate on the period enclosures', ce.ran ? (ce.certified ? 'certified' : '<b style="color:#e3342f">not certified</b>') + ' (' + fmt(ce.period_enclosures, 0) + ' enclosures)' : (R.guarantee === 'sampled' ? 'not required' : 'did not run')],
  ['  state bounds', cpart(ce.state_bounds)], ['  obstacles', cpart(ce.obstacle)], ['  collisions', cpart(ce.collision)], ['  formation', cpart(ce.formation)]]);
const bs = v.between_samples || {};
table($('ver'), ['', 'runs', 'violations', 'margin at samples', 'margin between (dense)', 'runs/s'],
  [['feedback', fmt(v.runs, 0), fmt(v.violations, 0), fmt(v.sampled_min_margin), mark(bs.min_margin, fmt(bs.min_margin)), v.runs_time_s > 0 ? fmt(v.runs / v.runs_time_s, 0) : '-'], ['open loop', fmt(ol.runs, 0), fmt(ol.violations, 0), fmt(ol.min_margin), '-', '-']]);
const part = p => p ? fmt(p.margin) + ' (k=' + p.step + ')' : '-';
table($('olr'), ['disturbance', 'obstacle', 'collision', 'formation', 'goal'],
  (ol.by_run || []).map(r => [r.disturbance, ...['obstacle', 'collision', 'formation'].map(k =>
    mark(r[k] && r[k].margin, part(r[k]))), mark(r.goal_margin, fmt(r.goal_margin))]));
if (R.mission) {
  $('missionbox').style.display = '';
  const ms = R.mission.stages || [];
  table($('mission'), ['agent', '#', 'stage', 'visit k (t [s])', 'dwell', 'window', 'plan margin', 'certified margin'],
    ms.map(m => [esc(m.agent), m.order, esc(m.stage) + (m.team ? ' <span class="muted">team ' + esc(m.team) + '</span>' : '') +
      ((m.avoid || []).length ? ' <span class="muted">avoids ' + esc(m.avoid.join(', ')) + ' on the way</span>' : '') +
      ((m.avoid_after || []).length ? ' <span class="muted">avoids ' + esc(m.avoid_after.join(', ')) + ' after</span>' : ''),
      m.visit_step + ' (' + fmt(m.visit_time_s, 2) + ')', m.dwell, '[' + m.not_before + ', ' + (m.by === null ? 'T' : m.by) + ']',
      mark(m.plan_margin, fmt(m.plan_margin)), m.certified ? mark(m.certified.margin, fmt(m.certified.margin)) : '-']));
}
table($('att'), ['#', 'stage', 'parameters', 'T', 'outcome', 'time [s]'],
  (R.attempts || []).map((a, i) => [i + 1, esc(a.stage || ''), esc(a.parameters || ''), fmt(a.horizon, 0), esc(a.outcome || ''), fmt(a.time_s, 3)]));
const se = R.search || {};
$('stop').textContent = se.stop_message || '';
table($('rounds'), ['round', 'action', 'why', 'changes (from -> to)', 'T', 'outcome', 'plan [s]', 'track [s]', 'certify [s]', 'round [s]'],
  (se.rounds || []).map(r => [r.round, esc(r.action), esc(r.reason || '-'),
    esc((r.changes || []).map(c => (c.agent ? c.agent + ' ' : '') + c.what + ' ' + c.from + ' -> ' + c.to).join('; ') || '-') + (r.undone ? ' <span class="muted">(undone)</span>' : ''),
    fmt(r.horizon, 0) + (r.planned ? '' : ' (kept)'), esc(r.outcome), fmt(r.plan_time_s, 2), fmt(r.track_time_s, 2),
    fmt(r.certify_time_s, 2), fmt(r.time_s, 2)]));

// Workspace animation: one view per canvas (the top view; a 3-D workspace adds the side view x-z and the front view y-z).
const colors = ['#3490dc', '#e3342f', '#38c172', '#f6993f', '#9561e2', '#f66d9b', '#4dc0b5', '#6574cd', '#ffed4a', '#8795a1'];
function makeView(cv, S) {
const ctx = cv.getContext('2d');
let xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
const grow = (x, y) => { xmin = Math.min(xmin, x); xmax = Math.max(xmax, x); ymin = Math.min(ymin, y); ymax = Math.max(ymax, y); };
S.agents.forEach(a => { a.tube.forEach(b => { grow(b[0], b[1]); grow(b[2], b[3]); }); grow(a.goal[0], a.goal[1]); grow(a.goal[2], a.goal[3]); });
// Open-loop runs can drift metres away (no feedback): they do not set the frame.
(S.runs || []).filter(r => !r.label.startsWith('open loop')).forEach(r => r.points.forEach(tr => tr.forEach(p => grow(p[0], p[1]))));
S.obstacles.forEach(o => o.vertices.forEach(p => { if (p[0] > xmin - 3 && p[0] < xmax + 3 && p[1] > ymin - 3 && p[1] < ymax + 3) grow(p[0], p[1]); }));
if (xmin > xmax) { xmin = 0; xmax = 1; ymin = 0; ymax = 1; }
const pad = 0.05 * Math.max(xmax - xmin, ymax - ymin, 1e-3);
xmin -= pad; xmax += pad; ymin -= pad; ymax += pad;
// The frame takes the scene's proportions (a long, flat field fills the width instead of a
// strip of a square), between a quarter and one and a half of its width high.
cv.height = Math.round(Math.min(Math.max(cv.width * (ymax - ymin) / (xmax - xmin), 0.25 * cv.width), 1.5 * cv.width));
const scale = Math.min(cv.width / (xmax - xmin), cv.height / (ymax - ymin));
const X = x => (x - xmin) * scale, Y = y => cv.height - (y - ymin) * scale;
return function draw(k) {
  ctx.clearRect(0, 0, cv.width, cv.height);
  ctx.fillStyle = '#cbd2d9';
  S.obstacles.forEach(o => { ctx.beginPath(); o.vertices.forEach((p, i) => i ? ctx.lineTo(X(p[0]), Y(p[1])) : ctx.moveTo(X(p[0]), Y(p[1]))); ctx.closePath();
    if (!o.binds) { ctx.fill(); return; }
    // A staged obstacle (scope: stages): solid while it binds some agent, dashed and labelled with who and when otherwise.
    const now = o.binds.filter(b => k >= b.from && k <= b.to);
    if (now.length) { ctx.fill(); } else { ctx.save(); ctx.setLineDash([2, 3]); ctx.strokeStyle = '#7b8794'; ctx.stroke(); ctx.restore(); }
    const cx = o.vertices.reduce((s, p) => s + p[0], 0) / o.vertices.length, cy = o.vertices.reduce((s, p) => s + p[1], 0) / o.vertices.length;
    ctx.save(); ctx.fillStyle = '#52606d'; ctx.font = '10px system-ui';
    ctx.fillText(o.name + ': ' + (o.binds.map(b => b.agent + ' ' + b.from + '-' + b.to).join(', ') || 'binds nobody'), X(cx) - 20, Y(cy) + 3); ctx.restore(); ctx.fillStyle = '#cbd2d9'; });
  ctx.setLineDash([5, 4]); ctx.strokeStyle = '#1f9d55'; ctx.lineWidth = 1.5;
  S.agents.forEach(a => ctx.strokeRect(X(a.goal[0]), Y(a.goal[3]), (a.goal[2] - a.goal[0]) * scale, (a.goal[3] - a.goal[1]) * scale));
  // Mission stages: each region dashed in its agent's colour, numbered in visiting order, filled
  // while the agent is due inside it.
  S.agents.forEach((a, i) => (a.stages || []).forEach(st => {
    const c = colors[i % colors.length];
    ctx.setLineDash([3, 3]); ctx.strokeStyle = c; ctx.lineWidth = 1.5; ctx.beginPath();
    st.vertices.forEach((p, j) => j ? ctx.lineTo(X(p[0]), Y(p[1])) : ctx.moveTo(X(p[0]), Y(p[1]))); ctx.closePath(); ctx.stroke();
    if (k >= st.visit && k <= st.visit + st.dwell) { ctx.globalAlpha = 0.2; ctx.fillStyle = c; ctx.fill(); ctx.globalAlpha = 1; }
    const cx = st.vertices.reduce((s, p) => s + p[0], 0) / st.vertices.length, cy = st.vertices.reduce((s, p) => s + p[1], 0) / st.vertices.length;
    ctx.fillStyle = c; ctx.font = '11px system-ui'; ctx.fillText(st.order + ': ' + st.name + ' @' + st.visit, X(cx) - 12, Y(cy) + 4);
  }));
  ctx.setLineDash([]);
  S.agents.forEach((a, i) => {
    const c = colors[i % colors.length];
    ctx.strokeStyle = c; ctx.globalAlpha = 0.5; ctx.lineWidth = 1; ctx.beginPath();
    a.nominal.forEach((p, j) => j ? ctx.lineTo(X(p[0]), Y(p[1])) : ctx.moveTo(X(p[0]), Y(p[1]))); ctx.stroke();
    const b = a.tube[Math.min(k, a.tube.length - 1)];
    if (b) { ctx.globalAlpha = 0.25; ctx.fillStyle = c; ctx.fillRect(X(b[0]), Y(b[3]), (b[2] - b[0]) * scale, (b[3] - b[1]) * scale); }
    const pe = (a.enclosures || [])[k];
    if (pe) { ctx.globalAlpha = 0.7; ctx.strokeStyle = c; ctx.lineWidth = 1; pe.forEach(e => ctx.strokeRect(X(e[0]), Y(e[3]), (e[2] - e[0]) * scale, (e[3] - e[1]) * scale)); }
    ctx.globalAlpha = 1;
  });
  // A body with a radius is drawn at its point: a square in the inf-norm, a disc in the 2-norm.
  const body = (a, p, c) => { if (!a || !a.radius || !p) return; ctx.save(); ctx.strokeStyle = c; ctx.lineWidth = 1.5; ctx.beginPath();
    if (S.norm === '2') ctx.arc(X(p[0]), Y(p[1]), a.radius * scale, 0, 7); else ctx.rect(X(p[0] - a.radius), Y(p[1] + a.radius), 2 * a.radius * scale, 2 * a.radius * scale);
    ctx.stroke(); ctx.restore(); };
  const r = (S.runs || [])[+$('run').value];
  if (r) r.points.forEach((tr, i) => {
    const c = colors[i % colors.length];
    ctx.strokeStyle = c; ctx.lineWidth = 2; ctx.beginPath();
    tr.slice(0, k + 1).forEach((p, j) => j ? ctx.lineTo(X(p[0]), Y(p[1])) : ctx.moveTo(X(p[0]), Y(p[1]))); ctx.stroke();
    const p = tr[Math.min(k, tr.length - 1)];
    if (p) { ctx.fillStyle = c; ctx.beginPath(); ctx.arc(X(p[0]), Y(p[1]), 4, 0, 7); ctx.fill(); }
    body(S.agents[i], p, c);
  });
  else S.agents.forEach((a, i) => body(a, a.nominal[Math.min(k, a.nominal.length - 1)], colors[i % colors.length]));
  // Further bodies (a cart behind its tractor) along the nominal, dashed, with their radius.
  S.agents.forEach((a, i) => (a.bodies || []).forEach(b => { const c = colors[i % colors.length];
    ctx.save(); ctx.setLineDash([2, 2]); ctx.strokeStyle = c; ctx.globalAlpha = 0.5; ctx.beginPath();
    b.nominal.forEach((p, j) => j ? ctx.lineTo(X(p[0]), Y(p[1])) : ctx.moveTo(X(p[0]), Y(p[1]))); ctx.stroke(); ctx.restore();
    const p = b.nominal[Math.min(k, b.nominal.length - 1)];
    if (p) { ctx.fillStyle = c; ctx.beginPath(); ctx.arc(X(p[0]), Y(p[1]), 3, 0, 7); ctx.fill(); body(b, p, c); } }));
  $('kt').textContent = 'k = ' + k + ' (t = ' + (k * S.tau).toFixed(1) + ' s)';
  if (S.axes) { ctx.fillStyle = '#52606d'; ctx.font = '11px system-ui'; ctx.fillText(S.axes[0] + ' \u2192, ' + S.axes[1] + ' \u2191', 6, 14); }
};
}
const views = [makeView($('cv'), S)];
if (S.side) { $('side').style.display = ''; views.push(makeView($('cv2'), S.side)); }
if (S.front) views.push(makeView($('cv3'), S.front));
const draw = k => views.forEach(d => d(k));
const steps = S.agents.length ? S.agents[0].tube.length : 1;
$('k').max = Math.max(0, steps - 1);
(S.runs || []).forEach((r, i) => { const o = document.createElement('option'); o.value = i; o.textContent = r.label + (r.satisfied ? '' : '  [violates]'); $('run').appendChild(o); });
const fb = (S.runs || []).findIndex(r => r.label.startsWith('feedback, constant'));
if (fb >= 0) $('run').value = fb;

let k = 0, playing = true;
$('k').oninput = e => { k = +e.target.value; draw(k); };
$('run').onchange = () => draw(k);
$('play').onclick = () => { playing = !playing; $('play').textContent = playing ? 'pause' : 'play'; };
setInterval(() => { if (!playing) return; k = (k + 1) % steps; $('k').value = k; draw(k); }, 80);
draw(0);

// Margin plot (SVG).
(function plot() {
  if (!(S.runs || []).length) { $('plot').innerHTML = '<p class="muted">No closed-loop runs: verification runs only when every agent has a controller (see the attempts below).</p>'; return; }
  // Dense margins (every integration substep) where the run has them, else the samples.
  (S.runs || []).forEach(r => { if (r.dense && r.dense.length > r.margin.length) r.margin = r.dense; });
  const runs = (S.runs || []).filter(r => r.margin.length && r.margin.some(m => Math.abs(m) < 999));
  if (!runs.length) { $('plot').innerHTML = '<p class="muted">This problem has no obstacle, collision or formation constraints; only the goal is checked (see the verification table).</p>'; return; }
  const W = 1100, H = 300, L = 50, B = 30;
  let lo = 0, hi = 0, n = 0;
  runs.forEach(r => r.margin.forEach(m => { if (Math.abs(m) < 999) { lo = Math.min(lo, m); hi = Math.max(hi, m); } n = Math.max(n, r.margin.length); }));
  hi = hi + 0.05 * (hi - lo + 1e-9); lo = lo - 0.05 * (hi - lo + 1e-9);
  const px = i => L + (W - L - 10) * i / Math.max(1, n - 1), py = m => 10 + (H - B - 10) * (hi - m) / (hi - lo);
  const col = r => r.label.startsWith('open loop') ? (r.satisfied ? '#f6993f' : '#e3342f') : r.label.startsWith('nominal') ? '#8795a1' : '#3490dc';
  let s = '<svg viewBox="0 0 ' + W + ' ' + H + '" width="100%" xmlns="http://www.w3.org/2000/svg" font-size="11">';
  s += '<line x1="' + L + '" x2="' + (W - 10) + '" y1="' + py(0) + '" y2="' + py(0) + '" stroke="#cc1f1a" stroke-dasharray="6 4"/>';
  s += '<text x="' + (W - 12) + '" y="' + (py(0) - 4) + '" text-anchor="end" fill="#cc1f1a">threshold (delta / formation tolerance)</text>';
  for (let t = 0; t <= 4; t++) { const m = lo + (hi - lo) * t / 4; s += '<text x="' + (L - 6) + '" y="' + (py(m) + 4) + '" text-anchor="end">' + m.toFixed(2) + '</text>'; }
  const T = S.agents.length ? S.agents[0].tube.length - 1 : 1;
  for (let t = 0; t <= 5; t++) { const i = Math.round((n - 1) * t / 5); s += '<text x="' + px(i) + '" y="' + (H - 8) + '" text-anchor="middle">' + (i * T * S.tau / Math.max(1, n - 1)).toFixed(1) + ' s</text>'; }
  runs.forEach(r => { s += '<polyline fill="none" stroke-width="1.6" stroke="' + col(r) + '" points="' + r.margin.map((m, i) => px(i) + ',' + py(Math.max(lo, Math.min(hi, m)))).join(' ') + '"><title>' + r.label + '</title></polyline>'; });
  $('plot').innerHTML = s + '</svg>';
  $('legend').innerHTML = '<span><i style="background:#8795a1"></i>nominal plan</span><span><i style="background:#3490dc"></i>feedback under disturbance</span><span><i style="background:#e3342f"></i>open loop under disturbance (violating)</span><span><i style="background:#f6993f"></i>open loop under disturbance (satisfying)</span>';
})();
</script></body></html>
)HTML";

std::string replace_marker(std::string page, const std::string& marker, const std::string& value) {
  const auto pos = page.find(marker);
  if (pos != std::string::npos) page.replace(pos, marker.size(), value);
  return page;
}

// JSON inside a <script> element must not contain "</": escape the slash.
std::string script_safe(const nlohmann::json& j) {
  std::string s = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '<' && i + 1 < s.size() && s[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace

void write_report_html(const std::string& path, const nlohmann::json& result, const nlohmann::json& scene) {
  std::string page = replace_marker(kPage, "/*RESULT*/", script_safe(result));
  page = replace_marker(page, "/*SCENE*/", script_safe(scene));
  std::ofstream out(path);
  out << page;
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace marsyn
