// The page's parameter fields under bad input, in headless Chromium (puppeteer-core, as
// browser.test.js). Into every field, typed as a user types: nothing (the field cleared), NaN,
// abc, 1e999, -1e999, "-", and a finite number outside the parameter's range. After each, the
// page must show the error and compute nothing with it:
//   - that field and no other is flagged (aria-invalid="true", a visible outline),
//   - the status line is the one error line naming the parameter as the model's messages do
//     ("melanin (C_m)") and its allowed range, never "Ready",
//   - the results are dimmed, and the downloads and the export are disabled,
//   - the colour shown (hex, sRGB) and the coefficient table are those from before;
//   - text that is not a number never reaches the module (no call at all); the number outside
//     the range reaches it and is refused by it (the fields flagged by the keys of its reply).
// Typing the previous value back must bring the page back: no field flagged, results not
// dimmed, "Ready", the same colour. Then two fields at once (both flagged, fixing one leaves the
// other's error), the constraint between two parameters (melanin + epidermal_hemoglobin <= 1:
// both flagged), and a slider moved after bad text (the field's error cleared).
// Run: node web/test/inputs.test.js (after scripts/web.sh and npm ci in web/). Screenshot of two
// fields in error: build-web/screenshots/page-input-error.png.
'use strict';
const fs = require('fs');
const path = require('path');
const { ROOT, fail, openPage } = require('./common');

const SHOTS = path.join(ROOT, 'build-web', 'screenshots');

const BAD_TEXT = ['', 'NaN', 'abc', '1e999', '-1e999', '-'];

async function main() {
  const t0 = Date.now();
  const opened = await openPage('input test');
  if (!opened) return;
  const { page, url, close } = opened;
  let checks = 0;
  try {
    await page.goto(url);
    await page.waitForFunction('window.skinReady === true', { timeout: 120000 });
    // Loaded: the first update and the melanin strip (computed after it) are done.
    await page.waitForFunction('window.skinState.updates >= 1 && !window.skinPending && window.skinState.strip !== null');
    // The coefficient table (collapsed as the page opens) shown: its first row is checked too.
    await page.click('#coefficients-details summary');
    await page.waitForFunction(() => document.querySelectorAll('#coefficients tr').length > 1);
    // Every call into the module, logged: the page computes through state.module.run alone (the
    // module itself is left as it is: embind's dispatch reads its own Module.run).
    await page.evaluate(() => {
      const m = window.skinState.module;
      window.skinCalls = [];
      window.skinState.module = { run: (command, request) => { window.skinCalls.push([command, request]); return m.run(command, request); } };
    });
    const table = await page.evaluate(() => window.skinState.table);
    const tLoaded = Date.now();

    // What the page shows, once it has no update pending and has made at least `updates`.
    const shown = (updates = 0) => page.evaluate(async (n) => {
      // Bounded: a wait that cannot end is reported as such (not as a protocol timeout).
      const deadline = performance.now() + 30000;
      // (and the background work of the last update done: its module calls are not the next case's)
      while (window.skinPending || window.skinState.updates < n || (window.skinBackgroundPending && window.skinBackgroundPending())) {
        if (performance.now() > deadline) throw new Error(`waited 30 s for update ${n}; the page made ${window.skinState.updates}, pending ${window.skinPending}`);
        await new Promise((r) => requestAnimationFrame(r));
      }
      const fields = [...document.querySelectorAll('#parameters input.value')];
      return {
        flagged: fields.filter((f) => f.getAttribute('aria-invalid') === 'true').map((f) => f.id.replace(/^param-/, '')),
        outlined: fields.filter((f) => getComputedStyle(f).outlineStyle === 'solid').map((f) => f.id.replace(/^param-/, '')),
        rowsInvalid: [...document.querySelectorAll('.param.invalid')].map((r) => r.dataset.key),
        status: document.getElementById('status').textContent,
        statusClass: document.getElementById('status').className,
        dimmed: document.getElementById('results').classList.contains('stale'),
        opacity: Number(getComputedStyle(document.getElementById('results')).opacity),
        disabled: ['dl-params', 'dl-spectrum-json', 'dl-spectrum-csv', 'dl-profile-json', 'dl-profile-csv', 'export-run']
          .filter((id) => document.getElementById(id).disabled),
        hex: document.getElementById('hex').textContent,
        srgb8: document.getElementById('srgb8').textContent,
        swatch: document.getElementById('swatch').style.background,
        firstRow: [...document.querySelectorAll('#coefficients tr')][1].textContent,
        updates: window.skinState.updates,
        calls: window.skinCalls.length,
        commands: window.skinCalls.map((c) => c[0]),
      };
    }, updates);
    // Types `text` into the field of `key` as a user does: the old text selected and replaced,
    // Tab to leave the field (shown() then waits for the page's update).
    const type = async (key, text) => {
      await page.evaluate((id) => { const f = document.getElementById(id); f.focus(); f.select(); }, `param-${key}`);
      if (text === '') await page.keyboard.press('Backspace');
      else await page.keyboard.type(text);
      await page.keyboard.press('Tab');
    };
    const normal = (s, before, what) => {
      const failures = [];
      if (s.flagged.length || s.rowsInvalid.length || s.outlined.length) failures.push(`flagged ${s.flagged} / ${s.rowsInvalid} / outlined ${s.outlined}`);
      if (s.dimmed || s.opacity !== 1) failures.push(`results dimmed (opacity ${s.opacity})`);
      if (!s.status.startsWith('Ready.') || s.statusClass === 'error') failures.push(`status "${s.status}"`);
      if (s.disabled.length) failures.push(`disabled ${s.disabled}`);
      if (before && (s.hex !== before.hex || s.srgb8 !== before.srgb8 || s.firstRow !== before.firstRow)) failures.push(`colour ${s.hex} != ${before.hex}`);
      fail(failures, what);
      checks += 1;
      return failures.length === 0;
    };
    // The page in error about the fields `keys`, with `before`'s results still shown.
    const inError = (s, before, keys, what, { called, message } = {}) => {
      const failures = [];
      const same = (a, b) => JSON.stringify([...a].sort()) === JSON.stringify([...b].sort());
      if (!same(s.flagged, keys)) failures.push(`aria-invalid on [${s.flagged}], expected [${keys}]`);
      if (!same(s.rowsInvalid, keys) || !same(s.outlined, keys)) failures.push(`styled [${s.rowsInvalid}] outlined [${s.outlined}], expected [${keys}]`);
      if (!s.dimmed || !(s.opacity < 1)) failures.push(`results not dimmed (opacity ${s.opacity})`);
      if (s.status.includes('Ready') || s.statusClass !== 'error') failures.push(`status "${s.status}" (${s.statusClass})`);
      if (s.status.includes('\n')) failures.push('status has more than one line');
      if (message && !message.test(s.status)) failures.push(`status "${s.status}" does not match ${message}`);
      if (s.disabled.length !== 6) failures.push(`only [${s.disabled}] disabled`);
      if (s.hex !== before.hex || s.srgb8 !== before.srgb8 || s.swatch !== before.swatch || s.firstRow !== before.firstRow)
        failures.push(`results changed: ${before.hex} -> ${s.hex}`);
      if (s.updates !== before.updates) failures.push('an update was computed');
      const newCalls = s.commands.slice(before.calls);
      if (!called && newCalls.length) failures.push(`module called: ${newCalls}`);
      if (called && !(newCalls.length === 1 && newCalls[0] === 'update')) failures.push(`module calls ${newCalls}, expected one refused update`);
      fail(failures, what);
      checks += 1;
      return failures.length === 0;
    };
    const escape = (s) => s.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
    // The parameter as the model's messages name it, and its range.
    const label = (p) => escape(p.flag.replace(/^--/, '') + (p.symbol ? ` (${p.symbol})` : ''));
    const range = (p) => escape(`${p.min_exclusive ? '(' : '['}${p.min === null ? '-inf' : p.min}, ${p.max === null ? 'inf' : p.max}${p.max_exclusive ? ')' : ']'}`);

    const start = await shown();
    normal(start, null, 'the page after loading');
    let failed = 0;
    for (const p of table) {
      const original = String(await page.evaluate((k) => window.skinState.values[k], p.key));
      // Text that is no number; then a finite number below the range (every minimum is finite).
      const cases = [...BAD_TEXT.map((text) => ({ text })), { text: String(p.min - 1), called: true }];
      for (const c of cases) {
        const before = await shown();
        if (process.env.SKIN_TEST_VERBOSE) console.log(`${p.key} = ${JSON.stringify(c.text)} (then ${original})`);
        await type(p.key, c.text);
        const what = `${p.key} = ${JSON.stringify(c.text)}`;
        // The page's own line for text (empty, not a number, beyond a double); the model's for
        // the number out of range ("params: melanin (C_m) = -1 is out of range: ...").
        const message = c.called
          ? new RegExp(`^params: ${label(p)} = ${escape(c.text)}( \\S+)? is out of range: `)
          : new RegExp(`^${label(p)} (is empty|= .* is (not a number|out of range)): allowed range is ${range(p)}$`);
        if (!inError(await shown(), before, [p.key], what, { called: c.called, message })) failed += 1;
        await type(p.key, original);
        if (!normal(await shown(before.updates + 1), before, `${what}, then ${original} again`)) failed += 1;
      }
    }
    console.log(`every field (${table.length}), typed ${BAD_TEXT.map((t) => JSON.stringify(t)).join(' ')} and a number below ` +
                `its range: ${failed === 0 ? 'flagged alone, results dimmed and unchanged, nothing computed; restored' : failed + ' FAILED'}`);

    // Two fields at once: both flagged, the first named; fixing it leaves the other's error.
    {
      const before = await shown();
      await type('melanin', 'abc');
      await type('g', '');
      inError(await shown(), before, ['melanin', 'g'], 'melanin and g', { message: /^melanin \(C_m\) = 'abc' is not a number: allowed range is \[0, 1\] \(and 1 more field\)$/ });
      fs.mkdirSync(SHOTS, { recursive: true });
      await page.screenshot({ path: path.join(SHOTS, 'page-input-error.png') });
      await type('melanin', String(await page.evaluate(() => window.skinState.values.melanin)));
      inError(await shown(), before, ['g'], 'g still empty', { message: /^g is empty: allowed range is \(-1, 1\)$/ });
      await type('g', String(await page.evaluate(() => window.skinState.values.g)));
      normal(await shown(before.updates + 1), before, 'melanin and g fixed');
    }
    // The model's constraint between two parameters: both named by its reply, both flagged.
    {
      const before = await shown();
      const values = await page.evaluate(() => ({ ...window.skinState.values }));
      await type('melanin', '0.6');
      const mid = await shown(before.updates + 1);
      await type('epidermal_hemoglobin', '0.5');
      inError(await shown(), mid, ['melanin', 'epidermal_hemoglobin'], 'melanin + epidermal_hemoglobin > 1',
              { called: true, message: /^melanin \+ epidermal-hemoglobin = 1\.1 is out of range/ });
      // One field at a time: two changes within one animation frame make one update.
      await type('epidermal_hemoglobin', String(values.epidermal_hemoglobin));
      const back = await shown(mid.updates + 1);
      await type('melanin', String(values.melanin));
      normal(await shown(back.updates + 1), before, 'melanin and epidermal_hemoglobin restored');
    }
    // The slider after bad text: the field takes the slider's number, the error is gone.
    {
      const before = await shown();
      await type('hemoglobin', 'x');
      inError(await shown(), before, ['hemoglobin'], 'hemoglobin = "x"');
      await page.focus('#s-hemoglobin');
      await page.keyboard.press('ArrowRight');
      const s = await shown(before.updates + 1);
      const field = await page.evaluate(() => [document.getElementById('param-hemoglobin').value, document.getElementById('s-hemoglobin').getAttribute('aria-valuetext'), window.skinState.values.hemoglobin]);
      normal(s, null, 'hemoglobin slider moved after bad text');
      if (field[0] !== field[1] || Number(field[0]) !== field[2]) fail([`field ${field[0]}, slider's value ${field[1]}, value ${field[2]}`], 'slider after bad text');
    }
    console.log(`input test: ${checks} checks in ${((Date.now() - t0) / 1000).toFixed(1)} s (the page loaded in ${((tLoaded - t0) / 1000).toFixed(1)} s)`);
  } finally {
    await close();
  }
}

main().catch((e) => { console.error(e); process.exitCode = 1; });
