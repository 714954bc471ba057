// The HTML report's style sheet and script, kept apart from the C++ that writes the page. They
// are inlined into every page (nothing is fetched from the network), so they are strings.
#include "report/html_assets.hpp"

namespace carve::html {

const char* const kCss = R"CSS(
:root{--bg:#f3f4f6;--card:#fff;--ink:#1d2433;--muted:#6b7280;--line:#e5e7eb;--accent:#1c7ed6}
*{box-sizing:border-box}
body{margin:0;background:var(--bg);color:var(--ink);font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif}
header.top{display:flex;align-items:center;gap:18px;padding:14px 28px;background:#111827;color:#f9fafb}
.brand{font-weight:800;font-size:20px;letter-spacing:.04em;padding:5px 12px;border-radius:8px;background:linear-gradient(135deg,#1c7ed6,#7048e8)}
header h1{margin:0;font-size:19px;font-weight:650}
header .sub{color:#9ca3af;font-size:13px}
main{max-width:1400px;margin:0 auto;padding:16px 22px 36px}
.cards{display:grid;grid-template-columns:repeat(5,minmax(0,1fr));gap:12px}
.card,.panel{background:var(--card);border-radius:12px;box-shadow:0 1px 2px rgba(16,24,40,.05),0 1px 4px rgba(16,24,40,.08)}
.card{padding:12px 16px 14px}
.label{font-size:11.5px;text-transform:uppercase;letter-spacing:.07em;color:var(--muted);font-weight:650}
.big{font-size:29px;font-weight:720;margin:2px 0 2px;font-variant-numeric:tabular-nums;white-space:nowrap}
.unit{font-size:15px;font-weight:600;color:var(--muted);margin-left:2px}
.small{font-size:12.5px;color:var(--muted)}
.card.good .big{color:#087f5b}
.bars{margin:6px 0 4px}
.bar{display:flex;align-items:center;gap:6px;font-size:11.5px;color:var(--muted);margin:2px 0}
.bar b{display:block;height:9px;border-radius:5px;min-width:2px}
.bar span{white-space:nowrap}
.panel{margin-top:14px;padding:14px 16px}
.viewer{display:grid;grid-template-columns:minmax(0,1fr) 318px;gap:16px}
.view-wrap{position:relative;background:#fcfcfd;border:1px solid var(--line);border-radius:10px;overflow:hidden}
#view{display:block;width:100%;height:640px;cursor:grab;touch-action:none}
#view.dragging{cursor:grabbing}
.zoom{position:absolute;right:10px;top:10px;display:flex;gap:4px}
.zoom button,.controls button{font:inherit;font-size:13px;border:1px solid var(--line);background:#fff;border-radius:7px;padding:3px 10px;cursor:pointer;color:var(--ink)}
.zoom button:hover,.controls button:hover{background:#f3f4f6}
.hint{position:absolute;left:12px;top:12px;font-size:11.5px;color:#9ca3af}
.side h2{margin:0;font-size:22px;font-weight:720;font-variant-numeric:tabular-nums}
.side .z{color:var(--muted);font-size:13px;margin-bottom:8px}
#slider{width:100%;accent-color:var(--accent);margin:4px 0 6px}
.controls{display:flex;gap:6px;margin-bottom:12px}
.legend{display:grid;grid-template-columns:1fr;gap:3px;border-top:1px solid var(--line);padding-top:10px}
.legend label{display:flex;align-items:center;gap:8px;font-size:13px;cursor:pointer;user-select:none}
.legend input{margin:0;accent-color:#4b5563}
.sw{display:inline-block;width:22px;height:6px;border-radius:3px}
.sw.fill{height:12px;border-radius:3px;opacity:.55}
.cavsw{display:inline-flex;gap:2px}.cavsw .sw{width:9px}
dl.figs{display:grid;grid-template-columns:auto 1fr;gap:3px 12px;margin:12px 0 0;padding-top:10px;border-top:1px solid var(--line);font-size:13px}
dl.figs dt{color:var(--muted)}dl.figs dd{margin:0;text-align:right;font-variant-numeric:tabular-nums}
.note{font-size:12px;color:var(--muted);margin:10px 0 0}
.plots{display:grid;grid-template-columns:1fr 1fr;gap:22px}
.plots h3{margin:0;font-size:15px}
.plots .cap{margin:2px 0 0;font-size:12.5px;color:var(--muted)}
.chip{display:inline-flex;align-items:center;gap:5px;margin-right:12px;font-size:12.5px;color:var(--muted)}
.chip i{display:inline-block;width:12px;height:12px;border-radius:3px}
.plot-svg{width:100%;height:auto;display:block;cursor:crosshair}
.plot-svg .grid{stroke:#eef0f3;stroke-width:1}
.plot-svg text{font-size:11px;fill:#8b93a1}
.plot-svg .ytick,.plot-svg .yunit{text-anchor:end}.plot-svg .xlabel,.plot-svg .xunit{text-anchor:middle}
.plot-svg .xtick{stroke:#c4c9d2}
.plot-svg .carve-area{fill:#1c7ed6;fill-opacity:.18}
.plot-svg .carve-line{fill:none;stroke:#1c7ed6;stroke-width:1.6;stroke-linejoin:round}
.plot-svg .conv{fill:none;stroke:#6b7280;stroke-width:1.4;stroke-dasharray:5 3}
.plot-svg .cursor{stroke:#111827;stroke-width:1.2;stroke-dasharray:2 2}
.plot-svg line.weak{stroke:#e03131;stroke-width:1.4}.plot-svg text.weak{fill:#e03131}
.details h2{font-size:16px;margin:0 0 8px}
.details .cols{display:grid;grid-template-columns:1.3fr 1fr;gap:28px}
.formula{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;background:#f6f7f9;border-radius:8px;padding:8px 10px;font-size:12.5px;overflow-x:auto}
table.settings{border-collapse:collapse;width:100%;font-size:13px}
table.settings td{padding:3px 6px;border-bottom:1px solid #f0f1f3}
table.settings td:last-child{text-align:right;font-variant-numeric:tabular-nums}
.warn{color:#b45309}
details pre{background:#f6f7f9;border-radius:8px;padding:10px;font-size:12px;max-height:360px;overflow:auto}
footer{text-align:center;color:#9ca3af;font-size:12px;padding:0 0 24px}
#view path{fill:none;stroke-linecap:round;stroke-linejoin:round}
#view path.O{fill:#eef1f4;stroke:none;fill-rule:evenodd}
#view path.r{stroke:none;fill-rule:evenodd;fill-opacity:.16}
#view path.g{stroke:#c9ced6}
#view .ruler line{stroke:#6b7280}
#view .ruler text{fill:#6b7280}
#view.hide-O .O,#view.hide-o .o,#view.hide-o .s,#view.hide-c .c,#view.hide-w .w,#view.hide-b .b,#view.hide-r .r,#view.hide-g .g{display:none}
@media (max-width:1100px){.cards{grid-template-columns:repeat(2,minmax(0,1fr))}.viewer,.plots,.details .cols{grid-template-columns:1fr}}
)CSS";

const char* const kScript = R"JS(
(function () {
  'use strict';
  const L = LAYERS, N = L.length, M = META;
  const view = document.getElementById('view');
  const layerG = document.getElementById('layer'), ghostG = document.getElementById('ghost');
  const slider = document.getElementById('slider');
  const cursors = Array.from(document.querySelectorAll('.plot-svg .cursor'));
  let current = -1;
  const fmt = (v, d) => (v === undefined || v === null) ? '\u2014' : Number(v).toFixed(d);
  const drawn = k => L[k] && L[k].P !== undefined;
  function drawnBelow(k) {
    for (; k >= 0; k--) if (drawn(k)) return k;
    return -1;
  }
  function nearestDrawn(k) {
    for (let d = 0; d < N; d++) {
      if (k - d >= 0 && drawn(k - d)) return k - d;
      if (k + d < N && drawn(k + d)) return k + d;
    }
    return -1;
  }
  function paths(r, ghost) {
    let h = '';
    if (!r || r.P === undefined) return h;
    if (ghost) {
      for (const p of r.P) h += '<path class="g" d="' + p[2] + '"/>';
      return h;
    }
    if (r.O) h += '<path class="O" d="' + r.O + '"/>';
    for (const c of r.R) h += '<path class="r k' + c[0] + '" d="' + c[1] + '"/>';
    for (const p of r.P) h += '<path class="' + p[0] + (p[0] === 'w' ? ' k' + p[1] : '') + '" d="' + p[2] + '"/>';
    return h;
  }
  function row(k, v) { return '<dt>' + k + '</dt><dd>' + v + '</dd>'; }
  function show(k) {
    k = Math.max(0, Math.min(N - 1, k | 0));
    current = k;
    slider.value = k;
    const r = L[k], d = nearestDrawn(k);
    layerG.innerHTML = d >= 0 ? paths(L[d], false) : '';
    const below = d > 0 ? drawnBelow(d - 1) : -1;
    ghostG.innerHTML = below >= 0 ? paths(L[below], true) : '';
    document.getElementById('lnum').textContent = 'Layer ' + (r.i + 1) + ' of ' + M.layers;
    document.getElementById('lz').textContent = 'z = ' + fmt(r.z, 2) + ' mm';
    let f = '';
    f += row('material', fmt(r.m, 1) + ' mm\u00b3');
    f += row('15 % infill estimate', fmt(r.v, 1) + ' mm\u00b3');
    f += row('slice area', fmt(r.a[0], 0) + ' mm\u00b2');
    f += row('covers', fmt(r.a[1], 0) + ' mm\u00b2');
    let cav = 0;
    r.C.forEach(function (c, j) {
      if (c <= 0) return;
      cav += c;
      f += row('<span class="sw" style="background:' + M.colors[j % M.colors.length] + '"></span> cavity ' + (j + 1), fmt(c, c < 10 ? 1 : 0) + ' mm\u00b2');
    });
    f += row('hollow share', r.a[0] > 0 ? fmt(100 * cav / r.a[0], 1) + ' %' : '\u2014');
    f += row('bridges', r.b + (r.b ? ' (' + fmt(r.l[3], 0) + ' mm)' : ''));
    f += row('walls / covers', fmt(r.l[0] + r.l[2], 0) + ' / ' + fmt(r.l[1], 0) + ' mm');
    document.getElementById('figs').innerHTML = f;
    let note = '';
    if (d !== k && d >= 0) note = 'Drawing of layer ' + (L[d].i + 1) + ' shown: only one layer in ' + M.stride + ' is drawn in this page. ';
    if (d >= 0) note += 'Paths simplified to ' + fmt(L[d].t, 2) + ' mm.';
    document.getElementById('note').textContent = note;
    cursors.forEach(function (c) {
      const x = M.plot.left + (k + 0.5) * M.plot.w / N;
      c.setAttribute('x1', x); c.setAttribute('x2', x);
    });
  }
  slider.addEventListener('input', function () { show(+slider.value); });
  document.getElementById('up').onclick = function () { show(current + 1); };
  document.getElementById('down').onclick = function () { show(current - 1); };
  let timer = null;
  const play = document.getElementById('play');
  play.onclick = function () {
    if (timer) { clearInterval(timer); timer = null; play.textContent = '\u25b6 play'; return; }
    if (current >= N - 1) show(0);
    play.textContent = '\u275a\u275a pause';
    timer = setInterval(function () {
      if (current >= N - 1) { play.onclick(); return; }
      show(current + 1);
    }, Math.max(15, Math.min(120, 6000 / N)));
  };
  document.addEventListener('keydown', function (e) {
    if (e.target && e.target.tagName === 'INPUT' && e.target.type === 'range') return;
    const step = { ArrowUp: 1, ArrowRight: 1, ArrowDown: -1, ArrowLeft: -1, PageUp: 10, PageDown: -10 }[e.key];
    if (step) { show(current + step); e.preventDefault(); }
    if (e.key === 'Home') show(0);
    if (e.key === 'End') show(N - 1);
  });
  document.querySelectorAll('.legend input').forEach(function (box) {
    const apply = function () { view.classList.toggle('hide-' + box.dataset.k, !box.checked); };
    box.addEventListener('change', apply);
    apply();
  });
  // Zoom about the pointer and pan by dragging; the base view box fits the whole model.
  const vb0 = M.viewBox.slice();
  let vb = vb0.slice();
  const setVB = function () { view.setAttribute('viewBox', vb.join(' ')); };
  function toUser(cx, cy) {
    const r = view.getBoundingClientRect();
    const s = Math.max(vb[2] / r.width, vb[3] / r.height);
    const ox = vb[0] - (r.width * s - vb[2]) / 2, oy = vb[1] - (r.height * s - vb[3]) / 2;
    return [ox + (cx - r.left) * s, oy + (cy - r.top) * s, s];
  }
  function zoom(f, cx, cy) {
    const r = view.getBoundingClientRect();
    if (cx === undefined) { cx = r.left + r.width / 2; cy = r.top + r.height / 2; }
    const u = toUser(cx, cy);
    vb = [u[0] - (u[0] - vb[0]) * f, u[1] - (u[1] - vb[1]) * f, vb[2] * f, vb[3] * f];
    setVB();
  }
  view.addEventListener('wheel', function (e) { e.preventDefault(); zoom(Math.exp(e.deltaY * 0.0015), e.clientX, e.clientY); }, { passive: false });
  let drag = null;
  view.addEventListener('pointerdown', function (e) { drag = [e.clientX, e.clientY]; view.classList.add('dragging'); view.setPointerCapture(e.pointerId); });
  view.addEventListener('pointermove', function (e) {
    if (!drag) return;
    const s = toUser(e.clientX, e.clientY)[2];
    vb[0] -= (e.clientX - drag[0]) * s; vb[1] -= (e.clientY - drag[1]) * s;
    drag = [e.clientX, e.clientY];
    setVB();
  });
  const endDrag = function () { drag = null; view.classList.remove('dragging'); };
  view.addEventListener('pointerup', endDrag);
  view.addEventListener('pointercancel', endDrag);
  view.addEventListener('dblclick', function () { vb = vb0.slice(); setVB(); });
  document.getElementById('zin').onclick = function () { zoom(1 / 1.5); };
  document.getElementById('zout').onclick = function () { zoom(1.5); };
  document.getElementById('zfit').onclick = function () { vb = vb0.slice(); setVB(); };
  document.querySelectorAll('.plot-svg').forEach(function (svg) {
    svg.addEventListener('click', function (e) {
      const r = svg.getBoundingClientRect();
      const x = (e.clientX - r.left) * M.plot.width / r.width;
      show(Math.floor((x - M.plot.left) / M.plot.w * N));
    });
  });
  const fromHash = /layer=(\d+)/.exec(location.hash);
  show(fromHash ? +fromHash[1] - 1 : M.start);
})();
)JS";

}  // namespace carve::html
