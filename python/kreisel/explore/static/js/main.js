// kreisel explore: the form, the runs, the playback loop and the panels.
import { ApiError, download, getJSON, postJSON } from './api.js';
import { Atlas } from './atlas.js';
import { Charts } from './charts.js';
import { SweepMap } from './sweep.js';
import { View3D } from './view3d.js';

const $ = (id) => document.getElementById(id);
const TABLES = ['top', 'state', 'simulation'];

const state = {
  schema: null,
  run: null, // the last run the server computed
  t: 0,
  playing: true,
  speed: 1,
  last: null,
  runs: 0,
  frames: 0, // frames drawn while playing (the frame rate is frames / playing time)
  playingSince: null,
  plane: null,
};
window.explore = state; // for the browser tests and the frame-rate note

// ---------------------------------------------------------------------------------------
// the form: one text field per field of the model's tables, filled from a preset
// ---------------------------------------------------------------------------------------

function showValue(v) {
  if (v === undefined || v === null) return '';
  // a play top's shape: its parts' tables, as JSON
  if (Array.isArray(v) && v.some((x) => x !== null && typeof x === 'object')) return JSON.stringify(v);
  if (Array.isArray(v)) return v.map(showValue).join(', ');
  // toExponential() without digits gives the shortest text that reads back as the same number
  if (typeof v === 'number' && v !== 0 && (Math.abs(v) < 1e-3 || Math.abs(v) >= 1e7)) return v.toExponential();
  return String(v);
}

// The value typed in a field as JSON: empty is left out, true/false, a list of numbers
// (comma-separated), a number, else the text itself (kreisel checks it and says what is wrong).
function parseValue(text) {
  const s = text.trim();
  if (s === '') return undefined;
  if (s.startsWith('[{')) {
    try {
      return JSON.parse(s); // a shape: [{"radius": ..., "z": ..., "name": ...}, ...]
    } catch (e) {
      return s; // kreisel says what is wrong with it
    }
  }
  if (s === 'true' || s === 'false') return s === 'true';
  if (s.includes(',') || s.startsWith('[')) {
    return s.replace(/^\[|\]$/g, '').split(',').map((x) => {
      const n = Number(x.trim());
      return x.trim() !== '' && Number.isFinite(n) ? n : x.trim();
    });
  }
  const n = Number(s);
  return Number.isFinite(n) && /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/.test(s) ? n : s;
}

function buildForm(kind, tables) {
  const fields = state.schema.fields[kind];
  for (const table of TABLES) {
    const fs = $(`fs-${table}`);
    fs.querySelectorAll('.field').forEach((e) => e.remove());
    for (const name of fields[table]) {
      const row = document.createElement('div');
      row.className = 'field';
      row.dataset.table = table;
      row.dataset.field = name;
      const label = document.createElement('label');
      label.textContent = name;
      label.htmlFor = `f-${table}-${name}`;
      let input;
      if (name === 'friction') {
        input = document.createElement('select');
        for (const f of ['', ...state.schema.frictions]) input.add(new Option(f || '(default)', f));
      } else {
        input = document.createElement('input');
        input.type = 'text';
        input.spellcheck = false;
      }
      input.id = `f-${table}-${name}`;
      input.name = name;
      input.value = showValue((tables[table] || {})[name]);
      const error = document.createElement('span');
      error.className = 'error';
      row.append(label, input, error);
      fs.appendChild(row);
    }
  }
}

function readForm() {
  const tables = { top: { kind: $('kind').value }, state: {}, simulation: {} };
  document.querySelectorAll('#form .field').forEach((row) => {
    const v = parseValue(row.querySelector('input, select').value);
    if (v !== undefined) tables[row.dataset.table][row.dataset.field] = v;
  });
  return tables;
}

function clearErrors() {
  document.querySelectorAll('#form .field').forEach((row) => {
    row.classList.remove('bad');
    row.querySelector('.error').textContent = '';
  });
  $('form-error').textContent = '';
}

// The API's message beside the field it names (or under the form).
function showError(e) {
  const row = e.field && document.querySelector(`#form .field[data-table="${e.table}"][data-field="${e.field}"]`);
  if (row) {
    row.classList.add('bad');
    row.querySelector('.error').textContent = e.message;
  } else {
    $('form-error').textContent = e.message;
  }
}

function choosePreset(name) {
  const p = state.schema.presets.find((x) => x.name === name);
  $('preset').value = name;
  if (!p) return;
  $('kind').value = p.kind;
  $('preset-summary').textContent = p.summary;
  buildForm(p.kind, p.tables);
}

function fillPresets(kind) {
  const select = $('preset');
  [...select.options].slice(1).forEach((o) => o.remove());
  for (const p of state.schema.presets) if (p.kind === kind) select.add(new Option(p.name, p.name));
}

// ---------------------------------------------------------------------------------------
// runs
// ---------------------------------------------------------------------------------------

const view = new View3D($('view3d'));
state.view = view;
const charts = new Charts($('charts'));
state.charts = charts;
const atlas = new Atlas($('atlas-plane'), $('jr'), $('jr-caption'), (alpha, gamma) => pickAlphaGamma(alpha, gamma));
const sweepMap = new SweepMap($('sweep-map'), (index) => openCell(index));

// The run's events in one line: "touchdown shoulder 2.246 s, ..., rest 4.017 s"; a long
// list keeps its first eight and its last.
function eventsText(events) {
  if (!events || events.length === 0) return 'none';
  const one = (e) => `${e.name}${e.part ? ' ' + e.part : ''} ${e.t.toFixed(3)} s`;
  const shown = events.length > 9 ? [...events.slice(0, 8).map(one), '...', one(events[events.length - 1])]
    : events.map(one);
  return shown.join(', ');
}

function status(text) {
  $('status').textContent = text;
}

async function run(tables) {
  clearErrors();
  status('computing...');
  let r;
  try {
    r = await postJSON('/api/run', { tables });
  } catch (e) {
    status('');
    if (e instanceof ApiError) { showError(e); return null; }
    throw e;
  }
  state.run = r;
  state.runs += 1;
  buildForm(r.kind, r.tables); // the checked tables, as the TOML file holds them
  $('run-count').textContent = String(state.runs);
  $('top-repr').textContent = `${r.top}  ${r.state}`;
  $('inversion-time').textContent = r.kind === 'play'
    ? (r.inversion_time === null ? 'none' : `${r.inversion_time} s`) : 'n/a';
  $('events').textContent = eventsText(r.events);
  $('elapsed').textContent = `${(1000 * r.elapsed).toFixed(1)} ms`;
  $('toml').textContent = r.toml;
  $('slider').max = String(r.t[r.t.length - 1]);
  view.setRun(r);
  charts.setRun(r);
  await showAtlas(r);
  state.t = 0;
  state.last = null;
  draw();
  status(`${r.t.length} samples`);
  return r;
}

async function showAtlas(r) {
  const a = r.kind === 'play' ? r.atlas : null;
  if (a) {
    $('atlas-note').textContent = `alpha = ${a.alpha.toFixed(4)}, gamma = ${a.gamma.toFixed(4)}: type ${a.type}, zone ${a.zone}`;
  } else {
    $('atlas-note').textContent = r.atlas_note || 'The atlas is of play tops: choose one (the tippe preset).';
  }
  if (a && !state.plane) {
    state.plane = await getJSON('/api/atlas');
    atlas.setPlane(state.plane);
  }
  atlas.setTop(a);
}

// alpha = s / rho and gamma = A / C: the atlas moves a top by its s and A
function pickAlphaGamma(alpha, gamma) {
  const tables = readForm();
  const top = tables.top;
  if (top.kind !== 'play') return;
  if (Array.isArray(top.shape) && top.shape.length) {
    // a top of parts: alpha is its first sphere's (z = -s, radius rho)
    top.shape[0].z = -alpha * top.shape[0].radius;
  } else {
    top.s = alpha * top.rho;
  }
  top.A = gamma * top.C;
  run(tables);
}

// ---------------------------------------------------------------------------------------
// playback
// ---------------------------------------------------------------------------------------

function indexAt(t) {
  const ts = state.run.t;
  let lo = 0;
  let hi = ts.length - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (ts[mid] <= t) lo = mid; else hi = mid;
  }
  if (t >= ts[hi]) return [hi, 0];
  return [lo, (t - ts[lo]) / (ts[hi] - ts[lo] || 1)];
}

function draw() {
  const r = state.run;
  if (!r) return;
  const [i, frac] = indexAt(state.t);
  view.setTime(i, frac);
  view.render();
  charts.setCursor(state.t);
  $('slider').value = String(state.t);
  $('clock').textContent = `t = ${state.t.toFixed(3)} s`;
  $('u-now').textContent = r.series.u[i] === null ? '-' : r.series.u[i].toFixed(4);
  $('mode-now').textContent = r.kind === 'play' ? r.modes[r.series.mode[i]] : 'pivot';
}

function frame(now) {
  if (state.run && state.playing) {
    if (state.last !== null) {
      const tEnd = state.run.t[state.run.t.length - 1];
      state.t += (state.speed * (now - state.last)) / 1000;
      if (state.t > tEnd) state.t = 0; // play it again
    }
    state.last = now;
    state.frames += 1;
    draw();
  } else {
    state.last = null;
    if (view.dirty) view.render();
  }
  requestAnimationFrame(frame);
}

// ---------------------------------------------------------------------------------------
// sweeps and export
// ---------------------------------------------------------------------------------------

async function loadStores() {
  const { stores, root } = await getJSON('/api/stores');
  const select = $('store');
  select.innerHTML = '';
  select.add(new Option(stores.length ? '(choose a store)' : '(none)', ''));
  for (const s of stores) select.add(new Option(s, s));
  $('sweep-note').textContent = root ? `stores under ${root}` : 'start kreisel explore with --store DIR to open sweeps';
}

async function openStore(store, variable) {
  $('sweep-note').textContent = '';
  try {
    const v = await postJSON('/api/sweep', { store, var: variable || null });
    const select = $('sweep-var');
    select.innerHTML = '';
    for (const name of v.vars) select.add(new Option(name, name));
    select.value = v.var;
    const fixed = Object.entries(v.fixed).map(([k, x]) => `${k} = ${x}`).join(', ');
    $('sweep-note').textContent = `${v.kind} tops, ${v.dims.join(' x ')}${fixed ? `; at ${fixed}` : ''}`;
    sweepMap.setView(v);
  } catch (e) {
    $('sweep-note').textContent = e.message;
  }
}

async function openCell(index) {
  try {
    const cell = await postJSON('/api/sweep/cell', { store: $('store').value, index });
    $('kind').value = cell.tables.top.kind;
    fillPresets(cell.tables.top.kind);
    $('preset').value = '';
    $('preset-summary').textContent = `sweep cell ${Object.entries(cell.values).map(([k, x]) => `${k} = ${x}`).join(', ')}`;
    buildForm(cell.tables.top.kind, cell.tables);
    await run(readForm());
  } catch (e) {
    $('sweep-note').textContent = e.message;
  }
}

async function exportFile(path, extra) {
  if (!state.run) return;
  try {
    status(`saved ${await download(path, { tables: state.run.tables, ...extra })}`);
  } catch (e) {
    status(e.message);
  }
}

// ---------------------------------------------------------------------------------------
// wiring
// ---------------------------------------------------------------------------------------

async function main() {
  state.schema = await getJSON('/api/schema');
  for (const k of state.schema.kinds) $('kind').add(new Option(`${k} top`, k));
  $('kind').addEventListener('change', () => {
    const kind = $('kind').value;
    fillPresets(kind);
    const first = state.schema.presets.find((p) => p.kind === kind);
    if (first) choosePreset(first.name); else buildForm(kind, {});
  });
  $('preset').addEventListener('change', () => {
    if ($('preset').value) choosePreset($('preset').value);
  });
  $('form').addEventListener('submit', (e) => {
    e.preventDefault();
    run(readForm());
  });
  $('play').addEventListener('click', () => {
    state.playing = !state.playing;
    $('play').textContent = state.playing ? 'Pause' : 'Play';
  });
  $('slider').addEventListener('input', () => {
    state.t = Number($('slider').value);
    draw();
  });
  $('speed').addEventListener('change', () => { state.speed = Number($('speed').value); });
  $('traces').addEventListener('change', () => { view.showTraces = $('traces').checked; draw(); });
  $('follow').addEventListener('change', () => { view.follow = $('follow').checked; draw(); });
  document.querySelectorAll('#tabs button').forEach((b) => b.addEventListener('click', () => {
    document.querySelectorAll('#tabs button, .tab').forEach((e) => e.classList.remove('active'));
    b.classList.add('active');
    $(`tab-${b.dataset.tab}`).classList.add('active');
    if (b.dataset.tab === 'charts') charts.resize();
  }));
  $('store').addEventListener('change', () => { if ($('store').value) openStore($('store').value); });
  $('sweep-var').addEventListener('change', () => openStore($('store').value, $('sweep-var').value));
  $('export-toml').addEventListener('click', () => exportFile('/api/export/toml', {}));
  $('export-csv').addEventListener('click', () => exportFile('/api/export/trajectory', { format: 'csv' }));
  $('export-netcdf').addEventListener('click', () => exportFile('/api/export/trajectory', { format: 'netcdf' }));
  const start = new URLSearchParams(window.location.search).get('preset') || 'tippe';
  const known = state.schema.presets.find((p) => p.name === start) ? start : 'tippe';
  $('kind').value = state.schema.presets.find((p) => p.name === known).kind;
  fillPresets($('kind').value);
  choosePreset(known);
  await loadStores();
  await run(readForm());
  document.body.dataset.ready = 'true';
  requestAnimationFrame(frame);
}

main().catch((e) => {
  status(`error: ${e.message}`);
  throw e;
});
