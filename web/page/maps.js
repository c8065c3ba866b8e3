// Parameter maps as `skin fit --texture` writes them (docs/parameter-maps.md): an OpenEXR file,
// one part, scanlines, channels melanin, melanin_blend, hemoglobin and error. three.js's
// EXRLoader decodes only R, G, B, A and Y channels, so this reads the subset the maps use:
// scanline images of HALF or FLOAT channels, uncompressed or with ZIP (16 lines per chunk) or
// ZIPS (1) compression, the zlib streams inflated by the fflate copy three.js ships. Anything
// else is refused with one line that names what is allowed.
//   readParameterMaps(ArrayBuffer, name) -> {width, height, melanin, melanin_blend, hemoglobin,
//     error} (Float32Array each, row 0 the top row of the fitted texture)
import { unzlibSync } from 'three/addons/libs/fflate.module.js';
import { DataUtils } from 'three';

export const MAP_CHANNELS = ['melanin', 'melanin_blend', 'hemoglobin', 'error'];
export const MAX_MAP_SIDE = 4096;
const COMPRESSION = { 0: ['none', 1], 2: ['ZIPS', 1], 3: ['ZIP', 16] };

export function readParameterMaps(buffer, name) {
  const fail = (what) => { throw new Error(`${name}: ${what}`); };
  const bytes = new Uint8Array(buffer);
  const view = new DataView(buffer);
  let at = 0;
  const need = (n) => { if (at + n > bytes.length) fail('the file ends inside its header: it is truncated, or not an OpenEXR file'); };
  const u8 = () => { need(1); return bytes[at++]; };
  const i32 = () => { need(4); const v = view.getInt32(at, true); at += 4; return v; };
  const text = () => {
    const end = bytes.indexOf(0, at);
    if (end < 0 || end - at > 255) fail('a header name is not terminated: not an OpenEXR file');
    const s = new TextDecoder().decode(bytes.subarray(at, end));
    at = end + 1;
    return s;
  };
  if (bytes.length < 8 || view.getUint32(0, true) !== 20000630) fail('not an OpenEXR file (expected the parameter maps of skin fit --texture, .exr)');
  at = 4;
  const flags = i32();
  if ((flags & 0xff) !== 2) fail(`OpenEXR version ${flags & 0xff}: version 2 is allowed`);
  if (flags & 0x1a00) fail('tiled, deep or multi-part OpenEXR: only a single-part scanline file is allowed');
  const header = {};
  for (;;) {
    const key = text();
    if (key === '') break;
    const type = text();
    const size = i32();
    if (size < 0) fail(`header attribute ${key} has a negative size`);
    need(size);
    header[key] = { type, at, size };
    at += size;
  }
  const attribute = (key, type) => {
    const a = header[key];
    if (!a || a.type !== type) fail(`no ${key} (${type}) in the header: not an OpenEXR file`);
    return a;
  };
  // Channels: name, pixel type (1 HALF, 2 FLOAT), pLinear, 3 reserved, x and y sampling.
  const chl = attribute('channels', 'chlist');
  const channels = [];
  {
    const end = chl.at + chl.size;
    at = chl.at;
    for (;;) {
      const n = text();
      if (n === '') break;
      const type = i32();
      at += 4;  // pLinear, reserved
      const xs = i32(), ys = i32();
      if (at > end) fail('the channel list overruns its attribute');
      if (type !== 1 && type !== 2) fail(`channel ${n} holds integers: HALF or FLOAT channels are allowed`);
      if (xs !== 1 || ys !== 1) fail(`channel ${n} is subsampled: full-resolution channels are allowed`);
      channels.push({ name: n, bytes: type === 1 ? 2 : 4 });
    }
  }
  const missing = MAP_CHANNELS.slice(0, 3).filter((c) => !channels.some((ch) => ch.name === c));
  if (missing.length) fail(`no ${missing.join(', ')} channel: the maps of skin fit --texture (channels ${MAP_CHANNELS.join(', ')}) are allowed`);
  // Maps of the extended model (skin fit --model extended) carry a channel per other fitted
  // parameter (epidermis_thickness, ...); this view's colour grid spans the three above only, so
  // shading them would drop those maps silently.
  // (The layer "uncertainty." of skin fit --uncertainty describes the maps; it is not one.)
  const more = channels.filter((ch) => !MAP_CHANNELS.includes(ch.name) && !ch.name.startsWith('uncertainty.')).map((ch) => ch.name);
  if (more.length) fail(`channels ${more.join(', ')}: maps of the extended model are not shaded here (only ${MAP_CHANNELS.join(', ')}); fit with skin fit --model paper`);
  const comp = attribute('compression', 'compression');
  const code = bytes[comp.at];
  if (!(code in COMPRESSION)) fail(`compression ${code}: none, ZIP or ZIPS is allowed (skin fit --texture writes ZIP)`);
  const [, lines] = COMPRESSION[code];
  const dw = attribute('dataWindow', 'box2i');
  at = dw.at;
  const x0 = i32(), y0 = i32(), x1 = i32(), y1 = i32();
  const width = x1 - x0 + 1, height = y1 - y0 + 1;
  if (!(width >= 1 && height >= 1 && width <= MAX_MAP_SIDE && height <= MAX_MAP_SIDE))
    fail(`${width} x ${height} texels: 1 to ${MAX_MAP_SIDE} on each side is allowed`);
  // The offset table follows the header's terminating 0 (at points past it now).
  at = Object.values(header).reduce((end, a) => Math.max(end, a.at + a.size), 0);
  if (bytes[at] !== 0) fail('the header is not terminated');
  at += 1;
  const chunks = Math.ceil(height / lines);
  need(8 * chunks);
  const offsets = [];
  for (let c = 0; c < chunks; c++) offsets.push(Number(view.getBigUint64(at + 8 * c, true)));
  const rowBytes = channels.reduce((s, ch) => s + ch.bytes * width, 0);
  const out = {};
  for (const n of MAP_CHANNELS) out[n] = new Float32Array(width * height);
  for (let c = 0; c < chunks; c++) {
    at = offsets[c];
    if (!(at >= 0 && at + 8 <= bytes.length)) fail(`chunk ${c} lies outside the file: the file is truncated`);
    const y = view.getInt32(at, true) - y0, size = view.getInt32(at + 4, true);
    const rows = Math.min(lines, height - c * lines);
    // The offset table lists the blocks of lines in order: block c starts at line c x lines (so
    // each is read once, whatever order the file holds them in).
    if (y !== c * lines) fail(`chunk ${c} starts at line ${y + y0}, not ${c * lines + y0}: the file is damaged`);
    if (!(size >= 0 && at + 8 + size <= bytes.length)) fail(`chunk ${c} runs past the end of the file: the file is truncated`);
    const raw = bytes.subarray(at + 8, at + 8 + size);
    const expected = rows * rowBytes;
    let data = raw;
    if (code !== 0 && size < expected) {
      // Into a buffer one byte longer than the chunk's pixels: a stream that inflates to more
      // (a zip bomb included) is cut there and refused below, without the memory.
      let t;
      try { t = unzlibSync(raw, { out: new Uint8Array(expected + 1) }); } catch (e) { fail(`chunk ${c} does not inflate (${e.message}): the file is damaged`); }
      if (t.length !== expected) fail(`chunk ${c} inflates to ${t.length} bytes, not ${expected}: the file is damaged`);
      // fflate does not check the stream's Adler-32 (its last 4 bytes, big-endian): a changed
      // byte that still inflates to the right size would be read as other values.
      let a1 = 1, a2 = 0;
      for (let i = 0; i < t.length; i++) {
        a1 = (a1 + t[i]) % 65521;
        a2 = (a2 + a1) % 65521;
      }
      const sum = raw.length >= 4 ? new DataView(raw.buffer, raw.byteOffset + raw.length - 4, 4).getUint32(0, false) : -1;
      if (((a2 << 16) | a1) >>> 0 !== sum) fail(`chunk ${c} fails its checksum: the file is damaged`);
      // OpenEXR's ZIP: a byte predictor, then the even and odd bytes interleaved.
      for (let i = 1; i < t.length; i++) t[i] = (t[i - 1] + t[i] - 128) & 0xff;
      data = new Uint8Array(expected);
      const half = (expected + 1) >> 1;
      for (let i = 0; i < expected; i++) data[i] = (i & 1) ? t[half + (i >> 1)] : t[i >> 1];
    } else if (size !== expected) {
      fail(`chunk ${c} holds ${size} bytes, not ${expected}: the file is damaged`);
    }
    const dv = new DataView(data.buffer, data.byteOffset, data.byteLength);
    let p = 0;
    for (let r = 0; r < rows; r++) {
      for (const ch of channels) {
        const dst = out[ch.name];
        const base = (y + r) * width;
        for (let x = 0; x < width; x++, p += ch.bytes) {
          if (!dst) continue;
          dst[base + x] = ch.bytes === 4 ? dv.getFloat32(p, true) : DataUtils.fromHalfFloat(dv.getUint16(p, true));
        }
      }
    }
  }
  const bad = MAP_CHANNELS.slice(0, 3).find((n) => out[n].some((v) => !Number.isFinite(v) || v < 0 || v > 1));
  if (bad) fail(`channel ${bad} holds values outside [0, 1] or not numbers: fitted parameter maps are allowed`);
  return { width, height, ...out };
}
