// kreisel explore: the form, the runs, the playback loop and the panels.
import { ApiError, download, getJSON, postJSON, saveBlob } from './api.js';
import { Atlas } from './atlas.js';
import { Charts } from './charts.js';
import { SweepMap } from './sweep.js';
import { ARROW_COLOURS, View3D } from './view3d.js';

const $ = (id) => document.getElementById(id);
const TABLES = ['top', 'pivot', 'damping', 'state', 'simulation'];
// tables a top may leave out (a pivot that moves, damping at it: heavy and Lagrange tops)
const OPTIONAL = ['pivot', 'damping'];

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

// A number as the form shows it: its shortest text when that has at most 6 significant digits,
// else rounded to 6 (the field keeps the exact value until it is edited: see readInput).
function showNumber(v) {
  const text = (x) => (x !== 0 && (Math.abs(x) < 1e-3 || Math.abs(x) >= 1e7) ? x.toExponential() : String(x));
  const exact = text(v);
  const digits = exact.replace(/e.*$/, '').replace(/[-.]/g, '').replace(/^0+/, '').length;
  return digits <= 6 ? exact : text(Number(v.toPrecision(6)));
}

// A result as the page shows it: 4 significant digits (1.444 s, not 1.4436780883518276 s).
function fmt4(v) {
  return v === null || v === undefined ? '-' : String(Number(v.toPrecision(4)));
}

function showValue(v) {
  if (v === undefined || v === null) return '';
  if (Array.isArray(v)) return v.map(showValue).join(', ');
  if (typeof v === 'number') return showNumber(v);
  return String(v);
}

// The value typed in a field as JSON: empty is left out, true/false, a list of numbers
// (comma-separated), a number, else the text itself (kreisel checks it and says what is wrong).
function parseValue(text) {
  const s = text.trim();
  if (s === '') return undefined;
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

// An input showing value v; it keeps v exactly while its text is the one shown.
function valueInput(v, id) {
  const input = document.createElement('input');
  input.type = 'text';
  input.spellcheck = false;
  if (id) input.id = id;
  input.value = showValue(v);
  if (v !== undefined && v !== null) {
    input.dataset.exact = JSON.stringify(v);
    input.dataset.shown = input.value;
  }
  return input;
}

function readInput(input) {
  if (input.dataset.exact !== undefined && input.value === input.dataset.shown) return JSON.parse(input.dataset.exact);
  return parseValue(input.value);
}

function info(table, name) {
  return (state.schema.info[table] || {})[name] || { label: name, unit: '', help: '' };
}

// The editor of a play top's shape: one block per part, its kind, name and remove button, then
// the kind's fields (m), each under its name.
function partRow(part) {
  const row = document.createElement('div');
  row.className = 'part';
  row.dataset.namedKind = String('kind' in part); // a sphere written kind = "sphere" stays so
  const head = document.createElement('div');
  head.className = 'part-head';
  const kind = document.createElement('select');
  kind.className = 'part-kind';
  for (const k of Object.keys(state.schema.parts)) kind.add(new Option(k, k));
  kind.value = part.kind || 'sphere';
  kind.title = 'the kind of part: a sphere, a spheroid or a torus about the figure axis';
  const name = valueInput(part.name);
  name.className = 'part-value';
  name.dataset.key = 'name';
  name.placeholder = 'name';
  name.title = 'the part\'s name (events and contacts name it)';
  name.setAttribute('aria-label', 'name of part');
  const remove = document.createElement('button');
  remove.type = 'button';
  remove.className = 'remove';
  remove.textContent = '×';
  remove.title = 'remove this part';
  remove.addEventListener('click', () => row.remove());
  head.append(kind, name, remove);
  const fields = document.createElement('div');
  fields.className = 'part-fields';
  const help = {
    radius: 'radius of the sphere',
    equatorial: 'semi-axis across the figure axis',
    axial: 'semi-axis along the figure axis',
    major: 'radius of the circle the ring\'s tube follows',
    minor: 'radius of the ring\'s tube',
    z: 'centre along the figure axis, from the centre of mass',
  };
  const fill = () => {
    fields.innerHTML = '';
    for (const key of state.schema.parts[kind.value]) {
      const label = document.createElement('label');
      label.textContent = `${key} (m)`;
      const input = valueInput(part[key]);
      input.className = 'part-value';
      input.dataset.key = key;
      input.title = `${key}: ${help[key] || key} (m)`;
      label.appendChild(input);
      fields.appendChild(label);
    }
  };
  kind.addEventListener('change', () => {
    fields.querySelectorAll('input.part-value').forEach((i) => { part[i.dataset.key] = readInput(i); });
    fill();
  });
  fill();
  row.append(head, fields);
  return row;
}

function shapeEditor(shape) {
  const box = document.createElement('div');
  box.className = 'parts';
  box.id = 'f-top-shape';
  const list = document.createElement('div');
  list.className = 'part-list';
  for (const part of Array.isArray(shape) ? shape : []) list.appendChild(partRow({ ...part }));
  const add = document.createElement('button');
  add.type = 'button';
  add.id = 'add-part';
  add.textContent = 'add a part';
  add.title = 'a contact part: then leave s and rho empty';
  add.addEventListener('click', () => list.appendChild(partRow({})));
  box.append(list, add);
  return box;
}

function readShape(box) {
  const parts = [...box.querySelectorAll('.part')].map((row) => {
    const part = {};
    const kind = row.querySelector('.part-kind').value;
    if (kind !== 'sphere' || row.dataset.namedKind === 'true') part.kind = kind;
    row.querySelectorAll('input.part-value').forEach((i) => {
      const v = readInput(i);
      if (v !== undefined) part[i.dataset.key] = v;
    });
    return part;
  });
  return parts.length ? parts : undefined;
}

function buildForm(kind, tables) {
  const fields = state.schema.fields[kind];
  for (const table of TABLES) {
    const fs = $(`fs-${table}`);
    fs.querySelectorAll('.field').forEach((e) => e.remove());
    fs.hidden = !(fields[table] || []).length;
    for (const name of fields[table] || []) {
      const about = info(table, name);
      const row = document.createElement('div');
      row.className = 'field';
      row.dataset.table = table;
      row.dataset.field = name;
      row.title = `${name}: ${about.help}`;
      const label = document.createElement('label');
      label.textContent = about.label;
      label.htmlFor = `f-${table}-${name}`;
      const unit = document.createElement('span');
      unit.className = 'unit';
      unit.textContent = about.unit;
      const value = (tables[table] || {})[name];
      let input;
      if (name === 'friction') {
        input = document.createElement('select');
        input.id = `f-${table}-${name}`;
        for (const f of ['', ...state.schema.frictions]) input.add(new Option(f || '(default)', f));
        input.value = value || '';
      } else if (name === 'shape') {
        input = shapeEditor(value);
      } else {
        input = valueInput(value, `f-${table}-${name}`);
      }
      input.name = name;
      const error = document.createElement('span');
      error.className = 'error';
      if (name === 'shape') row.append(label, unit, input, error);
      else row.append(label, input, unit, error);
      fs.appendChild(row);
    }
  }
}

function readForm() {
  const tables = { top: { kind: $('kind').value }, pivot: {}, damping: {}, state: {}, simulation: {} };
  document.querySelectorAll('#form .field').forEach((row) => {
    const input = row.querySelector(`#f-${row.dataset.table}-${row.dataset.field}`);
    let v;
    if (row.dataset.field === 'shape') v = readShape(input);
    else if (input.tagName === 'SELECT') v = input.value || undefined;
    else v = readInput(input);
    if (v !== undefined) tables[row.dataset.table][row.dataset.field] = v;
  });
  for (const t of OPTIONAL) if (!Object.keys(tables[t]).length) delete tables[t];
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
state.charts = charts;
const atlas = new Atlas($('atlas-plane'), $('jr'), $('jr-caption'), (alpha, gamma) => pickAlphaGamma(alpha, gamma));
const sweepMap = new SweepMap($('sweep-map'), (index) => openCell(index), $('sweep-readout'));

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
    ? (r.inversion_time === null ? 'none' : `${fmt4(r.inversion_time)} s`) : 'n/a';
  $('inversion-time').title = typeof r.inversion_time === 'number' ? `${r.inversion_time} s` : '';
  $('link').value = new URL(runLink(r.tables), window.location.href).href;
  $('events').textContent = eventsText(r.events);
  $('elapsed').textContent = `${(1000 * r.elapsed).toFixed(1)} ms`;
  $('toml').textContent = r.toml;
  $('slider').max = String(r.t[r.t.length - 1]);
  view.setRun(r);
  showLegend(r);
  charts.setRun(r);
  await showAtlas(r);
  state.t = 0;
  state.last = null;
  draw();
  status(`${r.t.length} samples`);
  return r;
}

// The legend of the 3D view's traces, in the colours they are drawn in.
function showLegend(r) {
  const lines = { tip: view.tipLine, contact: view.contactLine };
  for (const [name, line] of Object.entries(lines)) {
    const row = document.querySelector(`#legend [data-trace="${name}"]`);
    row.hidden = !line || !$('traces').checked;
    if (line) row.querySelector('.swatch').style.borderTopColor = `#${line.material.color.getHexString()}`;
  }
  // the contact arrows of a play top, in their colours
  const arrows = !!(r && r.contacts && r.contacts.parts.length) && $('forces').checked;
  for (const [name, colour] of Object.entries(ARROW_COLOURS)) {
    const row = document.querySelector(`#legend [data-trace="${name}"]`);
    row.hidden = !arrows;
    const css = `#${colour.toString(16).padStart(6, '0')}`;
    const mark = row.querySelector('.swatch, .dot');
    if (mark.classList.contains('dot')) mark.style.background = css; else mark.style.borderTopColor = css;
  }
  $('legend').hidden = !$('traces').checked && !arrows;
}

// The address of this page that runs ``tables``: ?run=<the tables as JSON>.
function runLink(tables) {
  return `?${new URLSearchParams({ run: JSON.stringify(tables) })}`;
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
  $('parts-now').textContent = r.contacts && r.contacts.parts.length
    ? r.contacts.parts.map((name, p) => `${name} ${r.contacts.states[r.contacts.state[p][i]]}`).join(', ')
    : '-';
}

// One sample forward (k = 1) or back (k = -1) from the time shown; the playback pauses.
function step(k) {
  const r = state.run;
  if (!r) return;
  setPlaying(false);
  const [i, frac] = indexAt(state.t);
  const j = k > 0 ? i + 1 : (frac > 0 ? i : i - 1);
  state.t = r.t[Math.min(Math.max(j, 0), r.t.length - 1)];
  draw();
}

function setPlaying(on) {
  state.playing = on;
  $('play').textContent = on ? 'Pause' : 'Play';
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
// the view as a picture, a video, a link; a TOML file into the form
// ---------------------------------------------------------------------------------------

function fileStem() {
  const r = state.run;
  return `kreisel-${$('preset').value || (r && r.kind) || 'top'}-t${state.t.toFixed(3)}s`;
}

function screenshot() {
  view.render();
  view.renderer.domElement.toBlob((blob) => status(`saved ${saveBlob(blob, `${fileStem()}.png`)}`), 'image/png');
}

// Records the 3D view (the canvas's stream) as WebM until pressed again, then saves it.
function toggleRecording() {
  if (state.recorder) {
    state.recorder.stop();
    return;
  }
  const type = ['video/webm;codecs=vp9', 'video/webm;codecs=vp8', 'video/webm']
    .find((t) => window.MediaRecorder && MediaRecorder.isTypeSupported(t));
  if (!type) {
    status('this browser cannot record WebM video (no MediaRecorder)');
    return;
  }
  const chunks = [];
  const name = `${fileStem()}.webm`;
  const recorder = new MediaRecorder(view.renderer.domElement.captureStream(30), { mimeType: type });
  recorder.ondataavailable = (e) => { if (e.data.size) chunks.push(e.data); };
  recorder.onstop = () => {
    state.recorder = null;
    $('record').classList.remove('on');
    $('record').textContent = 'Record video';
    status(`saved ${saveBlob(new Blob(chunks, { type: 'video/webm' }), name)}`);
  };
  recorder.start(250);
  state.recorder = recorder;
  $('record').classList.add('on');
  $('record').textContent = 'Stop and save';
  status('recording the 3D view...');
}

async function copyLink() {
  const link = $('link');
  link.hidden = false;
  link.select();
  try {
    await navigator.clipboard.writeText(link.value);
    status('link copied');
  } catch (e) {
    status('the link is selected: copy it');
  }
}

// The tables into the form (its kind, no preset) and run.
async function loadTables(tables, note) {
  const kind = tables.top.kind;
  $('kind').value = kind;
  fillPresets(kind);
  $('preset').value = '';
  $('preset-summary').textContent = note;
  buildForm(kind, tables);
  return run(readForm());
}

async function loadToml(file) {
  $('notice').textContent = '';
  try {
    const text = await file.text();
    const { tables } = await postJSON('/api/import/toml', { toml: text, name: file.name });
    await loadTables(tables, `from ${file.name}`);
  } catch (e) {
    $('notice').textContent = e.message;
  }
}

// The keys of a viewer: space plays and pauses, the arrows step, r resets the camera.
function onKey(e) {
  if (e.ctrlKey || e.metaKey || e.altKey || !state.run) return;
  const target = e.target;
  if (target instanceof HTMLInputElement && target.type !== 'range' && target.type !== 'checkbox') return;
  if (target instanceof HTMLSelectElement || target instanceof HTMLTextAreaElement) return;
  if (e.key === ' ') setPlaying(!state.playing);
  else if (e.key === 'ArrowRight') step(1);
  else if (e.key === 'ArrowLeft') step(-1);
  else if (e.key === 'r') view.resetCamera();
  else return;
  e.preventDefault();
}

// The first top: ?run=<tables as JSON> (a link to a run), else ?preset=NAME (tippe).
async function firstRun() {
  const query = new URLSearchParams(window.location.search);
  const names = state.schema.presets.map((p) => p.name);
  if (query.get('run')) {
    let tables = null;
    try {
      tables = JSON.parse(query.get('run'));
    } catch (e) {
      $('notice').textContent = `the link's run is not readable (${e.message}): the tippe top instead`;
    }
    if (tables && tables.top && state.schema.kinds.includes(tables.top.kind)) {
      return loadTables(tables, 'from the link');
    }
    if (tables) $('notice').textContent = 'the link\'s run names no kind of top: the tippe top instead';
  }
  const asked = query.get('preset');
  if (asked !== null && !names.includes(asked)) {
    $('notice').textContent = `preset = '${asked}' is not known: known presets are ${names.join(', ')}. `
      + 'Showing tippe.';
  }
  const known = names.includes(asked) ? asked : 'tippe';
  $('kind').value = state.schema.presets.find((p) => p.name === known).kind;
  fillPresets($('kind').value);
  choosePreset(known);
  return run(readForm());
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
  $('play').addEventListener('click', () => setPlaying(!state.playing));
  $('step-back').addEventListener('click', () => step(-1));
  $('step-forward').addEventListener('click', () => step(1));
  document.addEventListener('keydown', onKey);
  $('view-reset').addEventListener('click', () => view.resetCamera());
  $('view-side').addEventListener('click', () => view.sideView());
  $('view-top').addEventListener('click', () => view.topView());
  $('screenshot').addEventListener('click', screenshot);
  $('record').addEventListener('click', toggleRecording);
  $('copy-link').addEventListener('click', copyLink);
  $('load-toml').addEventListener('change', () => {
    const file = $('load-toml').files[0];
    if (file) loadToml(file);
    $('load-toml').value = '';
  });
  $('slider').addEventListener('input', () => {
    state.t = Number($('slider').value);
    draw();
  });
  $('speed').addEventListener('change', () => { state.speed = Number($('speed').value); });
  $('traces').addEventListener('change', () => {
    view.showTraces = $('traces').checked;
    showLegend(state.run);
    draw();
  });
  $('forces').addEventListener('change', () => {
    view.showForces = $('forces').checked;
    showLegend(state.run);
    draw();
  });
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
  await loadStores();
  await firstRun();
  document.body.dataset.ready = 'true';
  requestAnimationFrame(frame);
}

main().catch((e) => {
  status(`error: ${e.message}`);
  throw e;
});
