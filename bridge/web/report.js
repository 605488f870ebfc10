// retreat report: draws window.REPORT (computed by retreat-bridge from a run directory) with
// uPlot. Inlined into report.html together with uPlot, so the file needs no network.
'use strict';

(() => {
  const R = window.REPORT;
  const C = {
    free: '#2f7ed8', band: 'rgba(47,126,216,0.16)', optimum: '#2a9d4b', truth: '#f28f1c',
    curve: '#7b4fd0', bars: 'rgba(47,126,216,0.55)', text: '#475569', grid: '#e2e8f0',
  };
  const num = (v) => typeof v === 'number' && Number.isFinite(v);
  const fmt = (v, d) => (num(v) ? v.toFixed(d) : '–');
  const main = document.getElementById('report');
  const width = () => Math.min(1000, Math.max(360, main.clientWidth - 40));

  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    for (const c of children) e.append(c);
    return e;
  }

  function axes(xLabel, yLabel) {
    return [
      { label: xLabel, stroke: C.text, grid: { stroke: C.grid }, ticks: { stroke: C.grid } },
      { label: yLabel, stroke: C.text, grid: { stroke: C.grid }, ticks: { stroke: C.grid }, size: 56 },
    ];
  }

  function section(title, note) {
    const s = el('section', { class: 'plot' }, el('h2', {}, title));
    if (note) s.append(el('p', { class: 'note' }, note));
    const box = el('div', { class: 'chart' });
    s.append(box);
    main.append(s);
    return box;
  }

  // --- header and summary table -------------------------------------------------------------
  const seeds = R.population.seeds;
  main.append(el('header', {},
    el('h1', {}, `retreat report: ${R.title}`),
    el('p', { class: 'sub' },
      `${R.arena.encounter_model} world, ${R.arena.shape} |D| = ${fmt(R.area, 3)} m², ` +
      `${R.arena.robots_inside} robots inside + ${R.arena.robots_waiting} waiting · ` +
      `λ* = ${fmt(R.lambda_star, 4)} robots/m², optimum λ*·|D| = ${fmt(R.optimum, 2)} · ` +
      `controller ${R.agent.controller}, L = ${R.agent.L} s, K_p = ${R.agent.K_p} · ` +
      `${seeds} run${seeds > 1 ? 's' : ''}`)));

  const table = el('table', { class: 'summary' });
  const head = ['run', 'seed', 'dds', 'ticks', 'ticks/s', 'final', 'mean last 300 s', 'optimum', 'deliveries', 'retreated', 'lost'];
  table.append(el('thead', {}, el('tr', {}, ...head.map((h) => el('th', {}, h)))));
  const body = el('tbody');
  for (const r of R.runs) {
    const s = r.summary || {};
    const pop = s.population || {};
    const agents = s.agents || {};
    const cells = [r.dir, s.seed ?? '–', s.dds ?? '–', s.ticks ?? '–', fmt(s.ticks_per_second, 0), pop.final ?? '–',
      fmt(pop.mean_last_300s, 2), fmt(s.optimal_population, 2), s.deliveries ?? '–', agents.retreated ?? '–', agents.lost ?? '–'];
    body.append(el('tr', {}, ...cells.map((c) => el('td', {}, String(c)))));
  }
  table.append(body);
  main.append(el('section', { class: 'plot' }, el('h2', {}, 'Runs'), table));

  // --- population over time -------------------------------------------------------------------
  {
    const p = R.population;
    const opt = p.time.map(() => R.optimum);
    const box = section('Population over time',
      seeds > 1 ? `Robots inside: mean over ${seeds} runs, band from the lowest to the highest; dashed: the optimum λ*·|D|.`
        : 'Robots inside D; dashed: the optimum λ*·|D|.');
    const series = [{ label: 't [s]' }];
    const data = [p.time];
    const bands = [];
    if (seeds > 1) {
      series.push({ label: 'highest', stroke: 'rgba(47,126,216,0.35)', width: 1, points: { show: false } });
      series.push({ label: 'lowest', stroke: 'rgba(47,126,216,0.35)', width: 1, points: { show: false } });
      data.push(p.max, p.min);
      bands.push({ series: [1, 2], fill: C.band });
    }
    series.push({ label: seeds > 1 ? 'mean inside' : 'inside', stroke: C.free, width: 2, points: { show: false } });
    data.push(p.mean);
    series.push({ label: 'optimum λ*·|D|', stroke: C.optimum, width: 2, dash: [8, 5], points: { show: false } });
    data.push(opt);
    new uPlot({ width: width(), height: 300, legend: { live: false }, scales: { x: { time: false }, y: { range: (u, mn, mx) => [0, Math.ceil(Math.max(mx, R.optimum * 1.3, 1))] } },
      axes: axes('simulated time [s]', 'robots inside'), series, bands }, data, box);
  }

  // --- throughput against the CTMC -------------------------------------------------------------
  {
    const t = R.throughput;
    const xs = [];
    for (const [n] of t.curve) xs.push(n);
    for (const [n] of t.points) xs.push(n);
    const uniq = Array.from(new Set(xs)).sort((a, b) => a - b);
    const index = new Map(uniq.map((x, i) => [x, i]));
    const curve = uniq.map(() => null);
    const measured = uniq.map(() => null);
    for (const [n, r] of t.curve) curve[index.get(n)] = r;
    for (const [n, r] of t.points) measured[index.get(n)] = r;
    const box = section('Throughput against the CTMC',
      `Deliveries per second in ${fmt(t.window, 0)} s windows against the window's mean population N; ` +
      'line: the CTMC\'s swarm output T(λ)·λ·|D| at λ = N/|D|.');
    new uPlot({ width: width(), height: 300, legend: { live: false }, scales: { x: { time: false }, y: { range: (u, mn, mx) => [0, Math.max(mx, 1e-3) * 1.1] } },
      axes: axes('robots inside N', 'deliveries per second'),
      series: [{ label: 'N' },
        { label: 'CTMC T(λ)·λ·|D|', stroke: C.curve, width: 2, spanGaps: true, points: { show: false } },
        { label: 'measured', stroke: C.free, width: 0, paths: () => null, points: { show: true, size: 7, fill: C.free, stroke: C.free } }],
    }, [uniq, curve, measured], box);
  }

  // --- inter-encounter times -------------------------------------------------------------------
  if (R.encounters && R.encounters.bins) {
    const e = R.encounters;
    const xs = e.bins.map((b) => b[0]);
    const hist = e.bins.map((b) => b[1]);
    const model = xs.map((x) => e.model_rate * Math.exp(-e.model_rate * x));
    const fitted = xs.map((x) => e.fitted_rate * Math.exp(-e.fitted_rate * x));
    const box = section('Inter-encounter times',
      `${e.gaps} gaps between encounter onsets (per robot), mean ${fmt(e.mean_gap, 2)} s; ` +
      `exponential densities with the model's Ω_c = ${fmt(e.model_rate, 4)}/s at the mean density ` +
      `${fmt(e.mean_density, 3)} robots/m², and with the fitted rate ${fmt(e.fitted_rate, 4)}/s.`);
    new uPlot({ width: width(), height: 300, legend: { live: false }, scales: { x: { time: false } },
      axes: axes('time between onsets [s]', 'density [1/s]'),
      series: [{ label: 'gap [s]' },
        { label: 'measured', stroke: C.free, fill: C.bars, width: 1, paths: uPlot.paths.bars({ size: [0.92, Infinity], align: 0 }), points: { show: false } },
        { label: 'Exp(Ω_c) model', stroke: C.optimum, width: 2, points: { show: false } },
        { label: 'Exp(fitted)', stroke: C.truth, width: 2, dash: [6, 4], points: { show: false } }],
    }, [xs, hist, model, fitted], box);
  } else {
    main.append(el('section', { class: 'plot' }, el('h2', {}, 'Inter-encounter times'),
      el('p', { class: 'note' }, R.encounters
        ? `Only ${R.encounters.gaps} gap${R.encounters.gaps === 1 ? '' : 's'} between encounter onsets in this run: too few for a histogram.`
        : 'No encounters.csv in this run (set arena.record_encounters: true to record them).')));
  }

  // --- estimates over time ---------------------------------------------------------------------
  if (R.estimates) {
    const s = R.estimates;
    const star = s.time.map(() => R.lambda_star);
    const box = section('Estimates over time',
      `The deciding agents' λ̂ (${s.agents} agents, ${fmt(s.bin_width, 1)} s bins): mean, band from the 10th to the ` +
      '90th percentile; the true density inside D and λ*.');
    new uPlot({ width: width(), height: 300, legend: { live: false }, scales: { x: { time: false }, y: { range: (u, mn, mx) => [0, Math.max(mx, R.lambda_star * 1.5)] } },
      axes: axes('simulated time [s]', 'robots/m²'),
      series: [{ label: 't [s]' },
        { label: '90th pct', stroke: 'rgba(47,126,216,0.35)', width: 1, points: { show: false } },
        { label: '10th pct', stroke: 'rgba(47,126,216,0.35)', width: 1, points: { show: false } },
        { label: 'mean λ̂', stroke: C.free, width: 2, points: { show: false } },
        { label: 'true λ', stroke: C.truth, width: 1.5, points: { show: false } },
        { label: 'λ*', stroke: C.optimum, width: 2, dash: [8, 5], points: { show: false } }],
      bands: [{ series: [1, 2], fill: C.band }],
    }, [s.time, s.high, s.low, s.mean, s.true_density, star], box);
  } else {
    main.append(el('section', { class: 'plot' }, el('h2', {}, 'Estimates over time'),
      el('p', { class: 'note' }, 'No agent_status.csv in this run: the bridge records it while the run goes on.')));
  }

  main.append(el('footer', {}, `Model: λ_p = ${R.model.lambda_p}, λ_d = ${R.model.lambda_d}, C = ${R.model.C}, ` +
    `δ = ${R.model.delta} m, v = ${R.model.v} m/s, ρ = ${R.model.rho}/s. Written by retreat-bridge.`));
  document.body.dataset.ready = '1';
})();
