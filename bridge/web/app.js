// retreat-bridge dashboard: live state over server-sent events (/api/events), the time series
// from /api/history, drawn with uPlot (time series) and two canvases (arena, histogram).
'use strict';

(() => {
  const COLORS = {
    free: '#2f7ed8', loaded: '#f28f1c', retreating: '#d7263d', waiting: '#8a8f98',
    pickup: '#2a9d4b', dropoff: '#7b4fd0', optimum: '#2a9d4b', truth: '#f28f1c',
    domain: '#334155', domainFill: '#f8fafc', grid: '#e2e8f0', text: '#475569',
  };
  const $ = (id) => document.getElementById(id);
  const num = (v) => typeof v === 'number' && Number.isFinite(v);
  const fmt = (v, digits) => (num(v) ? v.toFixed(digits) : '–');
  const fmtInt = (v) => (num(v) ? Math.round(v).toLocaleString('en-US') : '–');

  // What tests and people can inspect: how many states arrived, how often the arena was drawn,
  // how long the last draws took (ms, newest last), when the population was first plotted (ms
  // since the page's navigation began), and the agents' table: rows in all and rows in the DOM.
  const probe = { states: 0, time: -1, arenaFrames: 0, arenaTick: -1, robotsDrawn: 0, points: 0, historyLoads: 0,
                  replay: null, drawMs: [], firstPlotMs: -1, agents: 0, agentRowsShown: 0 };
  window.retreatDashboard = probe;

  let state = null;
  let lastEventAt = 0;
  const series = {
    time: [], inside: [], waiting: [], optimum: [], deliveries: [],
    compactions: -1, runs: -1, loading: false,
  };
  let popPlot = null;
  let drawPending = false;

  // ---------------------------------------------------------------------------------------------
  // Time series

  function optimum() {
    return state && num(state.run.optimal_population) ? state.run.optimal_population : null;
  }

  function resetSeries() {
    for (const k of ['time', 'inside', 'waiting', 'optimum', 'deliveries']) series[k].length = 0;
  }

  function pushPoint(p) {
    if (!p || !num(p.time)) return;
    const n = series.time.length;
    if (n > 0 && p.time <= series.time[n - 1]) {
      if (p.time === series.time[n - 1]) {
        series.inside[n - 1] = p.inside;
        series.waiting[n - 1] = p.waiting;
        series.deliveries[n - 1] = p.deliveries;
      }
      return;
    }
    series.time.push(p.time);
    series.inside.push(p.inside);
    series.waiting.push(p.waiting);
    series.optimum.push(optimum());
    series.deliveries.push(p.deliveries);
  }

  async function loadHistory() {
    if (series.loading) return;
    series.loading = true;
    try {
      const res = await fetch('api/history', { cache: 'no-store' });
      if (!res.ok) return;
      const h = await res.json();
      resetSeries();
      for (let i = 0; i < h.time.length; ++i) {
        pushPoint({ time: h.time[i], inside: h.inside[i], waiting: h.waiting[i], deliveries: h.deliveries[i] });
      }
      series.compactions = h.compactions;
      probe.historyLoads += 1;
      scheduleDraw();
    } catch (e) {
      // The event stream reconnects; the next state brings us back here.
    } finally {
      series.loading = false;
    }
  }

  function makePopulationPlot() {
    const el = $('population');
    const width = Math.max(300, el.clientWidth);
    const stepped = uPlot.paths.stepped({ align: 1 });
    popPlot = new uPlot({
      width,
      height: 250,
      scales: {
        x: { time: false },
        y: {
          range: (u, min, max) => {
            const top = Math.max(num(max) ? max : 0, (optimum() || 0) * 1.35, state ? state.run.robots : 0, 1);
            return [0, Math.ceil(top)];
          },
        },
      },
      axes: [
        { label: 'simulated time [s]', stroke: COLORS.text, grid: { stroke: COLORS.grid }, ticks: { stroke: COLORS.grid } },
        { label: 'robots', stroke: COLORS.text, grid: { stroke: COLORS.grid }, ticks: { stroke: COLORS.grid }, size: 46 },
      ],
      series: [
        { label: 't', value: (u, v) => (num(v) ? `${v.toFixed(1)} s` : '–') },
        { label: 'inside', stroke: COLORS.free, width: 2, fill: 'rgba(47,126,216,0.10)', paths: stepped, points: { show: false } },
        { label: 'optimum λ*·|D|', stroke: COLORS.optimum, width: 2, dash: [8, 5], points: { show: false },
          value: (u, v) => fmt(v, 2) },
        { label: 'waiting', stroke: COLORS.waiting, width: 1.5, paths: stepped, points: { show: false } },
      ],
      cursor: { drag: { x: true, y: false } },
      legend: { live: false },
    }, [series.time, series.inside, series.optimum, series.waiting], el);
  }

  // ---------------------------------------------------------------------------------------------
  // Canvases

  function fitCanvas(canvas) {
    const box = canvas.parentElement;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(50, box.clientWidth);
    const h = Math.max(50, box.clientHeight);
    if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
      canvas.width = Math.round(w * dpr);
      canvas.height = Math.round(h * dpr);
      canvas.style.width = `${w}px`;
      canvas.style.height = `${h}px`;
    }
    const ctx = canvas.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    return { ctx, w, h };
  }

  function drawArena() {
    const canvas = $('arena');
    const { ctx, w, h } = fitCanvas(canvas);
    if (!state) return;
    const run = state.run;
    const [hx, hy] = run.half_extent;
    const t = state.telemetry;
    const poses = state.poses;
    const waiting = t ? t.waiting : 0;
    const margin = 0.08 * Math.max(hx, hy);
    const queue = waiting > 0 ? Math.max(0.3 * hx, 4 * run.robot_radius) : 0;
    const xmin = -hx - margin - queue;
    const xmax = hx + margin;
    const ymin = -hy - margin;
    const ymax = hy + margin;
    const scale = Math.min(w / (xmax - xmin), h / (ymax - ymin));
    const ox = (w - (xmax - xmin) * scale) / 2;
    const oy = (h - (ymax - ymin) * scale) / 2;
    const px = (x) => ox + (x - xmin) * scale;
    const py = (y) => oy + (ymax - y) * scale;

    // The domain D.
    ctx.beginPath();
    if (run.shape === 'ellipse') {
      ctx.ellipse(px(0), py(0), hx * scale, hy * scale, 0, 0, 2 * Math.PI);
    } else {
      ctx.rect(px(-hx), py(hy), 2 * hx * scale, 2 * hy * scale);
    }
    ctx.fillStyle = COLORS.domainFill;
    ctx.fill();
    ctx.lineWidth = 2;
    ctx.strokeStyle = COLORS.domain;
    ctx.stroke();

    // Scale bar: 0.5 m (or 1 m on large domains).
    const bar = hx > 3 ? 1 : 0.5;
    ctx.strokeStyle = COLORS.text;
    ctx.fillStyle = COLORS.text;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(w - 12 - bar * scale, h - 12);
    ctx.lineTo(w - 12, h - 12);
    ctx.stroke();
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'right';
    ctx.fillText(`${bar} m`, w - 12, h - 17);

    const r = Math.max(3.5, run.robot_radius * scale);
    const reach = run.delta * scale;
    if (poses) {
      const spot = (p, color, shape) => {
        const [x, y] = p;
        if (!num(x) || !num(y)) return;
        ctx.globalAlpha = 0.13;
        ctx.fillStyle = color;
        ctx.beginPath();
        ctx.arc(px(x), py(y), Math.max(reach, 4), 0, 2 * Math.PI);
        ctx.fill();
        ctx.globalAlpha = 1;
        const s = Math.max(2.5, 0.35 * r);
        ctx.beginPath();
        if (shape === 'square') {
          ctx.rect(px(x) - s, py(y) - s, 2 * s, 2 * s);
        } else {
          ctx.moveTo(px(x), py(y) - 1.3 * s);
          ctx.lineTo(px(x) + 1.3 * s, py(y));
          ctx.lineTo(px(x), py(y) + 1.3 * s);
          ctx.lineTo(px(x) - 1.3 * s, py(y));
          ctx.closePath();
        }
        ctx.fill();
      };
      for (const p of poses.pickups) spot(p, COLORS.pickup, 'square');
      for (const p of poses.dropoffs) spot(p, COLORS.dropoff, 'diamond');

      // One path per colour (and one for the headings): a thousand robots cost a handful of
      // fills and strokes, not a thousand.
      probe.robotsDrawn = 0;
      const byColor = new Map();
      const headings = new Path2D();
      const reaches = poses.robots.length <= 40 ? new Path2D() : null;
      for (const b of poses.robots) {
        if (!num(b.x) || !num(b.y)) continue;
        probe.robotsDrawn += 1;
        const color = b.phase === 'retreating' ? COLORS.retreating : b.loaded ? COLORS.loaded : COLORS.free;
        const cx = px(b.x);
        const cy = py(b.y);
        if (reaches) {
          reaches.moveTo(cx + 2 * reach, cy);
          reaches.arc(cx, cy, 2 * reach, 0, 2 * Math.PI);
        }
        let body = byColor.get(color);
        if (!body) byColor.set(color, (body = new Path2D()));
        body.moveTo(cx + r, cy);
        body.arc(cx, cy, r, 0, 2 * Math.PI);
        if (num(b.theta)) {
          headings.moveTo(cx, cy);
          headings.lineTo(cx + Math.cos(b.theta) * r * 1.6, cy - Math.sin(b.theta) * r * 1.6);
        }
      }
      if (reaches) {
        ctx.strokeStyle = 'rgba(51,65,85,0.12)';
        ctx.lineWidth = 1;
        ctx.stroke(reaches);
      }
      for (const [color, body] of byColor) {
        ctx.fillStyle = color;
        ctx.fill(body);
        ctx.lineWidth = 1;
        ctx.strokeStyle = 'rgba(15,23,42,0.55)';
        ctx.stroke(body);
      }
      ctx.strokeStyle = '#0f172a';
      ctx.lineWidth = 1.5;
      ctx.stroke(headings);
    }

    // Waiting robots: a queue outside the domain, on the left.
    if (waiting > 0) {
      const qx = px(-hx - margin - queue / 2);
      const step = 2.6 * r;
      const fit = Math.max(1, Math.floor((h - 30) / step));
      const shown = Math.min(waiting, fit);
      const top = h / 2 - ((shown - 1) * step) / 2;
      for (let i = 0; i < shown; ++i) {
        ctx.beginPath();
        ctx.arc(qx, top + i * step, r, 0, 2 * Math.PI);
        ctx.fillStyle = COLORS.waiting;
        ctx.fill();
        ctx.strokeStyle = 'rgba(15,23,42,0.4)';
        ctx.lineWidth = 1;
        ctx.stroke();
      }
      ctx.fillStyle = COLORS.text;
      ctx.textAlign = 'center';
      ctx.fillText(waiting > shown ? `queue (+${waiting - shown})` : 'queue', qx, Math.max(12, top - step));
    }

    if (run.encounter_model === 'kinetic') {
      ctx.fillStyle = COLORS.text;
      ctx.textAlign = 'center';
      ctx.font = '13px system-ui, sans-serif';
      ctx.fillText('kinetic world: encounters without positions', px(0), py(0) - 8);
      ctx.fillText(`${t ? t.inside : 0} robots inside`, px(0), py(0) + 12);
    } else if (!poses) {
      ctx.fillStyle = COLORS.text;
      ctx.textAlign = 'center';
      ctx.font = '13px system-ui, sans-serif';
      ctx.fillText('waiting for the arena…', px(0), py(0));
    }
    if (poses) {
      canvas.dataset.tick = String(poses.tick);
      probe.arenaTick = poses.tick;
    }
    probe.arenaFrames += 1;
  }

  function drawHistogram() {
    const canvas = $('histogram');
    const { ctx, w, h } = fitCanvas(canvas);
    if (!state) return;
    const est = state.estimates;
    const run = state.run;
    const bins = est.counts.length + 1;  // the last bar: beyond the range
    const left = 42;
    const right = 12;
    const top = 14;
    const bottom = 34;
    const plotW = w - left - right;
    const plotH = h - top - bottom;
    const maxCount = Math.max(1, est.overflow, ...est.counts);
    const xmax = bins * est.bin_width;
    const X = (v) => left + (Math.min(v, xmax) / xmax) * plotW;
    const Y = (c) => top + plotH - (c / maxCount) * plotH;

    ctx.font = '11px system-ui, sans-serif';
    ctx.strokeStyle = COLORS.grid;
    ctx.fillStyle = COLORS.text;
    ctx.lineWidth = 1;
    const yStep = maxCount <= 6 ? 1 : Math.ceil(maxCount / 5);
    ctx.textAlign = 'right';
    for (let c = 0; c <= maxCount; c += yStep) {
      ctx.beginPath();
      ctx.moveTo(left, Y(c));
      ctx.lineTo(w - right, Y(c));
      ctx.stroke();
      ctx.fillText(String(c), left - 6, Y(c) + 4);
    }
    ctx.textAlign = 'center';
    const labelEvery = bins > 10 ? 2 : 1;
    for (let k = 0; k <= bins - 1; k += labelEvery) {
      ctx.fillText((k * est.bin_width).toFixed(2), X(k * est.bin_width), h - bottom + 14);
    }
    ctx.fillText('λ̂ [robots/m²]', left + plotW / 2, h - 4);

    const barW = plotW / bins;
    const counts = est.counts.concat([est.overflow]);
    for (let k = 0; k < bins; ++k) {
      if (!counts[k]) continue;
      ctx.fillStyle = k === bins - 1 ? 'rgba(47,126,216,0.45)' : COLORS.free;
      ctx.fillRect(left + k * barW + 1, Y(counts[k]), barW - 2, top + plotH - Y(counts[k]));
    }
    ctx.fillStyle = COLORS.text;
    ctx.fillText('≥', left + (bins - 0.5) * barW, top + plotH + 14);

    const marker = (v, color, label, dash, row) => {
      if (!num(v)) return;
      ctx.save();
      ctx.strokeStyle = color;
      ctx.fillStyle = color;
      ctx.lineWidth = 2;
      ctx.setLineDash(dash);
      ctx.beginPath();
      ctx.moveTo(X(v), top);
      ctx.lineTo(X(v), top + plotH);
      ctx.stroke();
      ctx.setLineDash([]);
      ctx.font = '12px system-ui, sans-serif';
      const right = X(v) > w - 110;
      const tw = ctx.measureText(label).width;
      const tx = right ? X(v) - 5 - tw : X(v) + 5;
      const ty = top + 12 + row * 16;
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(tx - 2, ty - 11, tw + 4, 15);
      ctx.fillStyle = color;
      ctx.textAlign = 'left';
      ctx.fillText(label, tx, ty);
      ctx.restore();
    };
    marker(run.lambda_star, COLORS.optimum, `λ* ${fmt(run.lambda_star, 2)}`, [7, 4], 0);
    if (state.telemetry) marker(state.telemetry.true_density, COLORS.truth, `λ ${fmt(state.telemetry.true_density, 2)}`, [2, 3], 1);
    if (est.count > 0) marker(est.mean, '#0f172a', `mean λ̂ ${fmt(est.mean, 2)}`, [1, 0], 2);

    if (est.count === 0) {
      ctx.fillStyle = COLORS.text;
      ctx.textAlign = 'center';
      ctx.font = '13px system-ui, sans-serif';
      ctx.fillText('no agent is deciding yet (each counts encounters for L seconds first)', left + plotW / 2, top + plotH / 2);
    }
  }

  // ---------------------------------------------------------------------------------------------
  // Counters and table

  function setText(id, text) {
    const el = $(id);
    if (el.textContent !== text) el.textContent = text;
  }

  function deliveryRate() {
    const n = series.time.length;
    if (n < 2) return null;
    const now = series.time[n - 1];
    let i = n - 1;
    while (i > 0 && now - series.time[i - 1] <= 60) --i;
    const span = now - series.time[i];
    if (span <= 0) return null;
    return ((series.deliveries[n - 1] - series.deliveries[i]) / span) * 60;
  }

  function updateCounters() {
    const run = state.run;
    const t = state.telemetry;
    setText('scenario', run.scenario);
    setText('mode', `${run.mode}, ${run.encounter_model}`);
    setText('optimum', fmt(run.optimal_population, 2));
    setText('lambda-star', fmt(run.lambda_star, 3));
    if (!t) return;
    setText('sim-time', `${fmt(t.time, 1)} s`);
    setText('tick', fmtInt(t.tick));
    setText('inside', String(t.inside));
    setText('waiting', String(t.waiting));
    setText('retreating', String(t.retreating));
    setText('departed', String(t.departed));
    setText('lost', String(t.lost_agents));
    setText('deliveries', fmtInt(t.deliveries));
    setText('delivery-rate', fmt(deliveryRate(), 1));
    setText('tps', fmtInt(t.ticks_per_second));
    setText('density', fmt(t.true_density, 3));
    $('lost').parentElement.classList.toggle('alert', t.lost_agents > 0);
    const full = Math.max(run.robots, (run.optimal_population || 0) * 2, t.inside, 1);
    $('inside-bar').style.width = `${Math.min(100, (100 * t.inside) / full)}%`;
    $('optimum-mark').style.left = `${Math.min(100, (100 * (run.optimal_population || 0)) / full)}%`;
    const off = run.optimal_population ? t.inside / run.optimal_population : 1;
    $('inside-bar').dataset.level = off > 1.5 ? 'high' : off < 0.5 ? 'low' : 'ok';
  }

  // The agents' table is virtual: all rows are kept as data, and only those in (or near) the
  // scrolled view are in the DOM, between two spacer rows that keep the scroll height true.
  const ROW_HEIGHT = 24;  // px, as style.css sets #agents tbody tr
  let agentRows = [];

  function updateAgents() {
    // Robots in D (the kinetic world's poses list none: then nobody is known to have left).
    const inD = state.poses && state.poses.robots.length ? new Set(state.poses.robots.map((r) => r.id)) : null;
    agentRows = state.agents.map((a) => {
      const gone = inD !== null && a.retreating && !inD.has(a.robot);
      const label = gone ? 'departed' : a.retreating ? 'retreating'
        : a.deciding ? (a.counted ? 'deciding' : 'deciding (stale)') : 'counting';
      const cls = gone ? 'waiting' : a.retreating ? 'retreating' : a.deciding ? 'free' : 'waiting';
      return `<tr><td>${a.robot}</td><td><span class="chip ${cls}"></span>${label}</td>` +
        `<td>${fmt(a.lambda_hat, 3)}</td><td>${fmt(a.epsilon, 4)}</td><td>${a.onsets_in_window}</td></tr>`;
    });
    probe.agents = agentRows.length;
    showAgentRows();
    const est = state.estimates;
    setText('estimates-note', est.count > 0 ? `${est.count} deciding, mean ${fmt(est.mean, 3)} /m²` : '');
  }

  function showAgentRows() {
    const box = $('agents').parentElement;
    const body = $('agents').tBodies[0];
    const n = agentRows.length;
    let html;
    if (n === 0) {
      html = '<tr><td colspan="5" class="muted">no agent status yet</td></tr>';
      probe.agentRowsShown = 0;
    } else {
      const first = Math.min(n, Math.max(0, Math.floor(box.scrollTop / ROW_HEIGHT) - 5));
      const last = Math.min(n, first + Math.ceil(box.clientHeight / ROW_HEIGHT) + 10);
      const spacer = (rows) => (rows > 0 ? `<tr class="spacer" style="height:${rows * ROW_HEIGHT}px"><td colspan="5"></td></tr>` : '');
      html = spacer(first) + agentRows.slice(first, last).join('') + spacer(n - last);
      probe.agentRowsShown = last - first;
    }
    if (body.innerHTML !== html) body.innerHTML = html;
  }

  let agentScrollPending = false;
  function onAgentsScroll() {
    if (agentScrollPending) return;
    agentScrollPending = true;
    requestAnimationFrame(() => {
      agentScrollPending = false;
      showAgentRows();
    });
  }

  function draw() {
    drawPending = false;
    if (!state) return;
    const began = performance.now();
    updateCounters();
    updateAgents();
    drawArena();
    drawHistogram();
    if (popPlot) popPlot.setData([series.time, series.inside, series.optimum, series.waiting]);
    probe.points = series.time.length;
    const now = performance.now();
    if (popPlot && probe.points > 0 && probe.firstPlotMs < 0) probe.firstPlotMs = now;
    probe.drawMs.push(now - began);
    if (probe.drawMs.length > 200) probe.drawMs.shift();
  }

  function scheduleDraw() {
    if (drawPending) return;
    drawPending = true;
    requestAnimationFrame(draw);
  }

  // ---------------------------------------------------------------------------------------------
  // Live updates

  function onState(s) {
    const firstState = state === null;
    const newRun = state !== null && s.runs !== state.runs;
    state = s;
    probe.states += 1;
    if (s.telemetry) probe.time = s.telemetry.time;
    lastEventAt = Date.now();
    if (firstState) setText('arena-note', s.run.shape === 'ellipse'
      ? `ellipse ${fmt(2 * s.run.half_extent[0], 1)} × ${fmt(2 * s.run.half_extent[1], 1)} m, |D| = ${fmt(s.run.area, 2)} m²`
      : `rectangle ${fmt(2 * s.run.half_extent[0], 1)} × ${fmt(2 * s.run.half_extent[1], 1)} m, |D| = ${fmt(s.run.area, 2)} m²`);
    if (replay) showReplayTick(s);
    if (newRun || (series.compactions !== -1 && s.history.compactions !== series.compactions) ||
        (replay && s.history.points !== series.time.length)) {
      // A replay moves by many points at once, and backwards: the whole series again.
      loadHistory();
    } else if (s.history.last) {
      pushPoint(s.history.last);
    }
    scheduleDraw();
  }

  function setLink(kind, text) {
    const el = $('link');
    if (el.dataset.state !== kind) el.dataset.state = kind;
    setText('link-text', text);
  }

  function connect() {
    const source = new EventSource('api/events');
    source.addEventListener('open', () => (replay ? showReplay(replay) : setLink('live', 'live')));
    source.addEventListener('state', (e) => {
      try {
        onState(JSON.parse(e.data));
      } catch (err) {
        showError(`bad state event: ${err}`);
      }
    });
    source.addEventListener('error', () => setLink('offline', 'reconnecting'));
  }

  // ---------------------------------------------------------------------------------------------
  // Replay (retreat-bridge --replay FILE): a slider over the recording's ticks, play and pause.

  let replay = null;  // the position from /api/replay, null when live
  let dragging = false;

  function showReplay(p) {
    replay = p;
    probe.replay = { tick: p.tick, playing: p.playing, first: p.first_tick, last: p.last_tick };
    const slider = $('replay-slider');
    slider.min = String(p.first_tick);
    slider.max = String(p.last_tick);
    if (!dragging) slider.value = String(p.tick);
    $('replay-play').textContent = p.playing ? '⏸' : '▶';
    $('replay-play').setAttribute('aria-label', p.playing ? 'pause' : 'play');
    setText('replay-position', `tick ${fmtInt(p.tick)} of ${fmtInt(p.last_tick)} · t = ${fmt(p.time, 1)} s`);
    setLink('replay', p.playing ? 'replay, playing' : 'replay, paused');
  }

  function showReplayTick(s) {
    if (!s.telemetry || dragging) return;
    $('replay-slider').value = String(s.telemetry.tick);
  }

  async function replayCommand(query) {
    try {
      const res = await fetch(`api/replay?${query}`, { method: 'POST', cache: 'no-store' });
      if (!res.ok) {
        showError(`replay: ${await res.text()}`);
        return;
      }
      showReplay(await res.json());
    } catch (e) {
      setLink('offline', 'bridge unreachable');
    }
  }

  async function pollReplay() {
    try {
      const res = await fetch('api/replay', { cache: 'no-store' });
      if (!res.ok) return false;
      const p = await res.json();
      if (p.replaying) showReplay(p);
      return p.replaying === true;
    } catch (e) {
      return false;
    }
  }

  function setUpReplay() {
    $('replay').hidden = false;
    document.querySelector('.brand .muted').textContent = 'replay';
    document.title = 'retreat · replay';
    const slider = $('replay-slider');
    slider.addEventListener('input', () => { dragging = true; });
    slider.addEventListener('change', async () => {
      dragging = false;
      await replayCommand(`tick=${encodeURIComponent(slider.value)}`);
    });
    $('replay-play').addEventListener('click', () => {
      if (replay && replay.playing) replayCommand('play=0');
      else replayCommand(`play=1&speed=${encodeURIComponent($('replay-speed').value)}`);
    });
    $('replay-speed').addEventListener('change', () => {
      if (replay && replay.playing) replayCommand(`play=1&speed=${encodeURIComponent($('replay-speed').value)}`);
    });
    setInterval(pollReplay, 500);
  }

  setInterval(() => {
    const el = $('link');
    if (replay) return;  // showReplay says where the replay is
    if (el.dataset.state === 'offline' || el.dataset.state === 'connecting') return;
    if (Date.now() - lastEventAt > 3000) {
      setLink('idle', state && state.telemetry ? 'no new data' : 'waiting for the arena');
    } else {
      setLink('live', 'live');
    }
  }, 1000);

  async function loadDownloads() {
    try {
      const res = await fetch('api/runs', { cache: 'no-store' });
      if (!res.ok) return;
      const j = await res.json();
      const el = $('downloads');
      if (!j.recording) return;
      el.classList.remove('muted');
      el.replaceChildren();
      if (j.files.length === 0) el.textContent = 'nothing recorded yet';
      j.files.forEach((f, i) => {
        if (i > 0) el.append(' · ');
        const a = document.createElement('a');
        a.href = f.url;
        a.textContent = f.name;
        a.title = `${(f.size / 1024).toFixed(1)} KiB`;
        el.append(a);
      });
    } catch (e) {
      // Not important: retried below.
    }
  }

  function showError(text) {
    const el = $('error');
    el.textContent = text;
    el.hidden = false;
  }

  window.addEventListener('resize', () => {
    if (popPlot) popPlot.setSize({ width: Math.max(300, $('population').clientWidth), height: 250 });
    scheduleDraw();
  });

  async function start() {
    makePopulationPlot();
    $('agents').parentElement.addEventListener('scroll', onAgentsScroll, { passive: true });
    if (await pollReplay()) setUpReplay();
    try {
      const res = await fetch('api/state', { cache: 'no-store' });
      if (res.ok) onState(await res.json());
    } catch (e) {
      setLink('offline', 'bridge unreachable');
    }
    await loadHistory();
    connect();
    loadDownloads();
    setInterval(loadDownloads, 10000);
  }

  start();
})();
