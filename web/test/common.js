// Helpers of the web tests: the built module, the `skin` command, and number comparison.
'use strict';
const { execFileSync } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');

const ROOT = path.resolve(__dirname, '..', '..');
const SITE = process.env.SKIN_WEB_SITE || path.join(ROOT, 'build-web', 'site');
const SKIN = process.env.SKIN_BINARY || path.join(ROOT, 'build', 'bin', 'skin');
const SPECTRA = path.join(ROOT, '..', 'shared', 'data', 'skin_spectra', 'vrhel_ncsu', 'vrhel_skin_reflectance.csv');
const TMP = fs.mkdtempSync(path.join(os.tmpdir(), 'skin-web-'));

// `skin ARGS... --params FILE` with the parameters written to FILE; the parsed JSON output.
function cli(args, params, cwd = TMP) {
  const file = path.join(TMP, 'params.json');
  fs.writeFileSync(file, JSON.stringify(params));
  const out = execFileSync(SKIN, [...args, '--params', file, '--format', 'json'], { cwd, encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] });
  return JSON.parse(out);
}

// `skin export --target TARGET ARGS... --params FILE` run in a new folder of its own (no -o: the
// files are named after --name, as the module names them): {file name: Buffer} of what it wrote.
function cliExport(target, args, params) {
  const dir = fs.mkdtempSync(path.join(TMP, `export-${target}-`));
  const file = path.join(dir, 'params.json');
  fs.writeFileSync(file, JSON.stringify(params));
  execFileSync(SKIN, ['export', '--target', target, ...args, '--params', file], { cwd: dir, stdio: 'ignore' });
  fs.rmSync(file);
  const out = {};
  for (const name of fs.readdirSync(dir)) out[name] = fs.readFileSync(path.join(dir, name));
  return out;
}

// The files of the module's export (`{name: content}`, text as UTF-8) against the CLI's: the
// same names (the CLI's images, which the module lists without writing, aside) and the same
// bytes. Returns the differences.
function compareExport(files, images, ref) {
  const failures = [];
  const expected = Object.keys(ref).filter((n) => !images.includes(n)).sort();
  const got = Object.keys(files).sort();
  if (JSON.stringify(got) !== JSON.stringify(expected)) failures.push(`files ${got.join(' ')} != ${expected.join(' ')}`);
  for (const n of images) if (!(n in ref)) failures.push(`image ${n} is not written by skin export`);
  for (const n of expected) {
    if (!(n in files)) continue;
    const a = Buffer.isBuffer(files[n]) ? files[n] : Buffer.from(files[n], 'utf8');
    if (!a.equals(ref[n])) {
      let i = 0;
      while (i < a.length && a[i] === ref[n][i]) i++;
      failures.push(`${n}: differs at byte ${i}: ${JSON.stringify(a.subarray(Math.max(0, i - 20), i + 20).toString())} vs ${JSON.stringify(ref[n].subarray(Math.max(0, i - 20), i + 20).toString())}`);
    }
  }
  return failures;
}

// Every number of `a` against `b` (same keys, same shapes): relative difference at most `tol`
// of the larger magnitude of the two, or of `floor` times the largest magnitude of the array
// it sits in (values near zero in a profile's tail, where the transform's absolute accuracy
// holds, not its relative one). Text and booleans must be equal. Returns the differences.
function compare(a, b, tol, where = '', floor = 0, out = { worst: 0, failures: [] }) {
  if (Array.isArray(b)) {
    if (!Array.isArray(a) || a.length !== b.length) out.failures.push(`${where}: length ${a && a.length} != ${b.length}`);
    else {
      const scale = Math.max(0, ...b.filter((v) => typeof v === 'number').map(Math.abs));
      b.forEach((v, i) => {
        if (typeof v === 'number') check(a[i], v, tol, `${where}[${i}]`, floor * scale, out);
        else compare(a[i], v, tol, `${where}[${i}]`, floor, out);
      });
    }
  } else if (b !== null && typeof b === 'object') {
    for (const k of Object.keys(b)) compare(a ? a[k] : undefined, b[k], tol, `${where}.${k}`, floor, out);
    for (const k of Object.keys(a || {})) if (!(k in b)) out.failures.push(`${where}.${k}: extra key`);
  } else if (typeof b === 'number') {
    check(a, b, tol, where, 0, out);
  } else if (a !== b) {
    out.failures.push(`${where}: ${JSON.stringify(a)} != ${JSON.stringify(b)}`);
  }
  return out;
}
function check(a, b, tol, where, abs_floor, out) {
  const d = Math.abs(a - b) / Math.max(Math.abs(a), Math.abs(b), abs_floor, 1e-300);
  if (!(d <= tol) && a !== b) out.failures.push(`${where}: ${a} vs ${b} (relative ${d.toExponential(2)})`);
  else if (a !== b) out.worst = Math.max(out.worst, d);
}

// The page (build-web/site) served from a local server and opened in headless Chromium (Debian's
// chromium through puppeteer-core), ready: {browser, page, url, server, close()}; null, with a
// SKIP line, when there is no browser at $CHROMIUM.
const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
function serve() {
  const http = require('http');
  const types = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm' };
  const server = http.createServer((req, res) => {
    const file = path.join(SITE, path.normalize(decodeURIComponent(req.url.split('?')[0])).replace(/^(\.\.[/\\])+/, '') || 'index.html');
    const target = fs.existsSync(file) && fs.statSync(file).isDirectory() ? path.join(file, 'index.html') : file;
    if (!target.startsWith(SITE) || !fs.existsSync(target)) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'Content-Type': types[path.extname(target)] || 'application/octet-stream' });
    fs.createReadStream(target).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}
// `extraArgs`: more Chromium flags (head.test.js: --enable-unsafe-swiftshader, WebGL2 on
// SwiftShader without a GPU).
async function openPage(what, extraArgs = []) {
  if (!fs.existsSync(CHROMIUM)) {
    console.log(`SKIP ${what}: no browser at ${CHROMIUM} (install Debian's chromium: scripts/install-deps.sh)`);
    return null;
  }
  const puppeteer = require('puppeteer-core');
  const server = await serve();
  const url = `http://127.0.0.1:${server.address().port}/index.html`;
  const profileDir = fs.mkdtempSync(path.join(os.tmpdir(), 'skin-chromium-'));
  const browser = await puppeteer.launch({
    executablePath: CHROMIUM,
    headless: true,
    userDataDir: profileDir,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', ...extraArgs],
  });
  const close = async () => {
    await browser.close();
    server.close();
    fs.rmSync(profileDir, { recursive: true, force: true });
  };
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1280, height: 1000 });
    page.on('pageerror', (e) => fail([String(e)], 'page error'));
    return { browser, page, url, server, close };
  } catch (e) {
    await close();
    throw e;
  }
}

// A small deterministic generator (mulberry32) for reproducible random parameter sets.
function rng(seed) {
  return () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}
// Random skin within the paper's ranges (C_m 0-0.5, C_h 0-0.2) and around the other defaults,
// for `solver`. The dermis scattering is drawn from 0.3-0.8 of the epidermis' (the accurate
// solver reads it from its table of skin profiles with the offsets for another dermis ratio).
// For the accurate solver the epidermis keeps its default thickness, 0.25 mm: a thinner one
// (below 0.078 / sigma_s') or a thicker one (above 10.1 / sigma_s') leaves the table at some
// wavelengths, which are then solved in the frequency domain (~1 s each in the module). It is
// drawn all the same, so that the sequence of draws does not depend on the solver.
function randomParameters(u, solver) {
  if (solver !== 'accurate' && solver !== 'multipole') throw new Error(`randomParameters: solver ${solver}`);
  const p = {
    melanin: 0.5 * u() ** 2, melanin_blend: u(), hemoglobin: 0.2 * u() ** 2, oiliness: u(),
    oxygenation: 0.5 + 0.5 * u(), epidermis_thickness: 0.1 + 0.3 * u(),
    dermis_scattering_scale: 0.3 + 0.5 * u(), beta_carotene: 50 * u(), bilirubin: 10 * u(),
  };
  if (solver === 'accurate') p.epidermis_thickness = 0.25;
  return p;
}

// CIELAB (D65 white) of linear sRGB, and CIEDE2000 (Sharma, Wu & Dalal 2005).
function lab(rgb) {
  const [r, g, b] = rgb;
  const X = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const Y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const Z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  const w = [0.95047, 1, 1.08883];
  const f = (t) => (t > (6 / 29) ** 3 ? Math.cbrt(t) : t / (3 * (6 / 29) ** 2) + 4 / 29);
  const [fx, fy, fz] = [X / w[0], Y / w[1], Z / w[2]].map(f);
  return [116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)];
}
function deltaE2000([L1, a1, b1], [L2, a2, b2]) {
  const rad = Math.PI / 180;
  const C1 = Math.hypot(a1, b1), C2 = Math.hypot(a2, b2), Cm = (C1 + C2) / 2;
  const G = 0.5 * (1 - Math.sqrt(Cm ** 7 / (Cm ** 7 + 25 ** 7)));
  const a1p = (1 + G) * a1, a2p = (1 + G) * a2;
  const C1p = Math.hypot(a1p, b1), C2p = Math.hypot(a2p, b2);
  const h = (b, a) => (b === 0 && a === 0 ? 0 : (Math.atan2(b, a) / rad + 360) % 360);
  const h1 = h(b1, a1p), h2 = h(b2, a2p);
  const dL = L2 - L1, dC = C2p - C1p;
  let dh = 0;
  if (C1p * C2p !== 0) dh = Math.abs(h2 - h1) <= 180 ? h2 - h1 : h2 - h1 > 180 ? h2 - h1 - 360 : h2 - h1 + 360;
  const dH = 2 * Math.sqrt(C1p * C2p) * Math.sin(dh * rad / 2);
  const Lm = (L1 + L2) / 2, Cmp = (C1p + C2p) / 2;
  let hm = h1 + h2;
  if (C1p * C2p !== 0) hm = Math.abs(h1 - h2) <= 180 ? (h1 + h2) / 2 : h1 + h2 < 360 ? (h1 + h2 + 360) / 2 : (h1 + h2 - 360) / 2;
  const T = 1 - 0.17 * Math.cos((hm - 30) * rad) + 0.24 * Math.cos(2 * hm * rad) + 0.32 * Math.cos((3 * hm + 6) * rad) - 0.2 * Math.cos((4 * hm - 63) * rad);
  const dTheta = 30 * Math.exp(-(((hm - 275) / 25) ** 2));
  const RC = 2 * Math.sqrt(Cmp ** 7 / (Cmp ** 7 + 25 ** 7));
  const SL = 1 + (0.015 * (Lm - 50) ** 2) / Math.sqrt(20 + (Lm - 50) ** 2), SC = 1 + 0.045 * Cmp, SH = 1 + 0.015 * Cmp * T;
  const RT = -Math.sin(2 * dTheta * rad) * RC;
  return Math.sqrt((dL / SL) ** 2 + (dC / SC) ** 2 + (dH / SH) ** 2 + RT * (dC / SC) * (dH / SH));
}
// An 8-bit sRGB value decoded to linear.
const decode = (v) => { const c = v / 255; return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4; };

function fail(failures, what) {
  if (failures.length === 0) return;
  console.error(`FAIL ${what}: ${failures.length} differences, first: ${failures.slice(0, 5).join('; ')}`);
  process.exitCode = 1;
}

module.exports = { ROOT, SITE, SKIN, SPECTRA, TMP, cli, cliExport, compareExport, compare, rng, randomParameters, fail, openPage,
  lab, deltaE2000, decode };
