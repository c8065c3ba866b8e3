// The page's 3D view (#view3d, web/page/view3d.js) in headless Chromium on SwiftShader (WebGL2
// in software; puppeteer-core, as browser.test.js):
//   - a lit head: the Lee Perry-Smith scan when the site holds it (scripts/web.sh copies it),
//     enough pixels off the background, of a sensible brightness; with the mesh's request
//     refused, a lit sphere instead;
//   - one to three lights: the fill and the back light switch off by their boxes (the skin gets
//     darker, skin render's scene loses them, the URL keeps them) and on again (the same frame);
//   - the subsurface kernels are the realtime export's for the current parameters;
//   - moving #param-melanin's slider changes the skin's pixels, and the time from the slider's
//     input event to the next frame after the view's is measured (median of 15 moves) and
//     printed with the view's draw times, then for every other slider (median of 5 moves each);
//     SKIN_VIEW_LATENCY_MS (e.g. 50, the issue's target) makes the slowest slider's median a
//     limit (not held by default: the machine is shared and loaded);
//   - the patch (the view's test mode: a square head-on, lit by the key light alone, no
//     specular) reads within 1 CIEDE2000 of the module's colour (`skin color`) for every preset;
//   - the brushes: a blush stroke with the mouse on the cheek reddens the skin under it, pallor
//     (two strokes) leaves it paler than before; a tan stroke darkens it, lightening (two
//     strokes) leaves it lighter than before; no pixel more than 80 px from the stroke changes,
//     and cleared the frame is as before;
//   - a mesh of one's own: a tetrahedron (OBJ, no normals) through the file picker
//     (#view3d-file) and dropped on the view is shown, lit; an OBJ with no faces, a .glb of
//     garbage and a file of another kind each give one line naming the file (the mesh shown
//     stays, the spectrum loader is not called, no page error);
//   - parameter maps (skin fit --texture's .exr) through the picker shade the head: the maps of
//     the preset's own colour leave it within 0.6 mean dE2000, those of the tanned preset's
//     colour give the tanned head within 1; cleared, as before; a file that is not maps (garbage,
//     truncated, an RGB image, the extended model's maps) gives one line.
// Run: node web/test/head.test.js (after scripts/web.sh and npm ci in web/).
'use strict';
const fs = require('fs');
const path = require('path');
const { ROOT, SITE, SKIN, TMP, fail, openPage, lab, deltaE2000, decode } = require('./common');

let checks = 0;
function check(failures, what) {
  fail(failures, what);
  checks += 1;
  console.log(`${failures.length === 0 ? 'ok' : 'FAILED'}: ${what}`);
}


// The view's pixels ({width, height, data}) split into skin (off the background) and the rest.
function skinPixels(p) {
  const bg = p.data.slice(0, 3);  // a corner: the background
  const skin = [];
  for (let i = 0; i < p.data.length; i += 4) {
    if (Math.abs(p.data[i] - bg[0]) + Math.abs(p.data[i + 1] - bg[1]) + Math.abs(p.data[i + 2] - bg[2]) > 6) skin.push(i);
  }
  return skin;
}
const luma = (d, i) => 0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2];
// The mean CIEDE2000 between two frames over the first one's skin pixels.
function meanDeltaE(a, b) {
  const px = skinPixels(a);
  let sum = 0;
  for (const i of px) sum += deltaE2000(lab([0, 1, 2].map((c) => decode(a.data[i + c]))), lab([0, 1, 2].map((c) => decode(b.data[i + c]))));
  return sum / Math.max(1, px.length);
}

async function ready(page) {
  await page.waitForFunction(() => window.skinReady && window.skinView3d && window.skinView3d.ready && !window.skinPending &&
    (skinState.profilePending || window.skinState.kernelsKey === JSON.stringify({ preset: skinState.preset, params: { ...skinState.values }, solver: skinState.solver })),
  { timeout: 60000 });
}

async function main() {
  const opened = await openPage('3D view test', ['--enable-unsafe-swiftshader']);
  if (!opened) return;
  const { page, url, close } = opened;
  try {
    const hasMesh = fs.existsSync(path.join(SITE, 'mesh', 'LeePerrySmith.glb'));
    await page.goto(url);
    await ready(page);
    const renderer = await page.evaluate(() => {
      const gl = document.getElementById('view3d').getContext('webgl2');
      const d = gl && gl.getExtension('WEBGL_debug_renderer_info');
      return gl ? gl.getParameter(d ? d.UNMASKED_RENDERER_WEBGL : gl.RENDERER) : null;
    });
    console.log(`WebGL2: ${renderer}`);

    // A lit head.
    const head = await page.evaluate(() => ({ mesh: skinView3d.meshName, pixels: skinView3d.pixels(), credit: !document.getElementById('view3d-credit').hidden }));
    const skin = skinPixels(head.pixels);
    const share = skin.length / (head.pixels.width * head.pixels.height);
    const mean = skin.reduce((s, i) => s + luma(head.pixels.data, i), 0) / Math.max(1, skin.length);
    check([
      ...(head.mesh !== (hasMesh ? 'head' : 'sphere') ? [`mesh ${head.mesh}, expected ${hasMesh ? 'head' : 'sphere'}`] : []),
      ...(hasMesh && !head.credit ? ['the head is shown without its credit'] : []),
      ...(share < 0.15 ? [`only ${(100 * share).toFixed(1)} % of the view off the background`] : []),
      ...(!(mean > 60 && mean < 230) ? [`mean skin luma ${mean.toFixed(1)} (8-bit) is not of a lit skin`] : []),
    ], `#view3d shows a lit ${head.mesh}: ${(100 * share).toFixed(0)} % of the view, mean luma ${mean.toFixed(0)}/255`);

    const shots = path.join(ROOT, 'build-web', 'screenshots');
    fs.mkdirSync(shots, { recursive: true });
    await (await page.$('#view3d')).screenshot({ path: path.join(shots, 'view3d.png') });

    // One to three lights: the back light and the fill switched off by their boxes each take
    // light away (the luma of the skin falls, the scene for skin render has one light fewer),
    // the URL keeps them; both on again, the frame is as before to the byte.
    {
      const failures = [];
      const state = async () => page.evaluate(() => ({ pixels: skinView3d.pixels(), lights: skinView3d.renderScene('m.glb', 'skin').lights.length, hash: location.hash }));
      const meanLuma = (p) => skin.reduce((s, i) => s + luma(p.data, i), 0) / Math.max(1, skin.length);
      await page.click('#view3d-back');
      const noBack = await state();
      await page.click('#view3d-fill');
      const keyOnly = await state();
      await page.click('#view3d-back');
      await page.click('#view3d-fill');
      const again = await state();
      const lumas = [mean, meanLuma(noBack.pixels), meanLuma(keyOnly.pixels)];
      if (!(lumas[1] < lumas[0] && lumas[2] < lumas[1])) failures.push(`skin luma ${lumas.map((l) => l.toFixed(1)).join(' -> ')} does not fall`);
      if (noBack.lights !== 2 || keyOnly.lights !== 1 || again.lights !== 3) failures.push(`scene lights ${noBack.lights}, ${keyOnly.lights}, ${again.lights} (expected 2, 1, 3)`);
      if (!/lights=key&|lights=key$/.test(keyOnly.hash) || /lights=/.test(again.hash)) failures.push(`URL ${keyOnly.hash} / ${again.hash}`);
      if (again.pixels.data.some((v, i) => v !== head.pixels.data[i])) failures.push('with every light on again the frame differs');
      check(failures, `lights: skin luma ${lumas.map((l) => l.toFixed(0)).join(' -> ')} with the back light, then the fill off; ` +
        `the scene's lights 3 -> ${noBack.lights} -> ${keyOnly.lights}; the URL keeps them; all on again, the same frame`);
    }

    // The kernels are the realtime export's of these parameters.
    const kernels = await page.evaluate(() => {
      const e = JSON.parse(JSON.parse(skinState.module.run('export', JSON.stringify({ preset: skinState.preset, params: skinState.values, solver: skinState.solver, target: 'realtime' }))).files[0].content);
      return { page: skinState.kernels.gaussians, exported: e.gaussians, used: skinView3d.kernels.variance };
    });
    check(JSON.stringify(kernels.page) === JSON.stringify(kernels.exported) &&
      JSON.stringify(kernels.used) === JSON.stringify(kernels.exported.map((g) => g.variance)) ? [] : ['kernels differ from the realtime export'],
    `the view's subsurface is the realtime export's ${kernels.exported.length} Gaussians`);

    // Melanin moves the skin's pixels, and the time from the input event to the next frame.
    // `moves` moves of a slider from `from` in steps of `step` (of the slider's positions): per
    // move the input event -> the frame after the view's (that one was presented), -> the end of
    // the view's draw calls, and whether the view redrew its light (not only the composite).
    const moveSlider = (key, moves, from, step) => page.evaluate(async (key, moves, from, step) => {
      const slider = document.getElementById(`s-${key}`);
      const nextFrame = () => new Promise((r) => requestAnimationFrame(r));
      const out = [];
      for (let k = 0; k < moves; k++) {
        await nextFrame();
        const frames = skinView3d.frames, lit = skinView3d.litFrames;
        const t0 = performance.now();
        slider.value = String(from + step * k);
        slider.dispatchEvent(new Event('input', { bubbles: true }));
        while (skinView3d.frames === frames) await nextFrame();
        const drawn = skinView3d.lastFrame;
        await nextFrame();
        out.push({ total: performance.now() - t0, drawn: drawn - t0, draw: skinView3d.frameTimes[skinView3d.frameTimes.length - 1], lit: skinView3d.litFrames > lit });
      }
      return out;
    }, key, moves, from, step);
    const median = (a) => { const s = [...a].sort((x, y) => x - y); return s[s.length >> 1]; };
    const latencies = await moveSlider('melanin', 15, 200, 40);
    const latency = median(latencies.map((l) => l.total));
    console.log(`input event -> next frame: median ${latency.toFixed(1)} ms (min ${Math.min(...latencies.map((l) => l.total)).toFixed(1)}, max ` +
      `${Math.max(...latencies.map((l) => l.total)).toFixed(1)}); input -> view drawn (model, page, view) median ${median(latencies.map((l) => l.drawn)).toFixed(1)} ms; ` +
      `the view's draw calls ${median(latencies.map((l) => l.draw)).toFixed(1)} ms median on the main thread`);
    const moved = await page.evaluate(() => ({ pixels: skinView3d.pixels(), melanin: skinState.values.melanin }));
    let diff = 0;
    for (const i of skin) diff += Math.abs(moved.pixels.data[i] - head.pixels.data[i]) + Math.abs(moved.pixels.data[i + 1] - head.pixels.data[i + 1]) + Math.abs(moved.pixels.data[i + 2] - head.pixels.data[i + 2]);
    diff /= 3 * Math.max(1, skin.length);
    const darker = skinPixels(moved.pixels).reduce((s, i) => s + luma(moved.pixels.data, i), 0) / Math.max(1, skinPixels(moved.pixels).length);
    check(diff > 5 && darker < mean ? [] : [`mean change ${diff.toFixed(2)}/255, luma ${mean.toFixed(1)} -> ${darker.toFixed(1)}`],
      `melanin ${moved.melanin} changes the skin's pixels (mean ${diff.toFixed(1)}/255 per channel, luma ${mean.toFixed(0)} -> ${darker.toFixed(0)})`);

    // Every other slider, 5 moves each (the preset restored after).
    const keys = await page.evaluate(() => [...document.querySelectorAll('input[type=range][id^="s-"]')].map((e) => e.id.slice(2)).filter((k) => k !== 'melanin'));
    const perSlider = { melanin: latency };
    const litSliders = [];
    for (const key of keys) {
      const l = await moveSlider(key, 5, 300, 60);
      perSlider[key] = median(l.map((x) => x.total));
      if (l.some((x) => x.lit)) litSliders.push(key);
    }
    await page.click('#presets button[data-preset="caucasian"]');
    await ready(page);
    const slowest = Object.entries(perSlider).sort((x, y) => y[1] - x[1])[0];
    console.log(`  input -> next frame, median of 5 moves per slider: ${Object.entries(perSlider).map(([k, v]) => `${k} ${v.toFixed(0)}`).join(', ')} ms; ` +
      `slowest ${slowest[0]} ${slowest[1].toFixed(1)} ms; the view redrew its light for ${litSliders.length ? litSliders.join(', ') : 'none'}`);
    const limit = Number(process.env.SKIN_VIEW_LATENCY_MS || 0);
    if (limit > 0) check(slowest[1] <= limit ? [] : [`median ${slowest[1].toFixed(1)} ms (${slowest[0]}) > ${limit} ms`], `every slider to frame within ${limit} ms`);

    // The patch against the module's colour, for every preset.
    const presets = await page.evaluate(() => skinState.presets.map((p) => p.name));
    const worst = { de: 0, preset: '' };
    const failures = [];
    for (const name of presets) {
      await page.click(`#presets button[data-preset="${name}"]`);
      await ready(page);
      const r = await page.evaluate(() => {
        skinView3d.setMode('patch');
        const p = skinView3d.pixels();
        skinView3d.setMode('head');
        // The mean of the central 16 x 16 pixels.
        const sum = [0, 0, 0];
        for (let y = (p.height >> 1) - 8; y < (p.height >> 1) + 8; y++)
          for (let x = (p.width >> 1) - 8; x < (p.width >> 1) + 8; x++)
            for (let c = 0; c < 3; c++) sum[c] += p.data[(y * p.width + x) * 4 + c];
        return { rgb8: sum.map((v) => v / 256), color: skinState.spectrum.color.srgb_linear };
      });
      const de = deltaE2000(lab(r.color), lab(r.rgb8.map(decode)));
      if (de > worst.de) Object.assign(worst, { de, preset: name });
      if (!(de <= 1)) failures.push(`${name}: dE2000 ${de.toFixed(3)} (patch ${r.rgb8.map((v) => v.toFixed(1)).join(' ')})`);
    }
    check(failures, `the lit patch reads the module's colour for all ${presets.length} presets: worst dE2000 ${worst.de.toFixed(3)} (${worst.preset})`);

    // The blush and pallor brush, a stroke on the cheek with the mouse: the skin around it redder
    // (blush) or paler (pallor), every pixel away from it unchanged; cleared, the frame as before.
    await page.click('#presets button[data-preset="caucasian"]');
    await ready(page);
    await page.evaluate(() => document.getElementById('view3d').scrollIntoView({ block: 'center' }));
    const box = await (await page.$('#view3d')).boundingBox();
    const before = await page.evaluate(() => skinView3d.pixels());
    const scale = before.width / box.width;
    const at = [box.x + 0.5 * box.width, box.y + 0.55 * box.height];  // the cheek
    const atPx = [(at[0] - box.x) * scale, (at[1] - box.y) * scale];
    async function stroke(brush) {
      await page.click(`input[name="view3d-brush"][value="${brush}"]`);
      await page.mouse.move(at[0] - 4, at[1]);
      await page.mouse.down();
      for (let i = -3; i <= 4; i++) await page.mouse.move(at[0] + i, at[1]);
      await page.mouse.up();
      await page.waitForFunction(() => skinView3d.painted && skinView3d.paintReady && !window.skinBackgroundPending(), { timeout: 20000 });
      return page.evaluate(() => skinView3d.pixels());
    }
    // Per pixel (top row first): its distance from the stroke, and the change of red over green.
    function changes(a, b) {
      let near = 0, nearLuma = 0, nearCount = 0, far = 0, farthest = 0;
      for (let i = 0; i < a.data.length; i += 4) {
        const k = i / 4, x = k % a.width, y = a.height - 1 - Math.floor(k / a.width);
        const d = Math.hypot(x - atPx[0], y - atPx[1]);
        const changed = Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) + Math.abs(a.data[i + 2] - b.data[i + 2]);
        if (changed > 0) farthest = Math.max(farthest, d);
        if (d <= 6) { near += b.data[i] / Math.max(1, b.data[i + 1]) - a.data[i] / Math.max(1, a.data[i + 1]); nearLuma += luma(b.data, i) - luma(a.data, i); nearCount += 1; }
        else if (d > 80 && changed > 0) far += 1;
      }
      return { redder: near / Math.max(1, nearCount), lighter: nearLuma / Math.max(1, nearCount), far, farthest };
    }
    const blush = changes(before, await stroke('blush'));
    await (await page.$('#view3d')).screenshot({ path: path.join(shots, 'view3d-blush.png') });
    const pallor = changes(before, await stroke('pallor') && await stroke('pallor'));
    await page.evaluate(() => { skinView3d.clearPaint(); skinView3d.setBrush('turn'); });
    const cleared = await page.evaluate(() => skinView3d.pixels());
    const same = cleared.data.every((v, i) => v === before.data[i]);
    console.log(`  blush: red/green ${blush.redder >= 0 ? '+' : ''}${blush.redder.toFixed(3)} at the stroke, changed pixels out to ${blush.farthest.toFixed(0)} px; ` +
      `pallor (two strokes after it): ${pallor.redder.toFixed(3)}, out to ${pallor.farthest.toFixed(0)} px`);
    check([
      ...(blush.redder > 0.02 ? [] : [`blush: red/green changed by ${blush.redder.toFixed(3)}`]),
      ...(pallor.redder < -0.02 ? [] : [`pallor: red/green changed by ${pallor.redder.toFixed(3)}`]),
      ...(blush.far === 0 && pallor.far === 0 ? [] : [`pixels changed more than 80 px from the stroke: ${blush.far}, ${pallor.far}`]),
      ...(same ? [] : ['cleared, the frame differs from the one before']),
    ], 'a blush stroke reddens the cheek, pallor pales it, nothing else changes; cleared, as before');
    // The melanin brushes: a tan stroke darkens the cheek, lightening (two strokes after it)
    // leaves it lighter than before; nothing far from the stroke changes; cleared, as before.
    const tan = changes(before, await stroke('tan'));
    const lighten = changes(before, await stroke('lighten') && await stroke('lighten'));
    await page.evaluate(() => { skinView3d.clearPaint(); skinView3d.setBrush('turn'); });
    const clearedAgain = await page.evaluate(() => skinView3d.pixels());
    console.log(`  tan: luma ${tan.lighter.toFixed(1)} at the stroke, out to ${tan.farthest.toFixed(0)} px; lighten (two strokes after it): ${lighten.lighter >= 0 ? '+' : ''}${lighten.lighter.toFixed(1)}, out to ${lighten.farthest.toFixed(0)} px`);
    check([
      ...(tan.lighter < -2 ? [] : [`tan: luma changed by ${tan.lighter.toFixed(2)}`]),
      ...(lighten.lighter > 2 ? [] : [`lighten: luma changed by ${lighten.lighter.toFixed(2)}`]),
      ...(tan.far === 0 && lighten.far === 0 ? [] : [`pixels changed more than 80 px from the stroke: ${tan.far}, ${lighten.far}`]),
      ...(clearedAgain.data.every((v, i) => v === before.data[i]) ? [] : ['cleared, the frame differs from the one before']),
    ], `a tan stroke darkens the cheek (luma ${tan.lighter.toFixed(1)}), lightening lightens it (${lighten.lighter >= 0 ? '+' : ''}${lighten.lighter.toFixed(1)}), nothing else changes; cleared, as before`);

    const picker = await page.$('#view3d-file');
    // Parameter maps of `skin fit --texture` (.exr) on the head: fitted from a texture of the
    // caucasian preset's own colour, the head is as without maps (the colour per texel is the
    // fit's, through the view's grid); from a texture of the tanned preset's colour, it is darker
    // and within 1 dE2000 of the head with the tanned preset's sliders; cleared, as before; bad
    // files give one line.
    {
      const dir = fs.mkdtempSync(path.join(TMP, 'maps-'));
      const colours = {};
      for (const name of ['caucasian', 'tanned']) {
        await page.click(`#presets button[data-preset="${name}"]`);
        await ready(page);
        colours[name] = await page.evaluate(() => ({ hex: skinState.spectrum.color.hex, pixels: skinView3d.pixels() }));
        // A 16 x 16 PNG of that colour (the browser's encoder), fitted by the command line.
        const png = await page.evaluate((hex) => {
          const c = document.createElement('canvas');
          c.width = c.height = 16;
          const g = c.getContext('2d');
          g.fillStyle = hex;
          g.fillRect(0, 0, 16, 16);
          return c.toDataURL('image/png').split(',')[1];
        }, colours[name].hex);
        fs.writeFileSync(path.join(dir, `${name}.png`), Buffer.from(png, 'base64'));
        // (The tanned maps with their uncertainty layer, which the view reads past.)
        require('child_process').execFileSync(SKIN, ['fit', '--texture', path.join(dir, `${name}.png`), '-o', path.join(dir, `${name}.exr`),
          ...(name === 'tanned' ? ['--uncertainty'] : [])], { stdio: 'pipe' });
      }
      await page.click('#presets button[data-preset="caucasian"]');
      await ready(page);
      const load = async (name) => {
        await picker.uploadFile(path.join(dir, name));
        await page.waitForFunction((n) => window.skinView3d.maps && window.skinView3d.maps.name === n && !window.skinBackgroundPending(), { timeout: 60000 }, name);
        return page.evaluate(() => ({ pixels: skinView3d.pixels(), status: document.getElementById('view3d-file-status').textContent, ms: skinState.mapMs }));
      };
      const same = await load('caucasian.exr');
      const deSame = meanDeltaE(same.pixels, colours.caucasian.pixels);
      const tanned = await load('tanned.exr');
      const deTanned = meanDeltaE(tanned.pixels, colours.tanned.pixels);
      const lumaOf = (p) => { const px = skinPixels(p); return px.reduce((t, i) => t + luma(p.data, i), 0) / Math.max(1, px.length); };
      await page.click('#view3d-clear-maps');
      const cleared = await page.evaluate(() => ({ pixels: skinView3d.pixels(), maps: skinView3d.maps }));
      console.log(`  maps: "${same.status}" (the grid's colours in ${same.ms.toFixed(0)} ms); mean dE2000 to the head without maps ${deSame.toFixed(3)}; ` +
        `tanned maps on caucasian sliders: to the tanned head ${deTanned.toFixed(3)}, luma ${lumaOf(colours.caucasian.pixels).toFixed(1)} -> ${lumaOf(tanned.pixels).toFixed(1)}`);
      check([
        ...(/16 x 16 texels/.test(same.status) ? [] : [`status "${same.status}"`]),
        ...(deSame <= 0.6 ? [] : [`caucasian maps: mean dE2000 ${deSame.toFixed(3)} to the head without them`]),
        ...(deTanned <= 1 && lumaOf(tanned.pixels) < lumaOf(colours.caucasian.pixels) - 5 ? [] : [`tanned maps: mean dE2000 ${deTanned.toFixed(3)} to the tanned head`]),
        ...(cleared.maps === null && cleared.pixels.data.every((v, i) => v === colours.caucasian.pixels.data[i]) ? [] : ['cleared, the frame differs from the one before']),
      ], `fitted parameter maps (.exr, skin fit --texture) shade the head: its own colour's maps change it by ${deSame.toFixed(2)} dE2000, the tanned colour's give the tanned head within ${deTanned.toFixed(2)}; cleared, as before`);
      const badMaps = [];
      // An image of RGB channels (skin render's), not maps.
      require('child_process').execFileSync(SKIN, ['render', '--resolution', '8x8', '--spp', '1', '-o', path.join(dir, 'render.exr')], { stdio: 'pipe' });
      // Maps of the extended model: more channels than the view's grid spans (refused, not dropped).
      require('child_process').execFileSync(SKIN, ['fit', '--texture', path.join(dir, 'tanned.png'), '--model', 'extended', '-o', path.join(dir, 'extended.exr')], { stdio: 'pipe' });
      const cases = { 'garbage.exr': Buffer.from('not an exr at all'), 'truncated.exr': fs.readFileSync(path.join(dir, 'tanned.exr')).subarray(0, 400),
        'render.exr': fs.readFileSync(path.join(dir, 'render.exr')), 'extended.exr': fs.readFileSync(path.join(dir, 'extended.exr')) };
      for (const [name, bytes] of Object.entries(cases)) {
        const r = await page.evaluate(async (name, b64) => {
          const bytes = Uint8Array.from(atob(b64), (ch) => ch.charCodeAt(0));
          const ok = await skinView3d.loadFile(new File([bytes], name));
          const s = document.getElementById('view3d-file-status');
          return { ok, text: s.textContent, error: s.classList.contains('error'), maps: skinView3d.maps };
        }, name, bytes.toString('base64'));
        console.log(`  ${name}: ${r.text}`);
        if (r.ok || !r.error || !r.text.startsWith(`Not loaded: ${name}: `) || r.text.includes('\n') || r.maps !== null) badMaps.push(`${name}: ${JSON.stringify(r)}`);
      }
      check(badMaps, 'bad parameter-map files give one line each and load nothing');
    }

    // The Lee Perry-Smith head with the maps fitted from its own albedo (../shared/data; the
    // albedo drawn at 512 x 512 by the browser, fitted by the command line): the figure
    // build-web/screenshots/view3d-lps-maps.png, and the maps' status.
    {
      const albedo = path.join(ROOT, process.env.SKIN_HEAD_MESH_DIR || '../shared/data/meshes/LeePerrySmith', 'Map-COL.jpg');
      if (!hasMesh || !fs.existsSync(albedo)) {
        console.log(`SKIP the head with its fitted maps: no head mesh or no ${albedo}`);
      } else {
        const dir = fs.mkdtempSync(path.join(TMP, 'lps-'));
        const png = await page.evaluate(async (b64) => {
          const img = new Image();
          img.src = `data:image/jpeg;base64,${b64}`;
          await img.decode();
          const c = document.createElement('canvas');
          c.width = c.height = 512;
          c.getContext('2d').drawImage(img, 0, 0, 512, 512);
          return c.toDataURL('image/png').split(',')[1];
        }, fs.readFileSync(albedo).toString('base64'));
        fs.writeFileSync(path.join(dir, 'lps.png'), Buffer.from(png, 'base64'));
        const t0 = Date.now();
        require('child_process').execFileSync(SKIN, ['fit', '--texture', path.join(dir, 'lps.png'), '-o', path.join(dir, 'lps-maps.exr')], { stdio: 'pipe' });
        const fitS = (Date.now() - t0) / 1000;
        await page.click('#presets button[data-preset="caucasian"]');
        await ready(page);
        const plain = await page.evaluate(() => skinView3d.pixels());
        await picker.uploadFile(path.join(dir, 'lps-maps.exr'));
        await page.waitForFunction(() => window.skinView3d.maps && window.skinView3d.maps.name === 'lps-maps.exr' && window.skinView3d.paintReady && !window.skinBackgroundPending(), { timeout: 60000 });
        const lps = await page.evaluate(() => ({ pixels: skinView3d.pixels(), status: document.getElementById('view3d-file-status').textContent, ms: skinState.mapMs }));
        await (await page.$('#view3d')).screenshot({ path: path.join(shots, 'view3d-lps-maps.png') });
        const de = meanDeltaE(lps.pixels, plain);
        console.log(`  the head with its albedo's maps (fit ${fitS.toFixed(1)} s, grid ${lps.ms.toFixed(0)} ms): "${lps.status}"; mean dE2000 to the caucasian sliders' head ${de.toFixed(2)}`);
        check(/512 x 512 texels/.test(lps.status) && de > 1 ? [] : [`status "${lps.status}", mean dE2000 ${de.toFixed(2)}`],
          `the head shaded by the maps fitted from its own albedo (view3d-lps-maps.png): mean dE2000 ${de.toFixed(1)} from the uniform skin`);
        await page.click('#view3d-clear-maps');
      }
    }

    // A mesh of one's own, through the file picker and dropped; bad files.
    const tetra = 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n';
    const dir = fs.mkdtempSync(path.join(TMP, 'mesh-'));
    const files = { 'tetra.obj': tetra, 'empty-faces.obj': 'v 0 0 0\nv 1 0 0\n# no faces\n', 'garbage.glb': 'not a glb at all', 'notes.txt': 'hello' };
    for (const [name, text] of Object.entries(files)) fs.writeFileSync(path.join(dir, name), text);
    const label = await page.evaluate(() => document.querySelector('label[for="view3d-file"]')?.textContent || '');
    await picker.uploadFile(path.join(dir, 'tetra.obj'));
    await page.waitForFunction(() => /tetra\.obj/.test(document.getElementById('view3d-file-status').textContent), { timeout: 20000 });
    const own = await page.evaluate(() => ({ mesh: skinView3d.meshName, pixels: skinView3d.pixels(), status: document.getElementById('view3d-file-status').textContent }));
    const ownSkin = skinPixels(own.pixels);
    const ownLuma = ownSkin.reduce((s, i) => s + luma(own.pixels.data, i), 0) / Math.max(1, ownSkin.length);
    check(own.mesh === 'file' && ownSkin.length > 0.05 * own.pixels.width * own.pixels.height && ownLuma > 30 && /4 triangles/.test(own.status) && /mesh/i.test(label) ? []
      : [`mesh ${own.mesh}, ${ownSkin.length} pixels of luma ${ownLuma.toFixed(0)}, status "${own.status}", label "${label}"`],
    `a tetrahedron OBJ through the labelled file picker is shown, lit (${(100 * ownSkin.length / (own.pixels.width * own.pixels.height)).toFixed(0)} % of the view): "${own.status}"`);
    const bad = [];
    for (const name of ['empty-faces.obj', 'garbage.glb', 'notes.txt']) {
      const r = await page.evaluate(async (name, text) => {
        const before = document.getElementById('load-result').textContent;
        const ok = await skinView3d.loadFile(new File([text], name));
        const s = document.getElementById('view3d-file-status');
        return { ok, text: s.textContent, error: s.classList.contains('error'), mesh: skinView3d.meshName, spectrum: document.getElementById('load-result').textContent !== before };
      }, name, files[name]);
      console.log(`  ${name}: ${r.text}`);
      if (r.ok || !r.error || !r.text.startsWith(`Not loaded: ${name}: `) || r.text.includes('\n') || r.mesh !== 'file' || r.spectrum) bad.push(`${name}: ${JSON.stringify(r)}`);
    }
    // Dropped on the view (after a bad file: the view still works).
    const dropped = await page.evaluate(async (text) => {
      const dt = new DataTransfer();
      dt.items.add(new File([text], 'dropped.obj'));
      document.getElementById('view3d').dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
      const s = document.getElementById('view3d-file-status');
      for (let i = 0; i < 100 && !/dropped\.obj/.test(s.textContent); i++) await new Promise((r) => setTimeout(r, 50));
      return { text: s.textContent, error: s.classList.contains('error'), loaded: document.getElementById('load-result').textContent };
    }, tetra);
    if (!dropped.text.startsWith('Showing dropped.obj') || dropped.error || /dropped/.test(dropped.loaded)) bad.push(`drop: ${JSON.stringify(dropped)}`);
    check(bad, 'bad mesh files give one line each and keep the view; a mesh dropped on the view is shown');

    // Without the mesh: a sphere.
    await page.setRequestInterception(true);
    page.on('request', (req) => (req.url().endsWith('.glb') ? req.respond({ status: 404, body: '' }) : req.continue()));
    await page.goto(url + '?no-mesh#preset=african');  // a new document (a fragment alone is no reload)
    await ready(page);
    const sphere = await page.evaluate(() => ({ mesh: skinView3d.meshName, pixels: skinView3d.pixels(), credit: !document.getElementById('view3d-credit').hidden }));
    const sphereSkin = skinPixels(sphere.pixels);
    check(sphere.mesh === 'sphere' && !sphere.credit && sphereSkin.length > 0.1 * sphere.pixels.width * sphere.pixels.height ? []
      : [`mesh ${sphere.mesh}, credit ${sphere.credit}, ${sphereSkin.length} skin pixels`], 'without the head mesh, a lit sphere (no credit)');

  } finally {
    await close();
  }
  console.log(`${checks} checks${process.exitCode ? ', FAILED' : ''}`);
}

main().catch((e) => { console.error(e); process.exitCode = 1; });
