// The page: controls generated from the parameter table, live updates through the WebAssembly
// module (skin.js: the same schemas as the skin command), plots as SVG, a dropped measured
// spectrum overlaid and fitted, downloads in the CLI's formats. No framework, no network.
'use strict';

const state = {
  module: null,
  table: [],        // skin parameters --format json
  presets: [],      // skin presets --format json
  preset: 'caucasian',
  values: {},       // current parameter values by key (the last valid number of each field)
  fieldErrors: {},  // by key: the message of a field whose text is not a number (nothing is computed)
  modelError: null, // the last update's refusal: {message, parameters: [key]}
  solver: 'accurate',
  solveProfile: false,  // the next update solves a profile that needs solving (the button)
  profilePending: null, // the update's "profile_pending": the profile was not solved
  illuminant: 'D65',
  wide: false,
  spectrum: null,   // the last spectrum document (skin spectrum --format json)
  profile: null,    // the last profile document (skin profile --rgb --format json)
  color: null,      // the last colour document under an illuminant other than D65 (skin color --illuminant NAME --format json)
  measured: null,   // {file, csv, columns: [{name, R}], wavelength_nm}
  fit: null,        // the last fit document (skin fit --format json)
  export: null,     // the last export ({target, files: [{name, content}], images, report})
  exportKey: '',
  strip: null,
  stripKey: '',
  timings: [],      // ms of each full update (spectrum, colour, RGB profile, drawing)
  modelTimings: [], // ms of its model part (the module's update, JSON included)
  updates: 0,
};
window.skinState = state;

const $ = (id) => document.getElementById(id);
const num = (v) => Number(v).toPrecision(10).replace(/\.?0+(e|$)/, '$1');  // as %.10g

// A refusal of the module: its one-line message, and the keys of the parameters it is about
// (the reply's "parameters"; none for other errors).
function run(command, request) {
  const text = state.module.run(command, JSON.stringify(request));
  if (text.startsWith('{"error":')) {
    const reply = JSON.parse(text);
    throw Object.assign(new Error(reply.error), { parameters: reply.parameters || [] });
  }
  return text;
}
const runJson = (command, request) => JSON.parse(run(command, request));

function request(extra = {}) {
  const r = { preset: state.preset, params: { ...state.values }, solver: state.solver };
  if (state.wide) Object.assign(r, { lambda_min: 380, lambda_max: 780 });
  return Object.assign(r, extra);
}

// --- Controls ---------------------------------------------------------------------------------

function sliderRange(p) {
  // Finite ranges as they are; open-ended ones up to four times the default.
  const min = p.min === null ? 0 : p.min;
  const max = p.max === null ? 4 * p.default : p.max;
  return { min: p.min_exclusive ? Math.max(min, max / 1000) : min, max };
}

// The parameter's range as the model's messages write it ("[0, 1]", "(0, inf)").
const rangeText = (p) => `${p.min_exclusive ? '(' : '['}${p.min === null ? '-inf' : p.min}, ${p.max === null ? 'inf' : p.max}${p.max_exclusive ? ')' : ']'}`;
// The parameter as the model's messages name it: "melanin-blend (beta_m)".
const label = (p) => p.flag.replace(/^--/, '') + (p.symbol ? ` (${p.symbol})` : '');

// The number a field's text holds ({value}), or the line naming the parameter and its range
// ({error}): empty text, text that is not a decimal number ("NaN", "abc", "-", "0x1") and numbers
// beyond a double ("1e999") are refused here and never reach the model; a finite number outside
// the range goes to the model, which refuses it with its own line.
const DECIMAL = /^[+-]?(\d+\.?\d*|\.\d+)(e[+-]?\d+)?$/i;
function parseField(p, text) {
  const t = text.trim();
  const allowed = `allowed range is ${rangeText(p)}`;
  if (t === '') return { error: `${label(p)} is empty: ${allowed}` };
  if (!DECIMAL.test(t)) return { error: `${label(p)} = '${t}' is not a number: ${allowed}` };
  const value = Number(t);
  if (!Number.isFinite(value)) return { error: `${label(p)} = ${t} is out of range: ${allowed}` };
  return { value };
}

function buildControls() {
  const box = $('parameters');
  for (const p of state.table) {
    const { min, max } = sliderRange(p);
    const row = document.createElement('div');
    row.className = 'param';
    row.dataset.key = p.key;
    const unit = p.unit === '1' ? '' : ` [${p.unit}]`;
    const tip = `${p.help}${unit}; range ${rangeText(p)}; default ${p.default}; CLI ${p.flag}${p.symbol ? ' (--' + p.symbol + ')' : ''}`;
    // The field is text (inputmode decimal), not type=number: the page sees what was typed and
    // names it, where a number field hands over "" for "abc" or "1e999" alike.
    row.innerHTML = `<label title="${tip}" for="n-${p.key}">${p.key}${p.symbol ? ' <span class="muted">' + p.symbol + '</span>' : ''}${unit}</label>` +
      `<input type="range" id="s-${p.key}" min="${min}" max="${max}" step="${(max - min) / 1000}" title="${tip}">` +
      `<input type="text" inputmode="decimal" autocomplete="off" spellcheck="false" class="value" id="n-${p.key}" title="${tip}">`;
    box.appendChild(row);
    const slider = row.querySelector('input[type=range]'), field = row.querySelector('input.value');
    slider.addEventListener('input', () => { field.value = slider.value; setField(p, slider.value); });
    field.addEventListener('change', () => setField(p, field.value));
  }
  for (const pr of state.presets) {
    const b = document.createElement('button');
    b.textContent = pr.name;
    b.title = pr.description;
    b.dataset.preset = pr.name;
    b.addEventListener('click', () => applyPreset(pr.name));
    $('presets').appendChild(b);
  }
  // The solver and the illuminant: a choice each from the module's list ({name, description,
  // default}), kept in state[key].
  for (const key of ['solver', 'illuminant']) {
    for (const item of runJson(key + 's', {})) {
      const o = document.createElement('option');
      o.value = item.name;
      o.textContent = `${item.name}${item.default ? ' (default)' : ''}`;
      o.title = item.description;
      $(key).appendChild(o);
    }
    $(key).addEventListener('change', () => { state[key] = $(key).value; scheduleUpdate(); });
  }
  $('wide').addEventListener('change', () => { state.wide = $('wide').checked; scheduleUpdate(); });
}

function showValues() {
  for (const p of state.table) {
    $('s-' + p.key).value = state.values[p.key];
    $('n-' + p.key).value = state.values[p.key];
  }
  state.fieldErrors = {};
  for (const b of $('presets').children) b.classList.toggle('active', b.dataset.preset === state.preset);
}

function applyPreset(name) {
  state.preset = name;
  state.values = { ...state.presets.find((p) => p.name === name).parameters };
  showValues();
  scheduleUpdate();
}

// A field's text: a number becomes the parameter's value (the slider follows when it holds
// it); anything else is the field's error, the value stays the last valid one, and the update
// shows the error instead of computing.
function setField(p, text) {
  const { value, error } = parseField(p, text);
  if (error) {
    state.fieldErrors[p.key] = error;
  } else {
    delete state.fieldErrors[p.key];
    state.values[p.key] = value;
    if (String(value) !== $('s-' + p.key).value) $('s-' + p.key).value = value;
  }
  scheduleUpdate();
}

// The first field error in the table's order: {message, parameters: [every field in error]}.
function fieldError() {
  const keys = state.table.map((p) => p.key).filter((k) => k in state.fieldErrors);
  if (keys.length === 0) return null;
  const more = keys.length > 1 ? ` (and ${keys.length - 1} more field${keys.length > 2 ? 's' : ''})` : '';
  return { message: state.fieldErrors[keys[0]] + more, parameters: keys };
}

// The page in error (err: {message, parameters}) or not (null): the message in the status line,
// the fields of the named parameters flagged (aria-invalid and a red outline), the results
// dimmed (they belong to the last valid parameters) and the actions that would compute with
// the current parameters disabled.
function showError(err) {
  const flagged = new Set(err ? err.parameters : []);
  for (const row of document.querySelectorAll('.param')) {
    const bad = flagged.has(row.dataset.key), field = row.querySelector('input.value');
    row.classList.toggle('invalid', bad);
    if (bad) {
      field.setAttribute('aria-invalid', 'true');
      field.setAttribute('aria-describedby', 'status');
    } else {
      field.removeAttribute('aria-invalid');
      field.removeAttribute('aria-describedby');
    }
  }
  $('results').classList.toggle('stale', !!err);
  $('results').setAttribute('aria-disabled', err ? 'true' : 'false');
  for (const id of ['dl-params', 'dl-spectrum-json', 'dl-spectrum-csv', 'dl-profile-json', 'dl-profile-csv', 'export-run', 'fit'])
    $(id).disabled = !!err;
  if (err) {
    $('status').textContent = err.message;
    $('status').className = 'error';
  }
}

// --- Updates ----------------------------------------------------------------------------------

let pending = false;  // an update is scheduled (window.skinPending: for tests)
function scheduleUpdate() {
  if (pending) return;
  pending = true;
  window.skinPending = true;
  requestAnimationFrame(() => { pending = false; window.skinPending = false; update(); });
}

// One full update: spectrum (R_d, layer coefficients, colour) and the RGB profile at 256 radii,
// through the module, then the page redrawn. The time covers both computations and the drawing.
function update() {
  // A field that holds no number: nothing is computed, the error is shown.
  const invalid = fieldError();
  if (invalid) {
    state.modelError = null;
    showError(invalid);
    return;
  }
  const t0 = performance.now();
  let spectrum, profile, color;
  try {
    // A profile the solver would solve per wavelength (seconds each here) waits for the button.
    let pendingProfile;
    ({ spectrum, profile, color, profile_pending: pendingProfile } =
      runJson('update', request({ illuminant: state.illuminant, solve_profile: state.solveProfile })));
    state.solveProfile = false;
    state.profilePending = pendingProfile || null;
  } catch (e) {
    // The model's refusal: the fields of the parameters it names (by key, from its reply).
    state.modelError = { message: e.message, parameters: e.parameters || [] };
    showError(state.modelError);
    return;
  }
  const tModel = performance.now() - t0;
  state.modelError = null;
  showError(null);
  state.spectrum = spectrum;
  state.profile = profile;
  state.color = color || null;
  drawColour();
  drawSpectrum();
  drawProfile();
  drawCoefficients();
  const ms = performance.now() - t0;
  state.timings.push(ms);
  state.modelTimings.push(tModel);
  state.updates += 1;
  // This update, and the median and 10-90 % spread of the last 100.
  const quantiles = (a) => { const s = a.slice(-100).sort((x, y) => x - y); return [0.5, 0.1, 0.9].map((f) => s[Math.min(s.length - 1, Math.floor(f * s.length))].toFixed(1)); };
  const [m, lo, hi] = quantiles(state.timings);
  $('timing').textContent = `${ms.toFixed(1)} ms (model ${tModel.toFixed(1)} ms); median ${m} ms, 10–90 % ${lo}–${hi} ms ` +
    `of the last ${Math.min(state.timings.length, 100)} (model median ${quantiles(state.modelTimings)[0]} ms)`;
  const warn = !profile || profile.validity.profile ? '' : ` Profile outside the solver's validated range: ${profile.validity.reason}`;
  $('status').textContent = `Ready. ${state.solver} solver.${warn}`;
  $('status').className = warn ? 'error' : '';
  scheduleStrip();
  checkExport();
}

// The colour under the chosen illuminant: the spectrum's own (D65) or the update's "color"
// document, as skin color --illuminant NAME.
function drawColour() {
  const name = state.color ? state.color.illuminant : 'D65';
  const c = state.color ? state.color.color : state.spectrum.color;
  $('xyz-illuminant').textContent = name;
  $('adaptation').textContent = state.color ? `Under ${name}: sRGB and hex after the Bradford adaptation ${name} → D65; CIELAB relative to ${name}'s white.` : '';
  $('swatch').style.background = c.hex;
  $('hex').textContent = c.hex;
  $('srgb8').textContent = c.srgb8.join(' ');
  $('srgb-linear').textContent = c.srgb_linear.map(num).join('  ');
  $('lab').textContent = c.lab.map(num).join('  ');
  $('xyz').textContent = c.XYZ.map(num).join('  ');
}

let shownCells = [];  // the text of each coefficient cell, by column: only changed cells are written
function drawCoefficients() {
  // The rows are made once per grid; an update rewrites the text of the cells that changed (a
  // slider moves some columns only: melanin leaves the dermis alone).
  const s = state.spectrum, table = $('coefficients');
  const columns = [s.wavelength_nm, s.R_d, s.epidermis.sigma_a, s.epidermis.sigma_s_prime, s.dermis.sigma_a, s.dermis.sigma_s_prime];
  if (table.rows.length !== s.wavelength_nm.length + 1) {
    table.innerHTML = '<tr><th>wavelength_nm</th><th>R_d</th><th>epidermis.sigma_a</th><th>epidermis.sigma_s_prime</th><th>dermis.sigma_a</th><th>dermis.sigma_s_prime</th></tr>' +
      '<tr><td></td><td></td><td></td><td></td><td></td><td></td></tr>'.repeat(s.wavelength_nm.length);
    shownCells = columns.map(() => []);
  }
  for (let c = 0; c < columns.length; c++) {
    const shown = shownCells[c], column = columns[c];
    for (let i = 0; i < column.length; i++) {
      const text = c === 0 ? String(column[i]) : num(column[i]);
      if (shown[i] !== text) table.rows[i + 1].cells[c].textContent = shown[i] = text;
    }
  }
}

// --- Plots (SVG) ------------------------------------------------------------------------------

const W = 640, H = 300, M = { l: 56, r: 12, t: 10, b: 34 };

function axes(svg, x0, x1, y0, y1, logX, logY, xLabel, yLabel) {
  const tx = (x) => M.l + (W - M.l - M.r) * (logX ? Math.log10(x / x0) / Math.log10(x1 / x0) : (x - x0) / (x1 - x0));
  const ty = (y) => H - M.b - (H - M.t - M.b) * (logY ? Math.log10(y / y0) / Math.log10(y1 / y0) : (y - y0) / (y1 - y0));
  let g = `<rect x="${M.l}" y="${M.t}" width="${W - M.l - M.r}" height="${H - M.t - M.b}" fill="none" stroke="#999"/>`;
  const ticks = (a, b, log) => {
    if (log) {
      const out = [];
      for (let e = Math.ceil(Math.log10(a)); e <= Math.floor(Math.log10(b)); e++) out.push(10 ** e);
      return out;
    }
    const step = 10 ** Math.floor(Math.log10((b - a) / 4));
    const s = [1, 2, 5, 10].map((k) => k * step).find((k) => (b - a) / k <= 8);
    const out = [];
    for (let v = Math.ceil(a / s) * s; v <= b + 1e-12; v += s) out.push(+v.toPrecision(6));
    return out;
  };
  for (const x of ticks(x0, x1, logX))
    g += `<line x1="${tx(x)}" x2="${tx(x)}" y1="${H - M.b}" y2="${H - M.b + 4}" stroke="#999"/><text x="${tx(x)}" y="${H - M.b + 15}" text-anchor="middle">${x}</text>`;
  for (const y of ticks(y0, y1, logY))
    g += `<line x1="${M.l - 4}" x2="${M.l}" y1="${ty(y)}" y2="${ty(y)}" stroke="#999"/><text x="${M.l - 6}" y="${ty(y) + 4}" text-anchor="end">${logY ? y.toExponential(0) : y}</text>`;
  g += `<text x="${(M.l + W - M.r) / 2}" y="${H - 4}" text-anchor="middle">${xLabel}</text>`;
  g += `<text x="12" y="${(M.t + H - M.b) / 2}" transform="rotate(-90 12 ${(M.t + H - M.b) / 2})" text-anchor="middle">${yLabel}</text>`;
  svg.innerHTML = g;
  return { tx, ty };
}

function path(xs, ys, tx, ty, colour, extra = '') {
  let d = '';
  xs.forEach((x, i) => { if (Number.isFinite(ys[i])) d += `${d ? 'L' : 'M'}${tx(x).toFixed(1)},${ty(ys[i]).toFixed(1)}`; });
  return `<path d="${d}" fill="none" stroke="${colour}" stroke-width="1.8" ${extra}/>`;
}

function drawSpectrum() {
  const s = state.spectrum, svg = $('spectrum-plot');
  const x0 = s.wavelength_nm[0], x1 = s.wavelength_nm[s.wavelength_nm.length - 1];
  let yMax = Math.max(...s.R_d);
  const m = measuredSeries();
  if (m) yMax = Math.max(yMax, ...m.R);
  yMax = Math.max(0.1, Math.ceil(yMax * 10 + 0.5) / 10);
  const { tx, ty } = axes(svg, x0, x1, 0, yMax, false, false, 'wavelength [nm]', 'R_d');
  let g = path(s.wavelength_nm, s.R_d, tx, ty, '#b33');
  if (m) {
    const inside = m.wavelength_nm.map((l, i) => [l, m.R[i]]).filter(([l, r]) => l >= x0 && l <= x1 && Number.isFinite(r));
    g += inside.map(([l, r]) => `<circle cx="${tx(l).toFixed(1)}" cy="${ty(r).toFixed(1)}" r="1.8" fill="#222"/>`).join('');
    if (state.fit) g += path(state.fit.fitted.wavelength_nm, state.fit.fitted.R, tx, ty, '#36c', 'stroke-dasharray="5 3"');
  }
  g += `<text x="${W - M.r - 4}" y="${M.t + 14}" text-anchor="end">— model${m ? ' · measured' + (state.fit ? ' - - fit' : '') : ''}</text>`;
  svg.insertAdjacentHTML('beforeend', g);
}

function drawProfile() {
  const p = state.profile, svg = $('profile-plot');
  const pending = state.profilePending;
  $('profile-pending').hidden = !pending;
  if (pending) {
    // Off the accurate solver's skin table, or sfd: each wavelength is solved, ~2 s here.
    const minutes = Math.max(1, Math.round(pending.wavelengths * 2 / 60));
    const why = pending.solver === 'sfd' ? 'sfd reads no table'
      : 'they are off its table of skin profiles: another g, index or dermis scattering, or an epidermis outside its thickness range';
    $('profile-pending-text').textContent =
      `The ${pending.solver} profile of these parameters is solved at ${pending.wavelengths} of ${pending.of} ` +
      `wavelengths (${why}): about ${minutes} min in this page. The spectrum and colour above are exact.`;
    svg.innerHTML = '';
    return;
  }
  const all = [...p.R.r, ...p.R.g, ...p.R.b].filter((v) => v > 0);
  const yMax = 10 ** Math.ceil(Math.log10(Math.max(...all)));
  const yMin = Math.max(10 ** Math.floor(Math.log10(Math.min(...all))), yMax * 1e-12);
  const r = p.r_mm;
  const { tx, ty } = axes(svg, r[0], r[r.length - 1], yMin, yMax, true, true, 'r [mm]', 'R(r) [1/mm²]');
  const pos = (ys) => ys.map((v) => (v > yMin ? v : NaN));
  svg.insertAdjacentHTML('beforeend', path(r, pos(p.R.r), tx, ty, '#c22') + path(r, pos(p.R.g), tx, ty, '#2a2') + path(r, pos(p.R.b), tx, ty, '#23c'));
}

// --- Melanin strip ----------------------------------------------------------------------------

const STRIP_MELANIN = Array.from({ length: 11 }, (_, i) => +(0.05 * i).toFixed(2));
let stripTimer = 0;
function scheduleStrip() {
  // Every parameter but melanin decides the strip; it is recomputed after the update, off the
  // update's time, when one of them changed.
  const { melanin, ...rest } = state.values;
  const key = JSON.stringify([rest, state.solver, state.wide]);
  drawStrip();
  if (key === state.stripKey) return;
  clearTimeout(stripTimer);
  stripTimer = setTimeout(() => {
    try {
      state.strip = runJson('melanin_strip', request({ melanin: STRIP_MELANIN }));
      state.stripKey = key;
      drawStrip();
    } catch (e) { /* shown by the next update */ }
  }, 60);
}

function drawStrip() {
  if (!state.strip) return;
  const m = state.values.melanin;
  const nearest = STRIP_MELANIN.reduce((a, b) => (Math.abs(b - m) < Math.abs(a - m) ? b : a));
  $('strip').innerHTML = state.strip.map((s) =>
    `<div style="background:${s.color.hex}" title="melanin ${s.melanin}: ${s.color.hex}" class="${s.melanin === nearest ? 'current' : ''}">${s.melanin}</div>`).join('');
}

// --- Measured spectrum: drop, overlay, fit ----------------------------------------------------

function measuredSeries() {
  const m = state.measured;
  if (!m) return null;
  const col = m.columns.find((c) => c.name === $('measured-column').value) || m.columns[0];
  return { wavelength_nm: m.wavelength_nm, R: col.R, name: col.name };
}

function loadMeasured(file, text) {
  try {
    const s = runJson('spectra', { csv: text, file });
    state.measured = { file: s.file, csv: text, wavelength_nm: s.wavelength_nm, columns: s.columns };
  } catch (e) {
    $('status').textContent = e.message;
    $('status').className = 'error';
    return;
  }
  state.fit = null;
  $('measured').hidden = false;
  $('measured-file').textContent = state.measured.file;
  $('measured-column').innerHTML = state.measured.columns.map((c) => `<option>${c.name}</option>`).join('');
  $('fit-result').textContent = '';
  drawSpectrum();
}

function fitMeasured() {
  const m = state.measured;
  const column = m.columns.length > 1 ? $('measured-column').value : '';
  try {
    state.fit = runJson('fit', request({ csv: m.csv, file: m.file, column }));
  } catch (e) {
    $('fit-result').textContent = e.message;
    $('fit-result').className = 'error';
    return;
  }
  const f = state.fit;
  $('fit-result').className = '';
  $('fit-result').textContent = f.free.map((k) => `${k} ${num(f.parameters[k])} ± ${num(f.uncertainty[k])}`).join(', ') + `; RMS ${num(f.rms)}`;
  state.values = { ...f.parameters };
  showValues();
  scheduleUpdate();
}

function setUpDrop() {
  const body = document.body;
  body.addEventListener('dragover', (e) => { e.preventDefault(); body.classList.add('dragging'); });
  body.addEventListener('dragleave', () => body.classList.remove('dragging'));
  body.addEventListener('drop', async (e) => {
    e.preventDefault();
    body.classList.remove('dragging');
    const file = e.dataTransfer.files[0];
    if (file) loadMeasured(file.name, await file.text());
  });
  $('measured-column').addEventListener('change', () => { state.fit = null; $('fit-result').textContent = ''; drawSpectrum(); });
  $('fit').addEventListener('click', fitMeasured);
  $('solve-profile').addEventListener('click', () => {
    state.solveProfile = true;
    $('status').textContent = 'Solving the profile…';
    $('status').className = '';
    setTimeout(update, 30);  // let the status show before the page is busy
  });
}

// --- Downloads --------------------------------------------------------------------------------

function download(name, text, type) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

function setUpDownloads() {
  // The parameters as `skin --params FILE.json` reads them: an object of parameter keys.
  $('dl-params').addEventListener('click', () => download('skin-params.json', JSON.stringify(state.values, null, 2) + '\n', 'application/json'));
  $('dl-spectrum-json').addEventListener('click', () => download('spectrum.json', run('spectrum', request()), 'application/json'));
  $('dl-spectrum-csv').addEventListener('click', () => download('spectrum.csv', run('spectrum', request({ format: 'csv' })), 'text/csv'));
  $('dl-profile-json').addEventListener('click', () => download('profile.json', run('profile', request({ rgb: true })), 'application/json'));
  $('dl-profile-csv').addEventListener('click', () => download('profile.csv', run('profile', request({ rgb: true, format: 'csv' })), 'text/csv'));
}

// --- Export (skin export --target T) ---------------------------------------------------------

// The files of the chosen target for the current parameters, as links (each file its own
// download, byte for byte what `skin export --target T` writes), and the fit's error. The links
// stay valid until the parameters, the solver or the target change.
function exportKey() { return JSON.stringify([request(), $('export-target').value]); }

function runExport() {
  for (const a of document.querySelectorAll('#export-files a')) URL.revokeObjectURL(a.href);
  $('export-files').innerHTML = '';
  let e;
  try {
    e = runJson('export', request({ target: $('export-target').value }));
  } catch (err) {
    $('export-result').textContent = err.message;
    $('export-result').className = 'error';
    return;
  }
  const r = e.report, pct = (v) => `${v >= 0 ? '+' : ''}${(100 * v).toFixed(1)}%`;
  $('export-result').className = r.representable ? 'muted' : 'error';
  $('export-result').textContent = `${e.target}: colour dE2000 ${r.delta_e_2000.toFixed(2)}; profile L1 r/g/b ` +
    `${['r', 'g', 'b'].map((c) => r.profile_l1[c].toFixed(2)).join('/')}; mean radius ` +
    `${['r', 'g', 'b'].map((c) => r.mean_radius_mm[c].toPrecision(3)).join('/')} mm (target ` +
    `${['r', 'g', 'b'].map((c) => pct(r.mean_radius_error[c])).join('/')})` +
    (r.representable ? '' : `. ${r.notes[0]}`);
  for (const f of e.files) {
    const li = document.createElement('li'), a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([f.content], { type: 'application/octet-stream' }));
    a.download = f.name;
    a.textContent = f.name;
    li.appendChild(a);
    li.insertAdjacentText('beforeend', ` (${f.content.length} bytes)`);
    $('export-files').appendChild(li);
  }
  for (const name of e.images) {
    const li = document.createElement('li');
    li.className = 'muted';
    li.textContent = `${name}: written by the skin command only (no OpenEXR in the browser)`;
    $('export-files').appendChild(li);
  }
  state.export = e;
  state.exportKey = exportKey();
}

function checkExport() {
  // After a change the links no longer hold the current skin: they are removed.
  if (!state.export || state.exportKey === exportKey()) return;
  for (const a of document.querySelectorAll('#export-files a')) URL.revokeObjectURL(a.href);
  $('export-files').innerHTML = '';
  $('export-result').textContent = 'The parameters changed: Export again for files of the current skin.';
  $('export-result').className = 'muted';
  state.export = null;
}

function setUpExport() {
  for (const t of runJson('targets', {})) {
    const o = document.createElement('option');
    o.value = t.name;
    o.textContent = `${t.name} (${t.extension})`;
    o.title = t.description;
    $('export-target').appendChild(o);
  }
  $('export-run').addEventListener('click', runExport);
  $('export-target').addEventListener('change', checkExport);
}

// --- Start ------------------------------------------------------------------------------------

createSkinModule().then((module) => {
  state.module = module;
  state.table = runJson('parameters', {});
  state.presets = runJson('presets', {});
  buildControls();
  setUpDrop();
  setUpDownloads();
  setUpExport();
  applyPreset('caucasian');
  window.skinReady = true;
}).catch((e) => { $('status').textContent = 'The model failed to load: ' + e; $('status').className = 'error'; });
