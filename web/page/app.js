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
  scales: {},       // each parameter's slider scale (sliderScale), by key
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
  urlErrors: [],    // messages about the URL's values that are no parameter's (unknown names, solver, ...)
  fitLimits: null,  // the fit's thresholds ({good_fit_rms}), from the module
  atBound: [],      // keys of the fitted parameters that ended on a bound of the last fit
  lights: {},       // each illuminant's colour as a light in linear sRGB (luminance 1), by name
  viewLights: { fill: true, back: true },  // the 3D view's fill and back light on (the key always)
  kernels: null,    // the realtime export's document the 3D view's subsurface uses
  kernelsKey: '',   // the request it was computed for
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

// Slider scales. A slider has STEPS positions; the chromophore concentrations (and the overall
// scattering scale) span decades, so their sliders are logarithmic above a knee and linear
// below it, v = min + knee (exp(t ln(1 + (max - min) / knee)) - 1) for t from 0 to 1: the left
// end is the minimum itself (0: no such chromophore), and the presets' melanin (0.0005 to 0.5)
// spreads over the slider instead of its first 3 px. Each knee is about the smallest amount
// that changes the colour visibly. The other parameters are linear. A slider's value is
// rounded to 4 significant digits (log) and written to the number field, which holds the value
// exactly; a number typed into the field moves the slider to its nearest position.
const STEPS = 1000;
const LOG_KNEE = { melanin: 3e-4, hemoglobin: 1e-3, epidermal_hemoglobin: 1e-3, beta_carotene: 0.1, bilirubin: 1, scattering_scale: 0.01 };
function sliderScale(p) {
  const { min, max } = sliderRange(p);
  const knee = LOG_KNEE[p.key];
  const clamp = (v) => Math.min(max, Math.max(min, v));
  if (knee === undefined) {
    return {
      log: false,
      value: (t) => (t >= STEPS ? max : clamp(+(min + (max - min) * t / STEPS).toPrecision(12))),
      position: (v) => Math.round(STEPS * (clamp(v) - min) / (max - min)),
    };
  }
  const span = Math.log1p((max - min) / knee);
  return {
    log: true,
    value: (t) => (t <= 0 ? min : t >= STEPS ? max : clamp(+(min + knee * Math.expm1(span * t / STEPS)).toPrecision(4))),
    position: (v) => Math.round(STEPS * Math.log1p((clamp(v) - min) / knee) / span),
  };
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
    const scale = state.scales[p.key] = sliderScale(p);
    const row = document.createElement('div');
    row.className = 'param';
    row.dataset.key = p.key;
    const unit = p.unit === '1' ? '' : ` [${p.unit}]`;
    const tip = `${p.help}${unit}; range ${rangeText(p)}; default ${p.default}; CLI ${p.flag}${p.symbol ? ' (--' + p.symbol + ')' : ''}`;
    // The field is text (inputmode decimal), not type=number: the page sees what was typed and
    // names it, where a number field hands over "" for "abc" or "1e999" alike.
    // Ids: the field is param-<key> (the page's testing contract, README), its slider s-<key>.
    row.innerHTML = `<label title="${tip}" for="param-${p.key}" id="l-${p.key}">${p.key}${p.symbol ? ' <span class="muted">' + p.symbol + '</span>' : ''}${unit}</label>` +
      `<input type="range" id="s-${p.key}" min="0" max="${STEPS}" step="1" title="${tip}" aria-labelledby="l-${p.key}"` +
      ` data-scale="${scale.log ? 'log' : 'linear'}">` +
      `<input type="text" inputmode="decimal" autocomplete="off" spellcheck="false" class="value" id="param-${p.key}" title="${tip}">`;
    box.appendChild(row);
    const slider = row.querySelector('input[type=range]'), field = row.querySelector('input.value');
    slider.addEventListener('input', () => {
      const v = String(scale.value(Number(slider.value)));
      field.value = v;
      setField(p, v, true);
    });
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
      if (item.light_srgb_linear) state.lights[item.name] = item.light_srgb_linear;
      const o = document.createElement('option');
      o.value = item.name;
      o.textContent = `${item.name}${item.default ? ' (default)' : ''}`;
      o.title = item.description;
      $(key).appendChild(o);
    }
    $(key).addEventListener('change', () => { clearUserErrors(); state[key] = $(key).value; scheduleUpdate(); });
  }
  $('wide').addEventListener('change', () => { clearUserErrors(); state.wide = $('wide').checked; scheduleUpdate(); });
}

// The slider of `p` at the position nearest `value`, its value read out as the number.
function placeSlider(p, value) {
  const slider = $('s-' + p.key);
  slider.value = state.scales[p.key].position(value);
  slider.setAttribute('aria-valuetext', String(value));
}

function showValues() {
  for (const p of state.table) {
    placeSlider(p, state.values[p.key]);
    $('param-' + p.key).value = state.values[p.key];
  }
  state.fieldErrors = {};
  for (const b of $('presets').children) b.classList.toggle('active', b.dataset.preset === state.preset);
}

function applyPreset(name) {
  clearUserErrors();
  state.preset = name;
  state.values = { ...state.presets.find((p) => p.name === name).parameters };
  showValues();
  scheduleUpdate();
}

// A field's text: a number becomes the parameter's value (the slider follows when it holds
// it); anything else is the field's error, the value stays the last valid one, and the update
// shows the error instead of computing.
function setField(p, text, fromSlider = false) {
  const { value, error } = parseField(p, text);
  clearUserErrors();
  if (error) {
    state.fieldErrors[p.key] = error;
  } else {
    delete state.fieldErrors[p.key];
    state.values[p.key] = value;
    if (fromSlider) $('s-' + p.key).setAttribute('aria-valuetext', String(value));
    else placeSlider(p, value);
  }
  scheduleUpdate(fromSlider);
}

// A change by the user: the URL's errors (they were about the state it set) and the last fit's
// bound markers (they were about the fitted values) no longer hold.
function clearUserErrors() {
  state.urlErrors = [];
  if (state.atBound.length) {
    state.atBound = [];
    for (const row of document.querySelectorAll('.param.at-bound')) row.classList.remove('at-bound');
  }
}

// The first field error in the table's order: {message, parameters: [every field in error]}.
function fieldError() {
  const keys = state.table.map((p) => p.key).filter((k) => k in state.fieldErrors);
  if (state.urlErrors.length) return { message: state.urlErrors[0], parameters: keys };
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

// --- The state in the URL ---------------------------------------------------------------------

// The page's state in the URL's fragment, so that a reload restores it and a link shares it:
// preset=NAME, solver=NAME, illuminant=NAME, range=380-780 (the wide grid), table=open (the
// coefficient table shown), and KEY=VALUE for each parameter whose value differs from the
// preset's (the number exactly as the field holds it). Written after each computed update.
function urlFragment() {
  const q = new URLSearchParams();
  q.set('preset', state.preset);
  q.set('solver', state.solver);
  q.set('illuminant', state.illuminant);
  if (state.wide) q.set('range', '380-780');
  if ($('coefficients-details').open) q.set('table', 'open');
  if (!state.viewLights.fill || !state.viewLights.back) q.set('lights', lightsText(state.viewLights));
  const preset = state.presets.find((p) => p.name === state.preset).parameters;
  for (const p of state.table) if (state.values[p.key] !== preset[p.key]) q.set(p.key, String(state.values[p.key]));
  return '#' + q.toString();
}
// The 3D view's lights as the URL writes them: the key always, then those of fill and back on.
const LIGHTS = ['key', 'key,fill', 'key,back', 'key,fill,back'];
const lightsText = (l) => ['key', ...(l.fill ? ['fill'] : []), ...(l.back ? ['back'] : [])].join(',');
function writeUrl() {
  clearTimeout(urlTimer);
  const hash = urlFragment();
  if (location.hash !== hash) history.replaceState(null, '', hash);
}
// After an update the URL is written once the page has been still for URL_DELAY ms: replacing
// the history entry costs ~3 ms of the main thread, too much for every frame of a slider drag.
const URL_DELAY = 200;
let urlTimer = 0;
function scheduleUrl() {
  clearTimeout(urlTimer);
  urlTimer = setTimeout(writeUrl, URL_DELAY);
}

// The state a URL holds (its fragment, or its query), applied to the page. A value that is not
// one of those allowed is never replaced by a default in silence: a parameter's text goes into
// its field and is refused as typed text is (the same one-line error, the field flagged); any
// other (an unknown name, solver, illuminant, preset, range or table) gets a line of the same
// form in the status, and nothing is computed until the user changes something.
function restoreFromUrl() {
  const text = location.hash.length > 1 ? location.hash.slice(1) : location.search.slice(1);
  const q = new URLSearchParams(text);
  const errors = [];
  const choice = (name, allowed, fallback) => {
    if (!q.has(name)) return fallback;
    const v = q.get(name);
    if (allowed.includes(v)) return v;
    errors.push(`URL: ${name} = '${v}' is not known: allowed values are ${allowed.join(', ')}`);
    return fallback;
  };
  const options = (id) => [...$(id).options].map((o) => o.value);
  state.preset = choice('preset', state.presets.map((p) => p.name), 'caucasian');
  state.solver = choice('solver', options('solver'), state.solver);
  state.illuminant = choice('illuminant', options('illuminant'), state.illuminant);
  state.wide = choice('range', ['400-700', '380-780'], '400-700') === '380-780';
  $('coefficients-details').open = choice('table', ['open', 'closed'], 'closed') === 'open';
  const lights = choice('lights', LIGHTS, 'key,fill,back');
  state.viewLights = { fill: lights.includes('fill'), back: lights.includes('back') };
  $('view3d-fill').checked = state.viewLights.fill;
  $('view3d-back').checked = state.viewLights.back;
  if (window.skinView3d) window.skinView3d.setLights(state.viewLights);
  $('solver').value = state.solver;
  $('illuminant').value = state.illuminant;
  $('wide').checked = state.wide;
  state.values = { ...state.presets.find((p) => p.name === state.preset).parameters };
  const texts = {};
  for (const [name, v] of q) {
    if (['preset', 'solver', 'illuminant', 'range', 'table', 'lights'].includes(name)) continue;
    const p = state.table.find((t) => t.key === name);
    if (!p) errors.push(`URL: '${name}' is not a parameter key: allowed names are preset, solver, illuminant, range, table, lights and the parameters' keys (${state.table.map((t) => t.key).join(', ')})`);
    else texts[name] = v;
  }
  showValues();
  state.urlErrors = errors;
  for (const [key, text] of Object.entries(texts)) {
    const p = state.table.find((t) => t.key === key);
    const { value, error } = parseField(p, text);
    $('param-' + key).value = text;
    if (error) state.fieldErrors[key] = error;
    else { state.values[key] = value; placeSlider(p, value); }
  }
  scheduleUpdate();
}

// --- Updates ----------------------------------------------------------------------------------

let pending = false;  // an update is scheduled (window.skinPending: for tests)
let framedSinceUpdate = true;  // an animation frame has run since the last update ended
// A slider's move (now = true) is computed and drawn at once when an animation frame has run
// since the last update, so that it shows in the next frame (the 3D view's input-to-frame time,
// web/test/head.test.js); otherwise (a second move within one frame), and for every other
// change, in the next animation frame, which takes the changes in between together: at most one
// update per frame either way. (A rule of 16 ms since the last update instead deferred a move
// that came just after a slow update's frame by a whole frame: g and eta moves then took
// 47-61 ms to the screen against 40 when computed at once.)
function scheduleUpdate(now = false) {
  if (pending) return;
  if (now && framedSinceUpdate) {
    update();
    return;
  }
  pending = true;
  window.skinPending = true;
  const run = () => {
    if (!pending) return;
    pending = false;
    window.skinPending = false;
    update();
  };
  requestAnimationFrame(run);
  // (A page whose frames stop, hidden or throttled, still updates: once, after 250 ms. A headless
  // browser's test once waited 120 s on an update scheduled for a frame that never came.)
  setTimeout(run, 250);
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
  drawView3d();
  drawSpectrum();
  drawProfile();
  if ($('coefficients-details').open) drawCoefficients();
  scheduleUrl();
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
  scheduleKernels();
  checkExport();
  framedSinceUpdate = false;
  requestAnimationFrame(() => { framedSinceUpdate = true; });
}

// --- 3D view (view3d.js) ----------------------------------------------------------------------

// The view drawn with the model's colour (linear sRGB under D65: the view's lights carry the
// illuminant, as `skin render` lights an RGB scene with it) and the surface's parameters, in this
// frame; its subsurface kernels follow once the page is still (scheduleKernels).
function drawView3d() {
  const view = window.skinView3d;
  if (!view || !state.spectrum) return;
  view.light = state.lights[state.illuminant] || [1, 1, 1];
  view.setLights(state.viewLights);
  view.update(state.spectrum.color.srgb_linear, { oiliness: state.values.oiliness, roughness: state.values.roughness, eta: state.values.eta });
}
window.skinView3dPending = () => { drawView3d(); if (state.kernels) window.skinView3d.setKernels(state.kernels); };

// The model's colour over the grid of the view's parameter maps or paint (view3d.js, mapAxes;
// the module's color_grid, the other parameters as they are): when maps are loaded, at the first
// stroke of a brush, and with the kernels after a change (with maps, of a parameter they do not
// set). Maps take ~2 s, paint alone ~0.3 s, so it is computed one hemoglobin slice per task (the
// page stays responsive; a newer request drops an older one).
let mapJob = 0;
function mapColours() {
  const view = window.skinView3d;
  if (!view) return;
  const { melanin, melanin_blend, hemoglobin, ...others } = state.values;
  const centre = { melanin, melanin_blend, hemoglobin };
  const axes = view.mapAxes(centre, 1 - (state.values.epidermal_hemoglobin || 0));
  if (!axes) return;
  const key = JSON.stringify([request(view.maps ? { params: others } : {}), axes, !!view.maps]);
  if (key === state.mapKey || key === state.mapPendingKey) return;
  const job = ++mapJob;
  state.mapPendingKey = key;
  background.add('maps');
  const colours = [];
  const t0 = performance.now();
  let slice = 0;
  const step = () => {
    if (job !== mapJob) return;
    try {
      colours.push(...runJson('color_grid', request({ ...axes, hemoglobin: [axes.hemoglobin[slice]] })).srgb_linear);
    } catch (err) {  // the parameters are refused: the next update shows why
      background.delete('maps');
      state.mapPendingKey = null;
      return;
    }
    if (++slice < axes.hemoglobin.length) { setTimeout(step, 0); return; }
    background.delete('maps');
    state.mapKey = key;
    state.mapPendingKey = null;
    state.mapMs = performance.now() - t0;
    view.setMapColours(axes, colours, centre);
  };
  setTimeout(step, 0);
}
window.skinMapColours = mapColours;

// The sum of Gaussians of the current parameters, as `skin export --target realtime` fits it
// (the module's export: ~0.1 s here, so not in the frame of a slider's move): computed once the
// page has been still for KERNEL_DELAY ms. A profile the update did not solve (profile_pending:
// seconds per wavelength) is not solved for it either: the view keeps the last kernels and says so.
const KERNEL_DELAY = 150;
let kernelTimer = 0;
// The background jobs armed (kernels, strip): window.skinBackgroundPending() for tests, which
// wait for the page to be still before they count its module calls.
const background = new Set();
window.skinBackgroundPending = () => background.size > 0;
function kernelText() {
  const k = state.kernels;
  if (!k) return 'Subsurface: not yet fitted (the irradiance unblurred).';
  const v = k.gaussians.map((g) => g.variance);
  const current = state.kernelsKey === JSON.stringify(request());
  return `Subsurface: ${v.length} Gaussians, variances ${Math.min(...v).toPrecision(2)}–${Math.max(...v).toPrecision(2)} mm² ` +
    `(skin export --target realtime${current ? '' : ', of earlier parameters: these need the profile solved'}).`;
}
function scheduleKernels() {
  clearTimeout(kernelTimer);
  background.delete('kernels');
  const key = JSON.stringify(request());
  if (key === state.kernelsKey || state.profilePending) { $('view3d-status').textContent = kernelText(); return; }
  background.add('kernels');
  kernelTimer = setTimeout(() => {
    background.delete('kernels');
    try {
      const e = runJson('export', request({ target: 'realtime' }));
      state.kernels = JSON.parse(e.files[0].content);
      state.kernelsKey = key;
      if (window.skinView3d) window.skinView3d.setKernels(state.kernels);
    } catch (err) { /* the parameters are refused: the next update shows why */ }
    mapColours();
    $('view3d-status').textContent = kernelText();
  }, KERNEL_DELAY);
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

// Each plot is drawn at the width it has on the page (viewBox = its CSS pixels), so that its text
// is the 12 px the style sheet gives it at any window width; a ResizeObserver keeps the width
// (no layout is read during an update) and redraws a plot whose width changed.
const H = 300, M = { l: 60, r: 12, t: 10, b: 38 };
let W = 640;
const plotWidths = {};
function plotWidth(svg) {
  if (!(svg.id in plotWidths)) plotWidths[svg.id] = Math.round(svg.getBoundingClientRect().width) || 640;
  return Math.max(240, plotWidths[svg.id]);
}
function watchPlotWidths() {
  const observer = new ResizeObserver((entries) => {
    let changed = false;
    for (const e of entries) {
      const w = Math.round(e.contentRect.width);
      if (w > 0 && plotWidths[e.target.id] !== w) { plotWidths[e.target.id] = w; changed = true; }
    }
    if (changed && state.spectrum) { drawSpectrum(); drawProfile(); }
  });
  for (const id of ['spectrum-plot', 'profile-plot']) observer.observe($(id));
}

// A legend in the plot's top right corner: [{label, colour, dash, dots, width}].
function legend(items) {
  const rowH = 17, w = 12 + Math.max(...items.map((i) => i.label.length)) * 6.6 + 34;
  const x = W - M.r - w - 6, y = M.t + 6;
  let g = `<g class="legend"><rect x="${x}" y="${y}" width="${w}" height="${items.length * rowH + 8}" fill="#fff" fill-opacity="0.85" stroke="#ccc"/>`;
  items.forEach((it, i) => {
    const cy = y + 12 + i * rowH;
    g += it.dots
      ? `<circle cx="${x + 20}" cy="${cy}" r="2.5" fill="${it.colour}"/>`
      : `<line x1="${x + 8}" x2="${x + 32}" y1="${cy}" y2="${cy}" stroke="${it.colour}" stroke-width="${it.width || 2}"${it.dash ? ` stroke-dasharray="${it.dash}"` : ''}/>`;
    g += `<text x="${x + 38}" y="${cy + 4}">${it.label}</text>`;
  });
  return g + '</g>';
}

function axes(svg, x0, x1, y0, y1, logX, logY, xLabel, yLabel) {
  W = plotWidth(svg);
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
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

function path(xs, ys, tx, ty, colour, extra = '', width = 1.8) {
  let d = '';
  xs.forEach((x, i) => { if (Number.isFinite(ys[i])) d += `${d ? 'L' : 'M'}${tx(x).toFixed(1)},${ty(ys[i]).toFixed(1)}`; });
  return `<path d="${d}" fill="none" stroke="${colour}" stroke-width="${width}" ${extra}/>`;
}

function drawSpectrum() {
  const s = state.spectrum, svg = $('spectrum-plot');
  const x0 = s.wavelength_nm[0], x1 = s.wavelength_nm[s.wavelength_nm.length - 1];
  let yMax = Math.max(...s.R_d);
  const m = measuredSeries();
  if (m) yMax = Math.max(yMax, ...m.R);
  yMax = Math.max(0.1, Math.ceil(yMax * 10 + 0.5) / 10);
  const { tx, ty } = axes(svg, x0, x1, 0, yMax, false, false, 'wavelength [nm]', 'R_d');
  // The model's line (wide, solid) under the fit's (narrow, dashed): after a fit the two
  // coincide, and the model shows between the dashes.
  let g = path(s.wavelength_nm, s.R_d, tx, ty, '#b33', 'class="model"', 3);
  const items = [{ label: 'model R_d (current parameters)', colour: '#b33', width: 3 }];
  if (m) {
    const inside = m.wavelength_nm.map((l, i) => [l, m.R[i]]).filter(([l, r]) => l >= x0 && l <= x1 && Number.isFinite(r));
    g += inside.map(([l, r]) => `<circle cx="${tx(l).toFixed(1)}" cy="${ty(r).toFixed(1)}" r="2" fill="#222"/>`).join('');
    items.push({ label: `measured (${m.name})`, colour: '#222', dots: true });
    if (state.fit) {
      g += path(state.fit.fitted.wavelength_nm, state.fit.fitted.R, tx, ty, '#1f4fbf', 'class="fit" stroke-dasharray="6 4"', 1.6);
      items.push({ label: 'fit', colour: '#1f4fbf', dash: '6 4', width: 1.6 });
    }
  }
  svg.insertAdjacentHTML('beforeend', g + legend(items));
}

function drawProfile() {
  const p = state.profile, svg = $('profile-plot');
  const pending = state.profilePending;
  $('profile-pending').hidden = !pending;
  if (pending) {
    // Off the accurate solver's skin table, or sfd: each wavelength is solved, ~4 s here (~2 s
    // before the solver took 8 azimuthal orders at every frequency, 2026-12-05).
    const minutes = Math.max(1, Math.round(pending.wavelengths * 4 / 60));
    const why = pending.solver === 'sfd' ? 'sfd reads no table'
      : 'they are off its table of skin profiles: g, index or dermis scattering outside its range, or an epidermis too thin, too thick or too dark for it';
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
  // Blue dashed and green dotted as well as coloured: the channels stay apart in grey.
  svg.insertAdjacentHTML('beforeend', path(r, pos(p.R.r), tx, ty, '#c22') + path(r, pos(p.R.g), tx, ty, '#1a801a', 'stroke-dasharray="2 3"') +
    path(r, pos(p.R.b), tx, ty, '#23c', 'stroke-dasharray="7 4"') +
    legend([{ label: 'R: linear sRGB red', colour: '#c22' }, { label: 'G: linear sRGB green', colour: '#1a801a', dash: '2 3' },
            { label: 'B: linear sRGB blue', colour: '#23c', dash: '7 4' }]));
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
  background.add('strip');
  stripTimer = setTimeout(() => {
    background.delete('strip');
    try {
      state.strip = runJson('melanin_strip', request({ melanin: STRIP_MELANIN }));
      state.stripKey = key;
      drawStrip();
    } catch (e) { /* shown by the next update */ }
  }, 60);
}

let shownStrip = null;  // the strip document drawn: an update only moves the marker
function drawStrip() {
  if (!state.strip) return;
  const box = $('strip');
  if (shownStrip !== state.strip) {
    // Black or white text, whichever reads better on the swatch (its sRGB luminance).
    const ink = (hex) => {
      const l = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16) / 255).map((c) => (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4));
      return 0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2] > 0.18 ? '#000' : '#fff';
    };
    box.innerHTML = state.strip.map((s) =>
      `<div style="background:${s.color.hex};color:${ink(s.color.hex)}" title="melanin ${s.melanin}: ${s.color.hex}">${s.melanin}</div>`).join('');
    shownStrip = state.strip;
  }
  const m = state.values.melanin;
  const nearest = STRIP_MELANIN.reduce((a, b) => (Math.abs(b - m) < Math.abs(a - m) ? b : a));
  [...box.children].forEach((d, i) => { const on = state.strip[i].melanin === nearest; if (d.classList.contains('current') !== on) d.classList.toggle('current', on); });
}

// --- Measured spectrum: drop, overlay, fit ----------------------------------------------------

function measuredSeries() {
  const m = state.measured;
  if (!m) return null;
  const col = m.columns.find((c) => c.name === $('measured-column').value) || m.columns[0];
  return { wavelength_nm: m.wavelength_nm, R: col.R, name: col.name };
}

// A measured spectrum, from the file picker or dropped: read and checked by the module as
// `skin fit --spectrum` reads it, so that a file the fit would refuse (reflectance in percent,
// too few samples, ...) is refused now, with the fit's message, and nothing of it is kept.
function loadMeasured(file, text) {
  try {
    const s = runJson('spectra', { csv: text, file });
    state.measured = { file: s.file, csv: text, wavelength_nm: s.wavelength_nm, columns: s.columns };
  } catch (e) {
    $('load-result').textContent = `${file} not loaded: ${e.message}`;
    $('load-result').className = 'error';
    return;
  }
  $('load-result').textContent = `Loaded ${state.measured.file}: ${state.measured.columns.length} spectr${state.measured.columns.length === 1 ? 'um' : 'a'}.`;
  $('load-result').className = 'muted';
  $('fit-warning').textContent = '';
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
  // As `skin fit` writes it: a parameter that ended on its bound is marked "(at bound)" (its
  // uncertainty is then local), here also on its row; an RMS at or above the library's limit of
  // a good fit (fit::kGoodFitRms, the measured-spectra report's) gets a warning.
  $('fit-result').className = '';
  $('fit-result').textContent = f.free.map((k) => `${k} ${num(f.parameters[k])} ± ${num(f.uncertainty[k])}${f.at_bound[k] ? ' (at bound)' : ''}`).join(', ') + `; RMS ${num(f.rms)}`;
  const limit = state.fitLimits.good_fit_rms;
  $('fit-warning').textContent = f.rms >= limit
    ? `Poor fit: the RMS residual ${f.rms.toPrecision(3)} is at or above ${limit} (a good fit's limit, as in skin fit --measured-report); ` +
      `these parameters do not reproduce the spectrum${f.free.some((k) => f.at_bound[k]) ? ', and some ended on a bound' : ''}.`
    : '';
  state.values = { ...f.parameters };
  showValues();
  clearUserErrors();
  state.atBound = f.free.filter((k) => f.at_bound[k]);
  for (const k of state.atBound) document.querySelector(`.param[data-key="${k}"]`).classList.add('at-bound');
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
    // A mesh goes to the 3D view (view3d.js), anything else is a measured spectrum.
    if (file && /\.(glb|gltf|obj)$/i.test(file.name) && window.skinView3d) window.skinView3d.loadFile(file);
    else if (file) loadMeasured(file.name, await file.text());
  });
  $('spectrum-file').addEventListener('change', async () => {
    const file = $('spectrum-file').files[0];
    if (file) loadMeasured(file.name, await file.text());
    $('spectrum-file').value = '';  // the same file chosen again loads again
  });
  $('measured-column').addEventListener('change', () => { state.fit = null; $('fit-result').textContent = ''; $('fit-warning').textContent = ''; drawSpectrum(); });
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
  state.fitLimits = runJson('fit_limits', {});
  buildControls();
  setUpDrop();
  setUpDownloads();
  setUpExport();
  // The coefficient table (151 rows x 6) is filled only while it is open.
  $('coefficients-details').addEventListener('toggle', () => {
    if (state.spectrum) drawCoefficients();
    if (state.spectrum && !fieldError() && !state.modelError) writeUrl();
  });
  // The 3D view's fill and back light (view3d.js switches them; the URL keeps them).
  for (const key of ['fill', 'back']) {
    $('view3d-' + key).addEventListener('change', () => {
      state.viewLights = { ...state.viewLights, [key]: $('view3d-' + key).checked };
      if (window.skinView3d) window.skinView3d.setLights(state.viewLights);
      if (state.spectrum && !fieldError() && !state.modelError) writeUrl();
    });
  }
  watchPlotWidths();
  restoreFromUrl();
  // A link into this page pasted into its own tab differs in its fragment only, and the browser
  // does not load the page again: its state is applied as on load. (The page's own writes use
  // history.replaceState, which fires no hashchange.) Like a user's change, it ends the last fit's
  // bound markers.
  window.addEventListener('hashchange', () => {
    clearUserErrors();
    restoreFromUrl();
  });
  window.skinReady = true;
}).catch((e) => { $('status').textContent = 'The model failed to load: ' + e; $('status').className = 'error'; });
