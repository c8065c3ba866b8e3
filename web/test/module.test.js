// The built WebAssembly module (build-web/site/skin.js) against the `skin` command: for random
// parameter sets and both solvers (the accurate one on its skin table), and once for the accurate
// solver off its table (every 50 nm, three wavelengths solved in the frequency domain),
// `spectrum`, `profile --rgb` and the page's `update` (both at
// once) give the same JSON (keys, text, hex exactly; numbers to 1e-9, profiles to 1e-8), as do `color` and
// `update` under illuminants A and LED-B3 (`skin color --illuminant X`), and the spectrum fit of
// a Vrhel spectrum the same fit; `export` gives, for every target, the same files byte for byte
// as `skin export --target T`. Each part prints its wall time.
// Run: node web/test/module.test.js (after scripts/web.sh and the native build).
'use strict';
const fs = require('fs');
const path = require('path');
const { ROOT, SITE, SKIN, SPECTRA, TMP, cli, cliExport, compareExport, compare, rng, randomParameters, fail, lab, deltaE2000 } = require('./common');

const TOL = 1e-9;
// Profile values below 1e-6 of the profile's peak are compared absolutely at that level: the
// inverse transform is accurate to ~1e-8 of the peak (include/skin/transport/profile.hpp), and
// the two builds' libm differ in the last bit, which its far tail can amplify. The
// frequency-domain solver (skin with an epidermis thinner than 0.078 / sigma_s') sums hundreds
// of inverted nodes: its profiles differ between the builds by 1.5-3.5e-9 relative in the tail
// (1e-6 of the peak), so they are compared to 1e-8 (the transform's own accuracy).
const PROFILE_FLOOR = 1e-6;
const PROFILE_TOL = 1e-8;

require(path.join(SITE, 'skin.js'))({ wasmBinary: fs.readFileSync(path.join(SITE, 'skin.wasm')) }).then(async (m) => {
  const run = (command, request) => {
    const text = m.run(command, JSON.stringify(request));
    const doc = JSON.parse(text);
    if (doc && doc.error) throw new Error(doc.error);
    return doc;
  };
  // Each part's wall time, printed with its result line.
  let lapStart = Date.now();
  const lap = () => { const t = Date.now(); const s = ((t - lapStart) / 1000).toFixed(1); lapStart = t; return `(${s} s)`; };
  // The wavelengths at which the model solves the profile for `request` (the accurate solver off
  // its skin table: in the frequency domain): the update's "profile_pending" without a profile.
  const solves = (request) => {
    const r = run('update', { ...request, solve_profile: false });
    return r.profile_pending ? r.profile_pending.wavelengths : 0;
  };
  // `spectrum`, `profile --rgb` and the page's `update` (both documents from one pass) against
  // skin's for one parameter set; `grid`: the request's lambda_min, lambda_max, lambda_step.
  let worst = 0, cases = 0;
  const comparePair = (preset, solver, params, grid = {}) => {
    const args = ['--preset', preset, '--solver', solver];
    for (const [key, value] of Object.entries(grid)) args.push(`--${key.replace(/_/g, '-')}`, String(value));
    const refSpectrum = cli(['spectrum', ...args], params);
    const refProfile = cli(['profile', '--rgb', ...args], params);
    const spectrum = compare(run('spectrum', { preset, params, solver, ...grid }), refSpectrum, TOL, 'spectrum');
    fail(spectrum.failures, `spectrum ${solver} ${JSON.stringify(params)}`);
    const profile = compare(run('profile', { preset, params, solver, rgb: true, ...grid }), refProfile, PROFILE_TOL, 'profile', PROFILE_FLOOR);
    fail(profile.failures, `profile ${solver} ${JSON.stringify(params)}`);
    const both = run('update', { preset, params, solver, ...grid });
    const update = compare(both, { spectrum: refSpectrum, profile: refProfile }, PROFILE_TOL, 'update', PROFILE_FLOOR);
    fail(update.failures, `update ${solver} ${JSON.stringify(params)}`);
    worst = Math.max(worst, spectrum.worst, profile.worst, update.worst);
    cases += 2;
  };
  // Random skin, both solvers: the accurate one on its skin table (randomParameters keeps the
  // epidermis thickness there; checked: no wavelength solved), the multipole model with the
  // thickness drawn too.
  const u = rng(16);
  for (let i = 0; i < 6; i++) {
    for (const solver of ['accurate', 'multipole']) {
      const params = randomParameters(u, solver);
      const preset = ['caucasian', 'asian', 'african'][i % 3];
      if (solver === 'accurate' && solves({ preset, params, solver }) !== 0) fail([JSON.stringify(params)], 'accurate solver off its skin table');
      comparePair(preset, solver, params);
    }
  }
  console.log(`module vs skin: ${cases} spectrum/profile pairs (the accurate solver on its skin table), largest relative difference ${worst.toExponential(2)} ${lap()}`);
  // Off the skin table: a 0.015 mm epidermis (at the longer wavelengths below 0.078 / sigma_s',
  // the table's thinnest), where the accurate solver solves those wavelengths' profiles in the
  // frequency domain (the inverse transform of hundreds of nodes; seconds per wavelength in the
  // module), every 50 nm.
  {
    const params = { ...randomParameters(rng(29), 'multipole'), epidermis_thickness: 0.015 };
    const grid = { lambda_step: 50 };
    const n = solves({ preset: 'asian', params, solver: 'accurate', ...grid });
    if (!(n > 0)) fail([`${n} wavelengths solved`], 'the case off the skin table');
    worst = 0; cases = 0;
    comparePair('asian', 'accurate', params, grid);
    console.log(`module vs skin off the skin table (${n} of 7 wavelengths in the frequency domain): largest relative difference ${worst.toExponential(2)} ${lap()}`);
  }

  // The page's update with "solve_profile": false. On the skin table it is the full update;
  // off it (g = 0.6, outside the table's offsets: every wavelength) the spectrum is skin
  // spectrum's and the profile waits.
  {
    const onTable = run('update', { preset: 'tanned', solve_profile: false });
    const full = run('update', { preset: 'tanned' });
    if (JSON.stringify(onTable) !== JSON.stringify(full) || !full.profile) fail(['differs from the full update'], 'update on the table');
    const params = { g: 0.6 };
    const off = run('update', { preset: 'tanned', params, solve_profile: false });
    const failures = [];
    if (off.profile !== null) failures.push('a profile was solved');
    if (!off.profile_pending || off.profile_pending.wavelengths !== 151 || off.profile_pending.of !== 151 || off.profile_pending.solver !== 'accurate')
      failures.push(`profile_pending ${JSON.stringify(off.profile_pending)}`);
    failures.push(...compare(off.spectrum, cli(['spectrum', '--preset', 'tanned'], params), TOL, 'spectrum').failures);
    fail(failures, 'update off the skin table');
    console.log('update with solve_profile false: the full update on the skin table; off it the spectrum alone, the profile pending ' + lap());
  }

  // Illuminants: the CLI's list, D65 first; `color` and `update` under A and LED-B3 give the
  // document of `skin color --illuminant X` (update: from its own R_d, besides the other two).
  const names = run('illuminants', {}).map((il) => il.name);
  const refNames = JSON.parse(require('child_process').execFileSync(SKIN, ['illuminants', '--format', 'json'], { encoding: 'utf8' })).map((il) => il.name);
  if (JSON.stringify(names) !== JSON.stringify(refNames) || names[0] !== 'D65') fail([`${names} != ${refNames}`], 'illuminants');
  let worstColor = 0, colorCases = 0;
  for (let i = 0; i < 3; i++) {
    const solver = i === 2 ? 'multipole' : 'accurate';
    const params = randomParameters(u, solver);
    const preset = ['caucasian', 'asian', 'african'][i % 3];
    for (const illuminant of ['A', 'LED-B3']) {
      const ref = cli(['color', '--preset', preset, '--solver', solver, '--illuminant', illuminant], params);
      if (ref.illuminant !== illuminant) fail([`skin color gave illuminant ${ref.illuminant}`], 'skin color --illuminant');
      const c = compare(run('color', { preset, params, solver, illuminant }), ref, TOL, 'color');
      fail(c.failures, `color ${illuminant} ${solver} ${JSON.stringify(params)}`);
      const up = run('update', { preset, params, solver, illuminant });
      const cu = compare(up.color, ref, TOL, 'update.color');
      fail(cu.failures, `update ${illuminant} ${solver} ${JSON.stringify(params)}`);
      if (!up.spectrum || !up.profile) fail(['spectrum or profile missing'], `update ${illuminant}`);
      worstColor = Math.max(worstColor, c.worst, cu.worst);
      colorCases += 1;
    }
  }
  if ('color' in run('update', { illuminant: 'd65' })) fail(['a color key under D65'], 'update D65');
  console.log(`color and update under A, LED-B3 vs skin color --illuminant: ${colorCases} cases, largest relative difference ${worstColor.toExponential(2)} ${lap()}`);

  // CSV: the same columns (headers exactly), numbers to 1e-9.
  const csv = m.run('spectrum', JSON.stringify({ preset: 'tanned', format: 'csv' }));
  const lines = csv.trim().split('\n');
  if (lines[0] !== 'wavelength_nm,R_d,epidermis.sigma_a [1/mm],epidermis.sigma_s_prime [1/mm],dermis.sigma_a [1/mm],dermis.sigma_s_prime [1/mm]') fail(['header ' + lines[0]], 'spectrum CSV');

  // Exports: every target, its files byte for byte as `skin export` writes them (random skin,
  // both solvers, options of the CLI passed through).
  const targets = run('targets', {});
  targets.forEach((t, i) => {
    const t0 = Date.now();
    const solver = i % 4 === 3 ? 'multipole' : 'accurate';
    const params = randomParameters(u, solver);
    const preset = ['caucasian', 'asian', 'african'][i % 3];
    // (glTF's lengths are metres: the gltf target refuses another unit.)
    const options = i % 2 ? { units: t.name === 'gltf' ? 'm' : 'cm', world_scale: 2.5, name: 'skin_b' } : {};
    const args = ['--preset', preset, '--solver', solver];
    if (options.units) args.push('--units', options.units, '--world-scale', String(options.world_scale), '--name', options.name);
    const e = run('export', { preset, params, solver, target: t.name, ...options });
    const files = Object.fromEntries(e.files.map((f) => [f.name, f.content]));
    const ref = cliExport(t.name, args, params);
    fail(compareExport(files, e.images, ref), `export ${t.name} ${JSON.stringify(params)}`);
    const report = compare(e.report, JSON.parse(ref[`${options.name || 'spectral_skin'}.${t.name}.fit.json`]), 0, 'report');
    fail(report.failures, `export ${t.name}: report`);
    console.log(`  export ${t.name} ${solver}: ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  });
  console.log(`exports: ${targets.map((t) => t.name).join(', ')}: the files of skin export, byte for byte ${lap()}`);

  // Errors: the CLI's one line.
  const bad = JSON.parse(m.run('color', JSON.stringify({ params: { melanin: 2 } })));
  if (!bad.error || !bad.error.includes('melanin (C_m) = 2 is out of range')) fail([JSON.stringify(bad)], 'error message');
  const badTarget = JSON.parse(m.run('export', JSON.stringify({ target: 'renderman' })));
  const badIlluminant = JSON.parse(m.run('color', JSON.stringify({ illuminant: 'F13' })));
  if (!badIlluminant.error || !badIlluminant.error.startsWith("illuminant = 'F13' is unknown: must be one of D65, D50, A,")) fail([JSON.stringify(badIlluminant)], 'illuminant error message');
  if (!badTarget.error || !badTarget.error.startsWith("target = 'renderman' is unknown")) fail([JSON.stringify(badTarget)], 'export error message');
  // A refusal of the parameters lists their keys ("parameters": the page flags those fields):
  // the entry refused (by key or paper symbol, a number or not), or both sides of the constraint
  // melanin + epidermal_hemoglobin <= 1; an unknown key or another error names none.
  for (const [params, keys] of [
    [{ melanin: 2 }, ['melanin']], [{ C_m: 2 }, ['melanin']], [{ g: 'x', melanin: 0.1 }, ['g']],
    [{ 'melanin-blend': -1, g: 1 }, ['melanin_blend', 'g']], [{ epidermis_thickness: 0 }, ['epidermis_thickness']],
    [{ melanin: 0.6, epidermal_hemoglobin: 0.5 }, ['melanin', 'epidermal_hemoglobin']], [{ beta_carotene: true }, ['beta_carotene']],
    [{ gg: 1 }, []], [[1], []],
  ]) {
    for (const command of ['update', 'color', 'export']) {
      const r = JSON.parse(m.run(command, JSON.stringify({ params, target: 'openpbr' })));
      if (!r.error || JSON.stringify(r.parameters) !== JSON.stringify(keys)) fail([`${JSON.stringify(r)}, expected parameters ${JSON.stringify(keys)}`], `${command} parameter error keys ${JSON.stringify(params)}`);
    }
  }
  if ('parameters' in badIlluminant) fail([JSON.stringify(badIlluminant)], 'illuminant error: parameters');

  // color_grid (the 3D view's colours for parameter maps): every node is `color` of its
  // parameters exactly, and the view's trilinear interpolation of ln colour (12 x 4 x 12 nodes,
  // logarithmic in melanin and hemoglobin, over the ranges of the Lee Perry-Smith albedo's maps;
  // view3d.js, mapColour) is within 0.5 dE2000 of the model at 60 points drawn across the box.
  {
    const axis = (lo, hi, n, log) => Array.from({ length: n }, (_, i) => (log ? lo * (hi / lo) ** (i / (n - 1)) : lo + (hi - lo) * i / (n - 1)));
    const axes = { melanin: axis(0.0016, 0.5, 12, true), melanin_blend: axis(0, 1, 4, false), hemoglobin: axis(1e-4, 0.72, 12, true) };
    const grid = run('color_grid', { preset: 'caucasian', ...axes }).srgb_linear;
    const lnGrid = grid.map(Math.log);
    const colour = (p) => run('color', { preset: 'caucasian', params: p }).color.srgb_linear;
    const node = colour({ melanin: axes.melanin[7], melanin_blend: axes.melanin_blend[1], hemoglobin: axes.hemoglobin[4] });
    const at = 3 * ((4 * 4 + 1) * 12 + 7);
    if (node.some((v, c) => v !== grid[at + c])) fail([`${node} != ${grid.slice(at, at + 3)}`], 'color_grid node = color');
    const n = [12, 4, 12];
    const lo = [Math.log(axes.melanin[0]), 0, Math.log(axes.hemoglobin[0])];
    const hi = [Math.log(axes.melanin[11]), 1, Math.log(axes.hemoglobin[11])];
    const interp = (x) => {
      const f = x.map((v, i) => Math.min(1, Math.max(0, (v - lo[i]) / (hi[i] - lo[i]))) * (n[i] - 1));
      const i0 = f.map((v, i) => Math.min(Math.floor(v), n[i] - 2));
      const out = [0, 0, 0];
      for (let corner = 0; corner < 8; corner++) {
        const d = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
        const w = d.reduce((t, di, i) => t * (di ? f[i] - i0[i] : 1 - (f[i] - i0[i])), 1);
        const k = 3 * (((i0[2] + d[2]) * n[1] + i0[1] + d[1]) * n[0] + i0[0] + d[0]);
        for (let c = 0; c < 3; c++) out[c] += w * lnGrid[k + c];
      }
      return out.map(Math.exp);
    };
    const r = rng(31);
    let worst = 0;
    for (let i = 0; i < 60; i++) {
      const x = [lo[0] + r() * (hi[0] - lo[0]), r(), lo[2] + r() * (hi[2] - lo[2])];
      const exact = colour({ melanin: Math.exp(x[0]), melanin_blend: x[1], hemoglobin: Math.exp(x[2]) });
      worst = Math.max(worst, deltaE2000(lab(exact), lab(interp(x))));
    }
    fail(worst <= 0.5 ? [] : [`worst dE2000 ${worst.toFixed(3)}`], 'color_grid interpolated within 0.5 dE2000');
    const big = JSON.parse(m.run('color_grid', JSON.stringify({ melanin: axis(0.01, 0.5, 20, true), melanin_blend: [0.7], hemoglobin: axis(0.01, 0.5, 300, true) })));
    const badNode = JSON.parse(m.run('color_grid', JSON.stringify({ melanin: [0.01, 2], melanin_blend: [0.7], hemoglobin: [0.01] })));
    if (!big.error || !/6000 nodes is too many: at most 4096/.test(big.error)) fail([JSON.stringify(big)], 'color_grid: too many nodes');
    if (!badNode.error || !badNode.error.includes('melanin (C_m) = 2 is out of range') || JSON.stringify(badNode.parameters) !== '["melanin"]') fail([JSON.stringify(badNode)], 'color_grid: a node out of range');
    console.log(`color_grid: nodes are color's; 12 x 4 x 12 trilinear in ln colour within ${worst.toFixed(3)} dE2000 (60 points); too many nodes and a node out of range refused ${lap()}`);
  }

  // The view's reader of parameter maps (web/page/maps.js) against the Python module's fit of
  // the same texture (37 x 23 texels of distinct colours: the last ZIP chunk is 7 lines): the
  // file `skin fit --texture` writes reads back as the same float32 values.
  {
    const py = '/usr/bin/python3';
    const pyPath = path.join(ROOT, 'build', 'python');
    if (!fs.existsSync(py) || !fs.existsSync(path.join(pyPath, 'spectral_skin'))) {
      console.log(`SKIP maps reader: no Python module in ${pyPath}`);
    } else {
      const { readParameterMaps } = await import(path.join(ROOT, 'web', 'page', 'maps.js'));
      const { execFileSync } = require('child_process');
      const dir = fs.mkdtempSync(path.join(TMP, 'maps-'));
      const png = path.join(dir, 'texture.png'), exr = path.join(dir, 'maps.exr'), raw = path.join(dir, 'maps.f32');
      execFileSync(py, ['-c', `
import numpy as np, spectral_skin as s
from PIL import Image
h, w = 23, 37
y, x = np.mgrid[0:h, 0:w]
rgb = np.stack([200 - 2 * y, 150 - 2 * x + y, 120 - x], -1).clip(0, 255).astype(np.uint8)
Image.fromarray(rgb).save(${JSON.stringify(png)})
m = s.fit_texture(${JSON.stringify(png)})
np.concatenate([m[k].astype('<f4').ravel() for k in ('melanin', 'melanin_blend', 'hemoglobin', 'error')]).tofile(${JSON.stringify(raw)})
`], { env: { ...process.env, PYTHONPATH: pyPath }, stdio: 'pipe' });
      execFileSync(SKIN, ['fit', '--texture', png, '-o', exr], { stdio: 'pipe' });
      const bytes = fs.readFileSync(exr);
      const maps = readParameterMaps(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length), 'maps.exr');
      const ref = new Float32Array(fs.readFileSync(raw).buffer.slice(0));
      const got = ['melanin', 'melanin_blend', 'hemoglobin', 'error'].flatMap((k) => Array.from(maps[k]));
      const differing = got.filter((v, i) => v !== ref[i]).length;
      fail(maps.width === 37 && maps.height === 23 && differing === 0 ? [] : [`${maps.width} x ${maps.height}, ${differing} of ${ref.length} values differ`], 'maps.js reads skin fit --texture');
      // The first chunk replaced by a zlib stream of 1 MB of zeros (1 KB compressed): refused in one line, the
      // inflation stopped one byte past the chunk's 9472 bytes (16 lines x 37 x 4 channels x 4 bytes).
      const { zlibSync } = await import(path.join(ROOT, 'web', 'node_modules', 'three', 'examples', 'jsm', 'libs', 'fflate.module.js'));
      const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.length);
      let table = -1;  // the offset table: two chunks, the first right after it
      for (let i = 8; i + 16 <= bytes.length && table < 0; i++) if (Number(dv.getBigUint64(i, true)) === i + 16) table = i;
      const first = table + 16;
      const bomb = zlibSync(new Uint8Array(1 << 20));
      const file = new Uint8Array(first + 8 + bomb.length);
      file.set(bytes.subarray(0, first + 4));
      new DataView(file.buffer).setInt32(first + 4, bomb.length, true);
      file.set(bomb, first + 8);
      let refused = '';
      try { readParameterMaps(file.buffer, 'bomb.exr'); } catch (e) { refused = e.message; }
      fail(refused === 'bomb.exr: chunk 0 inflates to 9473 bytes, not 9472: the file is damaged' ? [] : [`"${refused}"`], 'maps.js refuses a zip bomb in one line');
      // 3000 damaged copies (1-8 random bytes changed anywhere, or cut short): each either reads,
      // with the right size, or is refused by an Error whose one line starts with the file's
      // name; nothing else is thrown (no TypeError or RangeError from a bad offset). A quarter
      // change only letters of the skin_layout text, which the reader does not use: those read.
      const gen = rng(5);
      const outcomes = { read: 0, refused: 0 };
      const odd = [];
      const layout = bytes.indexOf('Spectral Skin parameter maps');
      const original = new Uint8Array(bytes);  // (a Buffer's slice() is a view; a Uint8Array's a copy)
      for (let n = 0; n < 3000; n++) {
        let copy = original.slice();
        if (n % 4 === 3) copy = copy.subarray(0, Math.floor(gen() * copy.length)).slice();
        else if (n % 4 === 2) for (let k = 1 + Math.floor(gen() * 8); k > 0; k--) copy[layout + Math.floor(gen() * 28)] = 65 + Math.floor(gen() * 26);
        else for (let k = 1 + Math.floor(gen() * 8); k > 0; k--) copy[Math.floor(gen() * copy.length)] = Math.floor(gen() * 256);
        try {
          const m = readParameterMaps(copy.buffer, 'damaged.exr');
          if (m.melanin.length !== m.width * m.height) odd.push(`#${n}: ${m.width} x ${m.height} with ${m.melanin.length} values`);
          outcomes.read += 1;
        } catch (e) {
          if (!(e instanceof Error) || e.constructor !== Error || !e.message.startsWith('damaged.exr: ') || e.message.includes('\n')) odd.push(`#${n}: ${e.constructor.name}: ${e.message}`);
          if (n % 4 === 2) odd.push(`#${n}: a change of the skin_layout text refused: ${e.message}`);
          outcomes.refused += 1;
        }
      }
      fail(odd.slice(0, 5), `maps.js on 3000 damaged files (${odd.length} odd)`);
      console.log(`maps.js: the ${ref.length} values of a 37 x 23 fit read as the Python module's; a chunk inflating to 1 MB refused: "${refused}"; ` +
        `3000 damaged copies: ${outcomes.read} read, ${outcomes.refused} refused in one line ${lap()}`);
    }
  }

  if (!fs.existsSync(SPECTRA)) {
    console.log(`SKIP fit: ${SPECTRA} is absent`);
    return;
  }
  const text = fs.readFileSync(SPECTRA, 'utf8');
  fs.copyFileSync(SPECTRA, path.join(TMP, path.basename(SPECTRA)));
  const start = { melanin: 0.01 };
  const web = run('fit', { csv: text, file: path.basename(SPECTRA), column: 'vrhel_117', params: start });
  const ref = cli(['fit', '--spectrum', path.basename(SPECTRA), '--column', 'vrhel_117'], start);
  // The fit stops when Levenberg-Marquardt converges: the last-bit differences of the two builds
  // may move its end point within that tolerance (1e-8 measured), so the fit is compared to 1e-7.
  const f = compare(web, ref, 1e-7, "fit");
  fail(f.failures, 'fit of vrhel_117');
  console.log(`fit of vrhel_117: largest relative difference ${f.worst.toExponential(2)} ${lap()}`);
}).catch((e) => { console.error(e); process.exitCode = 1; });
