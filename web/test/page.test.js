// The page as a person uses it, in headless Chromium (puppeteer-core, as browser.test.js):
//   - sliders: melanin, blood and the chromophores on logarithmic scales (the presets spread
//     over the melanin slider, 1 umol/L of beta-carotene away from its left end), the number
//     field exact (a typed value is kept to the last digit, the slider moves to its nearest
//     position, a slider move writes the value it stands for);
//   - the file picker (an <input type=file> with a label): a spectrum in percent is refused when
//     it is loaded, with the fit's message; a white spectrum loads, its fit marks the
//     parameters that ended on a bound "(at bound)" (text and rows) and warns that the fit is
//     poor (RMS at or above the module's fit_limits.good_fit_rms);
//   - plots: legends (model, measured, fit; the profile's R, G, B), the fit's line dashed and
//     narrower than the model's, drawn over it; every plot text at least 11 px on screen;
//   - the state in the URL: parameters, solver, illuminant, range, table and the 3D view's lights restored on reload;
//     a bad value in the URL gives the line a bad field gives (never a silent default);
//   - layout: at 390 px and at 1280 px wide, no horizontal overflow and no two boxes overlapping;
//   - accessibility: axe-core (pinned in web/package.json) finds no violation;
//   - frame time: a Chrome trace over 40 slider updates; the median main-thread time of the
//     frame that computes and draws an update (rAF callback, style, layout, paint, commit) is
//     printed and written to build-web/screenshots/frame-time.json. The page's own part (the
//     frame less the model's computation) must stay within PAGE_BUDGET_MS; the whole frame is
//     held to SKIN_FRAME_BUDGET_MS when that is set (16 for the 16 ms target: on a shared,
//     loaded machine the model alone can take longer, so it is not held by default).
// Run: node web/test/page.test.js (after scripts/web.sh and npm ci in web/).
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { ROOT, TMP, fail, openPage } = require('./common');

const SHOTS = path.join(ROOT, 'build-web', 'screenshots');
// The page's own part of a slider update's frame (the drawing, style, layout and paint: the
// frame less the model's computation) may take this much at most. With the coefficient table
// filled on every update it was ~17 ms at load 9 on the 2-core reference machine (18.3 ms in
// one run); now ~6 ms, 11.6 ms measured once at load 7-8 with the 3D view paused. 15 ms keeps
// the old page failing and leaves room for a loaded machine.
const PAGE_BUDGET_MS = 15;
let checks = 0;
function check(failures, what) {
  fail(failures, what);
  checks += 1;
  console.log(`${failures.length === 0 ? 'ok' : 'FAILED'}: ${what}`);
}

const ready = (page) => page.waitForFunction('window.skinReady === true', { timeout: 120000 });
// Waits (bounded) for the page to have made more than `n` updates and have none pending.
const updated = (page, n) => page.waitForFunction((n) => window.skinState.updates > n && !window.skinPending, { polling: 20, timeout: 30000 }, n);
const updates = (page) => page.evaluate(() => window.skinState.updates);

// Text typed into a field as a user does (selected, replaced, Tab).
async function type(page, id, text) {
  await page.evaluate((id) => { const f = document.getElementById(id); f.focus(); f.select(); }, id);
  if (text === '') await page.keyboard.press('Backspace');
  else await page.keyboard.type(text);
  await page.keyboard.press('Tab');
}

// Horizontal overflow and overlapping boxes of the visible elements a person reads or uses.
function layoutProblems(page) {
  return page.evaluate(() => {
    const problems = [];
    const de = document.documentElement;
    if (de.scrollWidth > window.innerWidth) problems.push(`document ${de.scrollWidth} px wide in a ${window.innerWidth} px window`);
    const els = [...document.querySelectorAll('label, input, select, button, #swatch, .numbers, svg, figcaption, summary, h1, h2, header p, #status, #fit-result, #fit-warning, #load-result, #export-result, #strip, #timing')]
      .filter((e) => { const r = e.getBoundingClientRect(); return r.width > 0 && r.height > 0 && getComputedStyle(e).visibility !== 'hidden'; });
    const boxes = els.map((e) => e.getBoundingClientRect());
    const name = (e) => e.id ? `#${e.id}` : `${e.tagName.toLowerCase()}${e.className ? '.' + String(e.className).split(' ')[0] : ''}("${(e.textContent || '').trim().slice(0, 20)}")`;
    for (let i = 0; i < els.length; i++) {
      const r = boxes[i];
      if (r.right > window.innerWidth + 0.5) problems.push(`${name(els[i])} ends at ${r.right.toFixed(0)} px`);
      for (let j = i + 1; j < els.length; j++) {
        if (els[i].contains(els[j]) || els[j].contains(els[i])) continue;
        const q = boxes[j];
        const w = Math.min(r.right, q.right) - Math.max(r.left, q.left), h = Math.min(r.bottom, q.bottom) - Math.max(r.top, q.top);
        if (w > 1 && h > 1) problems.push(`${name(els[i])} overlaps ${name(els[j])} (${w.toFixed(0)}x${h.toFixed(0)} px)`);
      }
    }
    return problems;
  });
}

// Every SVG text's size on screen: its font size times the plot's scale.
function smallPlotText(page, minPx) {
  return page.evaluate((minPx) => [...document.querySelectorAll('svg text')]
    .map((t) => ({ t: t.textContent, px: parseFloat(getComputedStyle(t).fontSize) * t.ownerSVGElement.getScreenCTM().a }))
    .filter((x) => !(x.px >= minPx)).map((x) => `"${x.t}" ${x.px.toFixed(1)} px`), minPx);
}

// The frame time of slider updates, from a Chrome trace: for each update, the main-thread task
// that ran its animation frame (the page's update in requestAnimationFrame, then style, layout,
// pre-paint, paint, layerize and commit), found as the task holding a FireAnimationFrame and a
// Layout. Returns the medians of the task and of its parts, in ms.
// The 3D view is paused meanwhile (skinView3d.paused: it draws nothing): its frames are
// head.test.js's; on software WebGL they would be most of the paint and commit here.
async function frameTimes(page, slider, count) {
  await page.evaluate(() => { if (window.skinView3d) window.skinView3d.paused = true; });
  await page.focus(slider);
  await page.tracing.start({ categories: ['devtools.timeline', 'disabled-by-default-devtools.timeline', 'toplevel'] });
  for (let i = 0; i < count; i++) {
    const n = await updates(page);
    await page.keyboard.press(i < count / 2 ? 'ArrowRight' : 'ArrowLeft');
    await updated(page, n);
    await new Promise((r) => setTimeout(r, 40));  // the frame painted; no frame of the test's own
  }
  const events = JSON.parse(Buffer.from(await page.tracing.stop()).toString('utf8')).traceEvents;
  // The renderer's main thread: where the page's input events and layouts run.
  const marker = events.find((e) => (e.name === 'EventDispatch' || e.name === 'Layout') && e.ph === 'X');
  const main = marker ? marker.tid : -1;
  const onMain = events.filter((e) => e.tid === main && e.ph === 'X');
  // A frame: the task that updates the rendering (animation frame callbacks, style, layout,
  // paint), plus the slider's input event task before it when the page's update ran there (a
  // slider's move is computed at once when the last update is a frame old: app.js,
  // scheduleUpdate). Frames with neither an update nor a layout are not the slider's.
  const frames = [];
  let inputUpdate = 0;
  for (const task of onMain.filter((e) => e.name === 'ThreadControllerImpl::RunTask').sort((x, y) => x.ts - y.ts)) {
    const within = onMain.filter((e) => e.ts >= task.ts && e.ts + (e.dur || 0) <= task.ts + task.dur);
    const sum = (names) => within.filter((e) => names.includes(e.name)).reduce((a, e) => a + e.dur, 0) / 1000;
    const input = within.filter((e) => e.name === 'EventDispatch' && e.args && e.args.data && e.args.data.type === 'input');
    if (input.length && !within.some((e) => e.name === 'Layout')) {
      inputUpdate += task.dur / 1000;
      continue;
    }
    const animation = within.some((e) => e.name === 'FireAnimationFrame');
    if (!within.some((e) => e.name === 'Layout') || (!animation && inputUpdate === 0)) continue;
    frames.push({ frame: task.dur / 1000 + inputUpdate, update: sum(['FireAnimationFrame']) + inputUpdate, style_layout: sum(['UpdateLayoutTree', 'Layout']),
                  paint: sum(['PrePaint', 'Paint', 'Layerize', 'Commit']) });
    inputUpdate = 0;
  }
  const median = (k) => { const v = frames.map((f) => f[k]).sort((a, b) => a - b); return v[Math.floor(v.length / 2)]; };
  return { frames: frames.length, median_ms: median('frame'), update_ms: median('update'), style_layout_ms: median('style_layout'), paint_ms: median('paint') };
}

async function main() {
  const t0 = Date.now();
  const opened = await openPage('page test');
  if (!opened) return;
  const { page, url, close } = opened;
  try {
    await page.goto(url);
    await ready(page);
    await updated(page, 0);

    // --- Frame time, first: the page as it opens (the coefficient table collapsed) ---
    {
      await new Promise((r) => setTimeout(r, 200));  // the melanin strip computed
      await page.evaluate(() => { window.skinState.modelTimings = []; });
      const t = await frameTimes(page, '#s-melanin', 40);
      // The page's own part of a frame: the frame less the module's computation (the page's
      // measurement of the same updates), which is the model's cost, not the page's.
      const model = (await page.evaluate(() => window.skinState.modelTimings)).sort((a, b) => a - b);
      t.model_ms = model[Math.floor(model.length / 2)];
      t.page_ms = t.median_ms - t.model_ms;
      const budget = Number(process.env.SKIN_FRAME_BUDGET_MS || 0);
      const result = { ...t, loadavg: os.loadavg(), budget_ms: budget || null };
      fs.writeFileSync(path.join(SHOTS, 'frame-time.json'), JSON.stringify(result, null, 2) + '\n');
      console.log(`frame time over ${t.frames} slider updates (Chrome trace): median ${t.median_ms.toFixed(1)} ms ` +
                  `(model ${t.model_ms.toFixed(1)}, the page's own ${t.page_ms.toFixed(1)}; update ${t.update_ms.toFixed(1)}, style+layout ${t.style_layout_ms.toFixed(1)}, paint+commit ${t.paint_ms.toFixed(1)} ms; ` +
                  `load average ${os.loadavg()[0].toFixed(1)})`);
      const f = [];
      if (t.frames < 30) f.push(`only ${t.frames} frames found in the trace`);
      if (!(t.page_ms <= PAGE_BUDGET_MS)) f.push(`the page's own part of the frame, median ${t.page_ms.toFixed(1)} ms, is above ${PAGE_BUDGET_MS} ms`);
      if (budget && !(t.median_ms <= budget)) f.push(`median ${t.median_ms.toFixed(1)} ms above SKIN_FRAME_BUDGET_MS=${budget}`);
      check(f, `frame time measured from the trace; the page's own part <= ${PAGE_BUDGET_MS} ms`);
    }
    // --- Sliders ---
    {
      const failures = [];
      const logKeys = ['melanin', 'hemoglobin', 'epidermal_hemoglobin', 'beta_carotene', 'bilirubin'];
      const scales = await page.evaluate((keys) => keys.map((k) => document.getElementById('s-' + k).dataset.scale), logKeys);
      logKeys.forEach((k, i) => { if (scales[i] !== 'log') failures.push(`${k}'s slider is ${scales[i]}`); });
      // The presets' melanin on the slider (its position after the preset is applied).
      const presets = await page.evaluate(() => window.skinState.presets.map((p) => p.name));
      const at = {};
      for (const name of presets) {
        const n = await updates(page);
        await page.click(`button[data-preset="${name}"]`);
        await updated(page, n);
        at[name] = await page.evaluate(() => { const s = document.getElementById('s-melanin'); return [window.skinState.values.melanin, s.value / s.max]; });
      }
      const sorted = Object.values(at).sort((a, b) => a[0] - b[0]);
      const lowest5 = sorted.slice(0, 5);
      const spread = lowest5[4][1] - lowest5[0][1];
      if (!(spread >= 0.12)) failures.push(`the five presets of least melanin span ${(100 * spread).toFixed(1)} % of the slider`);
      if (!(sorted[sorted.length - 1][1] - sorted[0][1] >= 0.6)) failures.push('the presets span less than 60 % of the melanin slider');
      // 1 umol/L of beta-carotene (a plasma level) well away from the slider's left end.
      await type(page, 'param-beta_carotene', '1');
      const beta = await page.evaluate(() => { const s = document.getElementById('s-beta_carotene'); return s.value / s.max; });
      if (!(beta >= 0.25)) failures.push(`beta_carotene 1 umol/L at ${(100 * beta).toFixed(1)} % of its slider`);
      // The field is exact; the slider follows; a slider move writes its value.
      let n = await updates(page);
      await type(page, 'param-melanin', '0.0123456');
      await updated(page, n);
      const typed = await page.evaluate(() => [window.skinState.values.melanin, document.getElementById('param-melanin').value, Number(document.getElementById('s-melanin').value)]);
      if (typed[0] !== 0.0123456 || typed[1] !== '0.0123456') failures.push(`typed 0.0123456: value ${typed[0]}, field ${typed[1]}`);
      n = await updates(page);
      await page.focus('#s-melanin');
      await page.keyboard.press('ArrowRight');
      await updated(page, n);
      const moved = await page.evaluate(() => [window.skinState.values.melanin, document.getElementById('param-melanin').value, Number(document.getElementById('s-melanin').value), document.getElementById('s-melanin').getAttribute('aria-valuetext')]);
      if (moved[2] !== typed[2] + 1) failures.push(`slider at ${typed[2]} for 0.0123456, then ${moved[2]}`);
      if (String(moved[0]) !== moved[1] || moved[3] !== moved[1] || !(moved[0] > 0.0123456 && moved[0] < 0.0126)) failures.push(`slider step: value ${moved[0]}, field ${moved[1]}, aria-valuetext ${moved[3]}`);
      check(failures, `sliders: log scales; presets' melanin over ${(100 * (sorted[sorted.length - 1][1] - sorted[0][1])).toFixed(0)} % of the slider (lowest five over ${(100 * spread).toFixed(0)} %); beta-carotene 1 umol/L at ${(100 * beta).toFixed(0)} %; field exact`);
    }

    // --- The state in the URL ---
    {
      const failures = [];
      let n = await updates(page);
      await page.click('button[data-preset="asian"]');
      await updated(page, n);
      await type(page, 'param-hemoglobin', '0.0234567');
      await page.select('#solver', 'multipole');
      await page.select('#illuminant', 'A');
      await page.click('#wide');
      await page.click('#coefficients-details summary');
      await page.click('#view3d-back');
      await page.waitForFunction(() => window.skinState.spectrum.wavelength_nm[0] === 380 && window.skinState.color && !window.skinPending, { polling: 20 });
      // The URL is written once the page has been still for 200 ms.
      await page.waitForFunction(() => location.hash.includes('range=380-780') && location.hash.includes('table=open') && location.hash.includes('hemoglobin=0.0234567') && location.hash.includes('lights=key%2Cfill'), { polling: 50, timeout: 5000 });
      const before = await page.evaluate(() => ({ hash: location.hash, hex: document.getElementById('hex').textContent, values: window.skinState.values }));
      await page.reload();
      await ready(page);
      await updated(page, 0);
      const after = await page.evaluate(() => ({
        hex: document.getElementById('hex').textContent, values: window.skinState.values, preset: window.skinState.preset,
        solver: document.getElementById('solver').value, illuminant: document.getElementById('illuminant').value,
        wide: document.getElementById('wide').checked, table: document.getElementById('coefficients-details').open,
        rows: document.querySelectorAll('#coefficients tr').length, field: document.getElementById('param-hemoglobin').value,
        lights: [document.getElementById('view3d-fill').checked, document.getElementById('view3d-back').checked],
      }));
      if (after.hex !== before.hex || JSON.stringify(after.values) !== JSON.stringify(before.values)) failures.push(`reloaded: ${after.hex} ${JSON.stringify(after.values)} != ${before.hex} ${JSON.stringify(before.values)}`);
      if (after.preset !== 'asian' || after.solver !== 'multipole' || after.illuminant !== 'A' || !after.wide || !after.table || after.rows !== 202 || after.field !== '0.0234567' ||
          JSON.stringify(after.lights) !== '[true,false]')
        failures.push(`reloaded state ${JSON.stringify(after)}`);
      check(failures, `URL ${before.hash.slice(0, 90)}…: restored on reload`);

      // Bad values: the field's own line (the field flagged, nothing computed), or a line for the others.
      const bad = [
        ['melanin=abc', /^melanin \(C_m\) = 'abc' is not a number: allowed range is \[0, 1\]$/, ['melanin']],
        ['melanin=', /^melanin \(C_m\) is empty: allowed range is \[0, 1\]$/, ['melanin']],
        ['hemoglobin=1e999', /^hemoglobin \(C_h\) = 1e999 is out of range: allowed range is \[0, 1\]$/, ['hemoglobin']],
        ['solver=nope', /^URL: solver = 'nope' is not known: allowed values are .*accurate/, []],
        ['preset=caucasian&colour=red', /^URL: 'colour' is not a parameter key/, []],
        ['lights=all', /^URL: lights = 'all' is not known: allowed values are key, key,fill, key,back, key,fill,back$/, []],
      ];
      // The first loaded afresh; the others as a link pasted into the open tab (only the fragment
      // changes: the page applies it on hashchange, without a reload).
      let first = true, before_updates = 0;
      for (const [hash, message, flagged] of bad) {
        if (first) {
          await page.goto(`${url}#${hash}`);
          await page.reload();
          await ready(page);
          await new Promise((r) => setTimeout(r, 100));
        } else {
          before_updates = await updates(page);
          await page.goto(`${url}#${hash}`);
          await page.waitForFunction((h) => location.hash === '#' + h && !window.skinPending && document.getElementById('status').className === 'error', { polling: 20, timeout: 5000 }, hash);
          await new Promise((r) => setTimeout(r, 300));  // (an update would have run by now: 250 ms at most)
        }
        const s = await page.evaluate(() => ({
          status: document.getElementById('status').textContent, cls: document.getElementById('status').className,
          flagged: [...document.querySelectorAll('[aria-invalid="true"]')].map((f) => f.id.replace(/^param-/, '')),
          updates: window.skinState.updates, values: window.skinState.values,
        }));
        const f = [];
        if (!message.test(s.status) || s.cls !== 'error') f.push(`status "${s.status}" (${s.cls})`);
        if (JSON.stringify(s.flagged) !== JSON.stringify(flagged)) f.push(`flagged [${s.flagged}]`);
        if (s.updates !== (first ? 0 : before_updates)) f.push('computed anyway');
        first = false;
        if (hash.startsWith('melanin') && s.values.melanin === 0) f.push('melanin became 0');
        check(f, `URL #${hash}: "${s.status.slice(0, 70)}", nothing computed`);
      }
      // A good link pasted into the open tab (its fragment only) is applied and computed.
      {
        const f = [];
        n = await updates(page);
        await page.goto(`${url}#preset=african&hemoglobin=0.03`);
        await updated(page, n);
        const s = await page.evaluate(() => ({ preset: window.skinState.preset, hemoglobin: window.skinState.values.hemoglobin,
                                               cls: document.getElementById('status').className }));
        if (s.preset !== 'african' || s.hemoglobin !== 0.03 || s.cls === 'error') f.push(`state ${JSON.stringify(s)}`);
        check(f, 'a link pasted into the open tab (its fragment only): applied and computed');
      }
      // A user's change clears the URL's error and computes.
      n = await updates(page);
      await page.click('button[data-preset="caucasian"]');
      await updated(page, n);
    }

    // --- File picker, percent spectrum, fit at bounds and poor ---
    const pct = path.join(TMP, 'percent.csv'), white = path.join(TMP, 'white.csv');
    let csv = 'wavelength_nm,R\n';
    for (let l = 400; l <= 700; l += 10) csv += `${l},${(40 + 0.05 * (l - 400)).toFixed(2)}\n`;
    fs.writeFileSync(pct, csv);
    csv = 'wavelength_nm,R\n';
    for (let l = 400; l <= 700; l += 10) csv += `${l},0.9\n`;
    fs.writeFileSync(white, csv);
    {
      const picker = await page.$('input[type=file]#spectrum-file');
      const label = await page.evaluate(() => [...document.getElementById('spectrum-file').labels].map((l) => l.textContent.trim()).join(' '));
      const failures = [];
      if (!picker || !/spectrum/i.test(label)) failures.push(`file picker ${!!picker}, label "${label}"`);
      await picker.uploadFile(pct);
      await page.waitForFunction(() => document.getElementById('load-result').textContent !== '', { polling: 20 });
      const r = await page.evaluate(() => ({ text: document.getElementById('load-result').textContent, cls: document.getElementById('load-result').className,
                                             measured: window.skinState.measured, hidden: document.getElementById('measured').hidden }));
      if (!/percent\.csv not loaded: .*reflectance = 40 at 400 nm is out of range: must be within \[0, 1\] \(a percentage\? divide by 100\)/.test(r.text) || r.cls !== 'error')
        failures.push(`percent file: "${r.text}" (${r.cls})`);
      if (r.measured !== null || !r.hidden) failures.push('the percent file was kept');
      check(failures, `file picker: labelled "${label.slice(0, 40)}…"; a spectrum in percent refused on loading: "${r.text.slice(0, 110)}…"`);
    }
    {
      const failures = [];
      await (await page.$('#spectrum-file')).uploadFile(white);
      await page.waitForFunction(() => window.skinState.measured !== null, { polling: 20 });
      await page.click('#fit');
      await page.waitForFunction(() => window.skinState.fit !== null && !window.skinPending, { polling: 50, timeout: 120000 });
      await new Promise((r) => setTimeout(r, 100));
      const f = await page.evaluate(() => ({
        fit: window.skinState.fit, limit: window.skinState.module.run('fit_limits', '{}'),
        text: document.getElementById('fit-result').textContent, warning: document.getElementById('fit-warning').textContent,
        marked: [...document.querySelectorAll('.param.at-bound')].map((r) => r.dataset.key),
        after: [...document.querySelectorAll('.param.at-bound')].map((r) => getComputedStyle(r, '::after').content),
      }));
      const limit = JSON.parse(f.limit).good_fit_rms;
      const atBound = f.fit.free.filter((k) => f.fit.at_bound[k]);
      if (limit !== 0.02) failures.push(`fit_limits.good_fit_rms ${limit}`);
      if (atBound.length === 0) failures.push('the white spectrum fit ended on no bound');
      for (const k of atBound) if (!f.text.includes(`${k} `) || !new RegExp(`${k} [^,]*\\(at bound\\)`).test(f.text)) failures.push(`${k} not marked in "${f.text}"`);
      if (JSON.stringify(f.marked.sort()) !== JSON.stringify(atBound.sort())) failures.push(`rows marked [${f.marked}], at bound [${atBound}]`);
      if (!f.after.every((c) => c.includes('at bound'))) failures.push(`row markers ${f.after}`);
      if (!(f.fit.rms >= limit) || !f.warning.startsWith('Poor fit:') || !f.warning.includes(String(limit))) failures.push(`RMS ${f.fit.rms}, warning "${f.warning}"`);
      check(failures, `white spectrum fitted: at bound [${atBound}] marked; RMS ${f.fit.rms.toFixed(3)} >= ${limit}: "${f.warning.slice(0, 60)}…"`);

      // Plots: legends, the fit dashed over the wider model line, text >= 11 px.
      const plots = await page.evaluate(() => {
        const sp = document.getElementById('spectrum-plot'), pp = document.getElementById('profile-plot');
        const model = sp.querySelector('path.model'), fit = sp.querySelector('path.fit');
        const order = model && fit ? [...sp.querySelectorAll('path')].indexOf(fit) > [...sp.querySelectorAll('path')].indexOf(model) : false;
        return {
          spectrumLegend: [...sp.querySelectorAll('.legend text')].map((t) => t.textContent),
          profileLegend: [...pp.querySelectorAll('.legend text')].map((t) => t.textContent),
          profileLines: [...pp.querySelectorAll(':scope > path')].map((p) => p.getAttribute('stroke-dasharray') || 'solid'),
          fitDash: fit && fit.getAttribute('stroke-dasharray'), modelDash: model && model.getAttribute('stroke-dasharray'),
          widths: model && fit ? [Number(model.getAttribute('stroke-width')), Number(fit.getAttribute('stroke-width'))] : [],
          order,
        };
      });
      const pf = [];
      if (!(plots.spectrumLegend.some((t) => /^model/.test(t)) && plots.spectrumLegend.some((t) => /^measured/.test(t)) && plots.spectrumLegend.includes('fit'))) pf.push(`spectrum legend ${plots.spectrumLegend}`);
      if (!['R:', 'G:', 'B:'].every((c) => plots.profileLegend.some((t) => t.startsWith(c)))) pf.push(`profile legend ${plots.profileLegend}`);
      if (new Set(plots.profileLines).size !== 3) pf.push(`profile lines ${plots.profileLines}`);
      if (!plots.fitDash || plots.modelDash || !(plots.widths[0] > plots.widths[1]) || !plots.order) pf.push(`fit line ${JSON.stringify(plots)}`);
      pf.push(...(await smallPlotText(page, 11)).map((t) => `text ${t} at 1280 px`));
      check(pf, `plots: legends [${plots.spectrumLegend.join(' | ')}] [${plots.profileLegend.join(' | ')}]; fit dashed over the model; text >= 11 px`);
    }

    // --- Layout and accessibility (the measured spectrum, its fit and the coefficient table shown) ---
    fs.mkdirSync(SHOTS, { recursive: true });
    await page.evaluate(() => { document.getElementById('coefficients-details').open = true; });
    await page.waitForFunction(() => document.querySelectorAll('#coefficients tr').length > 1);
    const axeSource = fs.readFileSync(require.resolve('axe-core/axe.min.js'), 'utf8');
    for (const width of [1280, 390]) {
      await page.setViewport({ width, height: width === 390 ? 844 : 1000 });
      await new Promise((r) => setTimeout(r, 300));  // the plots redrawn at their new width
      const problems = await layoutProblems(page);
      if (width === 390) problems.push(...(await smallPlotText(page, 11)).map((t) => `text ${t}`));
      await page.screenshot({ path: path.join(SHOTS, `page-${width}.png`), fullPage: true });
      check(problems, `layout at ${width} px: no horizontal overflow, nothing overlapping (document ${await page.evaluate(() => document.documentElement.scrollWidth)} px wide)`);
      if (!(await page.evaluate(() => typeof window.axe !== 'undefined'))) await page.evaluate(axeSource);
      const violations = await page.evaluate(async () => (await window.axe.run(document)).violations
        .map((v) => `${v.id} (${v.impact}): ${v.help}: ${v.nodes.slice(0, 3).map((n) => n.target.join(' ')).join(', ')}`));
      check(violations, `axe-core at ${width} px: ${violations.length} violations`);
    }
    await page.setViewport({ width: 1280, height: 1000 });

    console.log(`page test: ${checks} checks in ${((Date.now() - t0) / 1000).toFixed(1)} s; screenshots in ${SHOTS}`);
  } finally {
    await close();
  }
}

main().catch((e) => { console.error(e); process.exitCode = 1; });
