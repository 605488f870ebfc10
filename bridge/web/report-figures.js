// retreat figures page: draws window.FIGURES (see retreat/bridge/figures.hpp) with uPlot.
// Inlined into the page together with uPlot, so the file needs no network. `#only=<id>` shows
// one figure alone, at a fixed size (for screenshots).
'use strict';

(() => {
  const P = window.FIGURES;
  const palette = ['#2f7ed8', '#2a9d4b', '#f28f1c', '#7b4fd0', '#d64545', '#14a3a3', '#8c6d31', '#e377c2'];
  const C = { text: '#475569', grid: '#e2e8f0' };
  const main = document.getElementById('report');
  const only = (location.hash.match(/only=([A-Za-z0-9_-]+)/) || [])[1];
  const width = () => (only ? 820 : Math.min(1000, Math.max(360, main.clientWidth - 80)));

  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const c of children) e.append(c);
    return e;
  }

  function rgba(hex, alpha) {
    const n = parseInt(hex.slice(1), 16);
    return `rgba(${(n >> 16) & 255},${(n >> 8) & 255},${n & 255},${alpha})`;
  }

  // uPlot wants one x array for every series: merge them, null where a series has no value.
  function merge(series) {
    const xs = new Set();
    for (const s of series) for (const x of s.x) if (typeof x === 'number') xs.add(x);
    const x = Array.from(xs).sort((a, b) => a - b);
    const at = new Map(x.map((v, i) => [v, i]));
    const column = (s, key) => {
      const out = x.map(() => null);
      s.x.forEach((v, i) => { if (typeof v === 'number') out[at.get(v)] = s[key][i]; });
      return out;
    };
    return { x, column };
  }

  function draw(f, box) {
    const { x, column } = merge(f.series);
    const data = [x];
    const series = [{ label: f.x_label }];
    const bands = [];
    f.series.forEach((s, i) => {
      const color = s.color || palette[i % palette.length];
      const dash = s.dash ? [8, 5] : undefined;
      if (s.kind === 'band') {
        data.push(column(s, 'high'), column(s, 'low'));
        series.push({ label: `${s.label} (high)`, stroke: rgba(color, 0.35), width: 1, spanGaps: true, points: { show: false } });
        series.push({ label: `${s.label} (low)`, stroke: rgba(color, 0.35), width: 1, spanGaps: true, points: { show: false } });
        bands.push({ series: [series.length - 2, series.length - 1], fill: rgba(color, 0.16) });
      } else if (s.kind === 'bars') {
        data.push(column(s, 'y'));
        series.push({ label: s.label, stroke: color, fill: rgba(color, 0.5), width: 1,
          paths: uPlot.paths.bars({ size: [0.92, Infinity], align: 0 }), points: { show: false } });
      } else if (s.kind === 'points') {
        data.push(column(s, 'y'));
        series.push({ label: s.label, stroke: color, width: 0, paths: () => null,
          points: { show: true, size: 7, fill: color, stroke: color } });
      } else {
        data.push(column(s, 'y'));
        series.push({ label: s.label, stroke: color, width: 2, dash, spanGaps: true, points: { show: false } });
      }
    });
    const range = (u, mn, mx) => {
      const lo = typeof f.y_min === 'number' ? f.y_min : mn;
      const hi = typeof f.y_max === 'number' ? f.y_max : (mx > lo ? mx + 0.05 * (mx - lo) : lo + 1);
      return [lo, hi];
    };
    const axis = (label, size) => ({ label, stroke: C.text, grid: { stroke: C.grid }, ticks: { stroke: C.grid }, ...(size ? { size } : {}) });
    new uPlot({
      width: width(), height: only ? 380 : 300, legend: { live: false },
      scales: {
        x: { time: false, distr: f.x_log ? 3 : 1,
          ...(typeof f.x_min === 'number' || typeof f.x_max === 'number'
            ? { range: (u, mn, mx) => [typeof f.x_min === 'number' ? f.x_min : mn, typeof f.x_max === 'number' ? f.x_max : mx] }
            : {}) },
        y: f.y_log ? { distr: 3 } : { range },
      },
      axes: [axis(f.x_label), axis(f.y_label, 64)],
      series, bands,
    }, data, box);
  }

  // A heat map: a table whose cells are coloured from green (low) through yellow to red (high).
  function heat(value, low, high) {
    if (typeof value !== 'number') return '#e2e8f0';
    const t = Math.min(1, Math.max(0, (value - low) / (high - low)));
    const hue = 120 * (1 - t);  // 120 green, 60 yellow, 0 red
    return `hsl(${hue.toFixed(0)}, 70%, 78%)`;
  }

  function heatmap(f, box) {
    const h = f.heatmap;
    const head = el('thead', {}, el('tr', {}, el('th', {}, f.y_label + ' / ' + f.x_label),
      ...h.columns.map((c) => el('th', {}, c))));
    const body = el('tbody', {}, ...h.rows.map((r, i) => el('tr', {}, el('th', {}, r),
      ...h.values[i].map((v, j) => {
        const text = h.text ? h.text[i][j] : (v === null ? '–' : String(v));
        const cell = el('td', { class: 'heat', style: `background:${heat(v, h.low, h.high)}` }, text);
        return cell;
      }))));
    box.append(el('table', { class: 'summary heatmap' }, head, body));
  }

  function table(t) {
    const head = el('thead', {}, el('tr', {}, ...t.columns.map((c) => el('th', {}, String(c)))));
    const body = el('tbody', {}, ...t.rows.map((r) => el('tr', {}, ...r.map((c) => el('td', {}, c === null ? '–' : String(c))))));
    return el('section', { class: 'plot' }, el('h2', {}, t.title), el('table', { class: 'summary' }, head, body));
  }

  if (only) main.style.padding = '8px';
  if (!only) {
    main.append(el('header', {}, el('h1', {}, P.title), ...(P.subtitle ? [el('p', { class: 'sub' }, P.subtitle)] : [])));
  }
  for (const s of P.sections) {
    if (!only) {
      const intro = el('section', { class: 'plot' }, el('h2', {}, s.heading));
      for (const p of s.text || []) intro.append(el('p', {}, p));
      main.append(intro);
    }
    for (const f of s.figures || []) {
      if (only && f.id !== only) continue;
      const box = el('div', { class: 'chart', id: `figure-${f.id}` });
      const sec = el('section', { class: 'plot' }, el('h2', {}, f.title));
      if (f.note) sec.append(el('p', { class: 'note' }, f.note));
      sec.append(box);
      main.append(sec);
      if (f.heatmap) heatmap(f, box);
      else draw(f, box);
    }
    if (!only) for (const t of s.tables || []) main.append(table(t));
  }
  if (!only && P.footer) main.append(el('footer', {}, P.footer));
  document.body.dataset.ready = '1';
})();
