// The page's 3D view (#view3d, web/page/view3d.js) against the offline renderer (`skin render`),
// in headless Chromium on SwiftShader (as head.test.js). The view gives its own scene
// (skinView3d.renderScene: its camera, canvas size, scale and lights; the page's parameters as a
// skin material), `skin render` renders it, and the two images are compared:
//   - colour: the mean CIEDE2000 over the skin pixels (those the view draws the head in, with
//     their 8 neighbours too: the edges' antialiasing differs) must be at most 3 (issue 33), for
//     the caucasian and african presets;
//   - the shadow edge's bleed: a close-up of the edge of the shadow the head casts (in the key
//     light) on the shoulder, the same camera in both; along lines across the edge, each
//     channel's 10-90 % rise width, from an error function fitted to each line (the median over
//     the lines), must agree within 20 % for each channel.
// The numbers are printed, and the images written to build-web/screenshots (head-view.png,
// head-render.png, and the close-ups). Skips with a message when the site has no head mesh.
// Run: node web/test/head-render.test.js (after scripts/web.sh and npm ci in web/; needs `skin`,
// SKIN_BINARY or build/bin/skin).
'use strict';
const { execFileSync } = require('child_process');
const fs = require('fs');
const path = require('path');
const { ROOT, SITE, SKIN, TMP, fail, openPage, lab, deltaE2000, decode } = require('./common');

const MESH = path.join(SITE, 'mesh', 'LeePerrySmith.glb');
const SHOTS = path.join(ROOT, 'build-web', 'screenshots');
const SPP = Number(process.env.SKIN_HEAD_RENDER_SPP || 32);
const MAX_MEAN_DE = 3;
const MAX_BLEED_DIFFERENCE = 0.2;
const EDGE = [103, 208];
const CLOSE = [160, 120];
const CLOSE_FOV = 5;
let checks = 0;
function check(failures, what) {
  fail(failures, what);
  checks += 1;
  console.log(`${failures.length === 0 ? 'ok' : 'FAILED'}: ${what}`);
}

async function ready(page) {
  await page.waitForFunction(() => window.skinReady && window.skinView3d && window.skinView3d.ready && !window.skinPending &&
    (skinState.profilePending || window.skinState.kernelsKey === JSON.stringify({ preset: skinState.preset, params: { ...skinState.values }, solver: skinState.solver })),
  { timeout: 60000 });
}

// `skin render` of the view's scene: the PNG's bytes (top row first) as {width, height, data}
// read back in the page (RGBA).
async function render(page, scene, name, spp = SPP) {
  const file = path.join(TMP, `${name}.json`);
  const png = path.join(SHOTS, `${name}-render.png`);
  fs.writeFileSync(file, JSON.stringify(scene, null, 1));
  const t0 = Date.now();
  execFileSync(SKIN, ['render', file, '--spp', String(spp), '--seed', '1', '-o', png], { stdio: ['ignore', 'ignore', 'pipe'] });
  const seconds = (Date.now() - t0) / 1000;
  const url = 'data:image/png;base64,' + fs.readFileSync(png).toString('base64');
  const image = await page.evaluate(async (url) => {
    const img = new Image();
    img.src = url;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    return { width: img.width, height: img.height, data: Array.from(g.getImageData(0, 0, img.width, img.height).data) };
  }, url);
  return { image, seconds };
}

// The view's frame (bottom row first) turned top row first, and its mask of skin pixels.
function flip(p) {
  const row = p.width * 4, data = new Array(p.data.length);
  for (let y = 0; y < p.height; y++) for (let i = 0; i < row; i++) data[y * row + i] = p.data[(p.height - 1 - y) * row + i];
  return { width: p.width, height: p.height, data };
}
function skinMask(p) {
  const bg = p.data.slice(0, 3);
  const on = (x, y) => {
    const i = 4 * (y * p.width + x);
    return Math.abs(p.data[i] - bg[0]) + Math.abs(p.data[i + 1] - bg[1]) + Math.abs(p.data[i + 2] - bg[2]) > 0;
  };
  const mask = [];
  for (let y = 1; y < p.height - 1; y++) {
    for (let x = 1; x < p.width - 1; x++) {
      let all = true;
      for (let dy = -1; dy <= 1 && all; dy++) for (let dx = -1; dx <= 1 && all; dx++) all = on(x + dx, y + dy);
      if (all) mask.push(y * p.width + x);
    }
  }
  return mask;
}

function meanDeltaE(view, rendered, mask) {
  let sum = 0;
  const values = [];
  for (const k of mask) {
    const i = 4 * k;
    const a = lab([0, 1, 2].map((c) => decode(view.data[i + c])));
    const b = lab([0, 1, 2].map((c) => decode(rendered.data[i + c])));
    const de = deltaE2000(a, b);
    sum += de;
    values.push(de);
  }
  values.sort((x, y) => x - y);
  return { mean: sum / Math.max(1, mask.length), p95: values[Math.floor(0.95 * (values.length - 1))] || 0 };
}

// The 10-90 % width (pixels) of a step along a profile (linear values): an error function
// lo + (hi - lo) Phi((x - x0) / s) fitted by least squares (a grid over x0 and s, lo and hi
// solved linearly at each), width = 2 x 1.2816 s.
function stepWidth(values) {
  const n = values.length;
  const erf = (x) => {
    const t = 1 / (1 + 0.3275911 * Math.abs(x));
    const y = 1 - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t + 0.254829592) * t * Math.exp(-x * x);
    return x >= 0 ? y : -y;
  };
  let best = { err: Infinity };
  const tryFit = (x0, s) => {
    const phi = values.map((_, x) => 0.5 * (1 + erf((x - x0) / (s * Math.SQRT2))));
    // values ~ lo + d phi: linear least squares in (lo, d).
    let sp = 0, spp = 0, sv = 0, spv = 0;
    for (let x = 0; x < n; x++) { sp += phi[x]; spp += phi[x] * phi[x]; sv += values[x]; spv += phi[x] * values[x]; }
    const det = n * spp - sp * sp;
    if (Math.abs(det) < 1e-12) return;
    const d = (n * spv - sp * sv) / det, lo = (sv - d * sp) / n;
    let err = 0;
    for (let x = 0; x < n; x++) err += (lo + d * phi[x] - values[x]) ** 2;
    if (err < best.err) best = { err, x0, s, lo, d };
  };
  // A coarse grid, then a fine one about its best.
  for (let x0 = 0.2 * n; x0 <= 0.8 * n; x0 += 1) for (let s = 0.2; s <= n / 3; s *= 1.1) tryFit(x0, s);
  const coarse = best;
  for (let x0 = coarse.x0 - 1; x0 <= coarse.x0 + 1; x0 += 0.1) for (let s = coarse.s / 1.1; s <= coarse.s * 1.1; s *= 1.005) tryFit(x0, s);
  return { width: 2 * 1.2815516 * best.s, x0: best.x0, lo: best.lo, hi: best.lo + best.d };
}

// The mean linear profile per channel down the columns x0..x1 (averaged), from row y0 to y1.
function profile(img, x0, x1, y0, y1) {
  const out = [[], [], []];
  for (let y = y0; y <= y1; y++) {
    for (let c = 0; c < 3; c++) {
      let s = 0;
      for (let x = x0; x <= x1; x++) s += decode(img.data[4 * (y * img.width + x) + c]);
      out[c].push(s / (x1 - x0 + 1));
    }
  }
  return out;
}

async function main() {
  if (!fs.existsSync(MESH)) {
    console.log(`SKIP head-vs-render test: no head mesh in the site (${MESH}; scripts/web.sh copies it from ../shared/data)`);
    return;
  }
  if (!fs.existsSync(SKIN)) {
    console.log(`SKIP head-vs-render test: no skin at ${SKIN} (build it, or set SKIN_BINARY)`);
    return;
  }
  const opened = await openPage('head-vs-render test', ['--enable-unsafe-swiftshader']);
  if (!opened) return;
  const { page, url, close } = opened;
  fs.mkdirSync(SHOTS, { recursive: true });
  try {
    await page.goto(url);
    await ready(page);
    // 320 x 240 pixels (the canvas is 4:3).
    await page.evaluate(() => { document.getElementById('view3d').style.width = '320px'; });
    const size = await page.evaluate(() => { const p = skinView3d.pixels(); return [p.width, p.height]; });
    if (size[0] !== 320 || size[1] !== 240) throw new Error(`the view is ${size.join('x')} pixels, not 320x240 (devicePixelRatio 1 expected)`);
    let figure = null;

    for (const preset of ['african', 'caucasian']) {
      await page.click(`#presets button[data-preset="${preset}"]`);
      await ready(page);
      const got = await page.evaluate((mesh) => {
        const material = { type: 'skin', preset: skinState.preset, ...skinState.values, solver: skinState.solver };
        return { scene: skinView3d.renderScene(mesh, material), pixels: skinView3d.pixels() };
      }, MESH);
      const view = flip(got.pixels);
      const { image, seconds } = await render(page, got.scene, `head-${preset}`);
      await savePng(page, view, path.join(SHOTS, `head-${preset}-view.png`));
      if (preset === 'caucasian') figure = sideBySide(view, image);
      const mask = skinMask(view);
      const de = meanDeltaE(view, image, mask);
      check(de.mean <= MAX_MEAN_DE ? [] : [`mean dE2000 ${de.mean.toFixed(2)} > ${MAX_MEAN_DE}`],
        `${preset}: the view against skin render (${view.width}x${view.height}, ${SPP} spp, ${seconds.toFixed(1)} s): mean dE2000 ${de.mean.toFixed(2)} ` +
        `over ${mask.length} skin pixels (95th percentile ${de.p95.toFixed(2)})`);
    }
    // The figure of the README (docs/images/head-vs-render.png): the view and the render.
    await savePng(page, figure, path.join(SHOTS, 'head-vs-render.png'));

    // The shadow's edge, close up (caucasian): the edge of the shadow the head casts (in the key
    // light) on the left shoulder, at pixel EDGE of the 320 x 240 view, seen through a field of
    // view CLOSE_FOV degrees high from the same eye; the edge runs across the close-up, and the
    // profile runs down each of its central 41 columns, 61 rows about its centre.
    const cam = await page.evaluate(() => skinView3d.getCamera());
    const sub = (a, b) => a.map((v, i) => v - b[i]);
    const norm = (a) => { const l = Math.hypot(...a); return a.map((v) => v / l); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const forward = norm(sub(cam.target, cam.eye)), right = norm(cross(forward, [0, 1, 0])), up = cross(right, forward);
    const t = Math.tan(cam.fov * Math.PI / 360);
    const nx = ((EDGE[0] + 0.5) / 320) * 2 - 1, ny = 1 - ((EDGE[1] + 0.5) / 240) * 2;
    const dir = norm(forward.map((f, i) => f + right[i] * nx * t * (4 / 3) + up[i] * ny * t));
    const distance = Math.hypot(...sub(cam.target, cam.eye));
    await page.evaluate((w) => { document.getElementById('view3d').style.width = `${w}px`; }, CLOSE[0]);
    const closeUp = await page.evaluate((c, mesh) => {
      skinView3d.setCamera(c);
      const material = { type: 'skin', preset: skinState.preset, ...skinState.values, solver: skinState.solver };
      return { scene: skinView3d.renderScene(mesh, material), pixels: skinView3d.pixels() };
    }, { eye: cam.eye, target: cam.eye.map((e, i) => e + dir[i] * distance), fov: CLOSE_FOV }, MESH);
    const closeView = flip(closeUp.pixels);
    await savePng(page, closeView, path.join(SHOTS, 'head-edge-view.png'));
    const closeRender = (await render(page, closeUp.scene, 'head-edge', 4 * SPP)).image;
    const mmPerPixel = 2 * distance * t * (CLOSE_FOV / cam.fov) * closeUp.scene.unit_mm / closeView.height;
    const w = closeView.width, h = closeView.height;
    const rows = [(h >> 1) - 30, (h >> 1) + 30], cols = [(w >> 1) - 20, (w >> 1) + 20];
    // Each column's step fitted on its own (the edge crosses the columns obliquely: their mean
    // would smear it), the median width over the columns, per channel.
    const median = (a) => { const s = [...a].sort((x, y) => x - y); return s[s.length >> 1]; };
    const widths = [closeView, closeRender].map((img) => {
      const fits = [];
      for (let x = cols[0]; x <= cols[1]; x++) fits.push(profile(img, x, x, rows[0], rows[1]).map(stepWidth));
      return [0, 1, 2].map((c) => ({
        width: median(fits.map((f) => f[c].width)), lo: median(fits.map((f) => f[c].lo)), hi: median(fits.map((f) => f[c].hi)),
      }));
    });
    const bleed = [];
    const names = ['R', 'G', 'B'];
    for (let c = 0; c < 3; c++) {
      const [v, r] = [widths[0][c], widths[1][c]];
      const diff = Math.abs(v.width - r.width) / r.width;
      console.log(`  ${names[c]}: view ${(v.width * mmPerPixel).toFixed(2)} mm (${v.lo.toFixed(3)} -> ${v.hi.toFixed(3)}), ` +
        `render ${(r.width * mmPerPixel).toFixed(2)} mm (${r.lo.toFixed(3)} -> ${r.hi.toFixed(3)}): ${(100 * diff).toFixed(0)} %`);
      if (!(diff <= MAX_BLEED_DIFFERENCE)) bleed.push(`${names[c]} ${(100 * diff).toFixed(0)} %`);
      if (!(r.hi > 1.5 * r.lo && v.hi > 1.5 * v.lo)) bleed.push(`${names[c]}: no shadow edge at the close-up's centre`);
    }
    check(bleed, `the shadow edge's 10-90 % width per channel, view against render, within ${100 * MAX_BLEED_DIFFERENCE} %: ` +
      names.map((n, c) => `${n} ${(widths[0][c].width * mmPerPixel).toFixed(2)} / ${(widths[1][c].width * mmPerPixel).toFixed(2)} mm`).join(', '));
  } finally {
    await close();
  }
  console.log(`${checks} checks${process.exitCode ? ', FAILED' : ''}`);
}

// Two RGBA images of one size side by side, 4 pixels of white between them.
function sideBySide(a, b) {
  const gap = 4, width = 2 * a.width + gap, data = new Array(width * a.height * 4).fill(255);
  for (let y = 0; y < a.height; y++) {
    for (let x = 0; x < a.width; x++) {
      for (let c = 0; c < 4; c++) {
        data[4 * (y * width + x) + c] = a.data[4 * (y * a.width + x) + c];
        data[4 * (y * width + a.width + gap + x) + c] = b.data[4 * (y * b.width + x) + c];
      }
    }
  }
  return { width, height: a.height, data };
}

// An RGBA image (top row first) saved as PNG through the page's canvas.
async function savePng(page, img, file) {
  const b64 = await page.evaluate((img) => {
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.putImageData(new ImageData(new Uint8ClampedArray(img.data), img.width, img.height), 0, 0);
    return c.toDataURL('image/png').split(',')[1];
  }, img);
  fs.writeFileSync(file, Buffer.from(b64, 'base64'));
}

main().catch((e) => { console.error(e); process.exitCode = 1; });
