// CPU time of the page's full update in Node (the same module as the page, build-web/site/skin.js):
// `update` (accurate R_d spectrum at 2 nm with the layer coefficients and the colour, and the
// RGB profile at 256 radii, as JSON text) plus JSON.parse of its answer, for a sweep of melanin
// as a slider gives it. Reports the median and spread of each call's CPU time (user + sys of
// this process: Node runs the module on one thread; a loaded machine inflates wall-clock time
// but much less CPU time), the wall-clock time beside it, the parts (`spectrum` alone, `profile`
// alone, JSON.parse) and the load average.
// Run: node web/bench/update-time.js [CALLS]  (after scripts/web.sh)
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');
const { performance } = require('perf_hooks');

const SITE = process.env.SKIN_WEB_SITE || path.join(__dirname, '..', '..', 'build-web', 'site');
const calls = Number(process.argv[2] || 200);

function stats(a) {
  const s = [...a].sort((x, y) => x - y), q = (f) => s[Math.min(s.length - 1, Math.floor(f * s.length))];
  return { median: q(0.5), p10: q(0.1), p90: q(0.9), min: s[0], max: s[s.length - 1] };
}
const show = (s) => `median ${s.median.toFixed(2)} ms (10-90% ${s.p10.toFixed(2)}-${s.p90.toFixed(2)}, min ${s.min.toFixed(2)}, max ${s.max.toFixed(2)})`;

require(path.join(SITE, 'skin.js'))({ wasmBinary: fs.readFileSync(path.join(SITE, 'skin.wasm')) }).then((m) => {
  const request = (i) => JSON.stringify({ preset: 'caucasian', solver: 'accurate', params: { melanin: 0.01 + 0.002 * (i % 100) } });
  const time = (f) => {
    const cpu = [], wall = [];
    for (let i = 0; i < 10; i++) f(i);  // warm-up: the profile solver's quadrature, the JIT
    for (let i = 0; i < calls; i++) {
      const c0 = process.cpuUsage(), t0 = performance.now();
      f(i);
      const t1 = performance.now(), c = process.cpuUsage(c0);
      wall.push(t1 - t0);
      cpu.push((c.user + c.system) / 1000);
    }
    return { cpu: stats(cpu), wall: stats(wall) };
  };
  const load = os.loadavg()[0];
  const update = time((i) => JSON.parse(m.run('update', request(i))));
  const spectrum = time((i) => m.run('spectrum', request(i)));
  const profile = time((i) => m.run('profile', request(i)));
  const text = m.run('update', request(0));
  const parse = time(() => JSON.parse(text));
  console.log(`full update (module + JSON.parse), ${calls} calls, load average ${load.toFixed(1)} -> ${os.loadavg()[0].toFixed(1)}, ${os.cpus()[0].model}`);
  console.log(`  CPU  ${show(update.cpu)}`);
  console.log(`  wall ${show(update.wall)}`);
  console.log(`parts (CPU): spectrum ${spectrum.cpu.median.toFixed(2)} ms, profile --rgb ${profile.cpu.median.toFixed(2)} ms, ` +
              `JSON.parse of the update (${(text.length / 1024).toFixed(0)} KiB) ${parse.cpu.median.toFixed(2)} ms`);
}).catch((e) => { console.error(e); process.exitCode = 1; });
