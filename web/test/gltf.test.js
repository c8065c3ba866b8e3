// The glTF export read by the tools people use: `skin export --target gltf` (the native build)
// for three presets, each file validated by Khronos' glTF-Validator (npm gltf-validator, pinned in
// web/package-lock.json: fails on any error; warnings and infos are counted and printed) and
// loaded by three.js's GLTFLoader (npm three, pinned), which must give a mesh with a
// MeshPhysicalMaterial holding the file's values (base colour, roughness, ior, specular
// intensity, thickness, attenuation). three.js reads KHR_materials_volume, _ior and _specular;
// it has no diffuse transmission or volume scattering (docs/export.md, "glTF").
// Run: node web/test/gltf.test.js (after the native build and `npm ci` in web/).
'use strict';
const fs = require('fs');
const path = require('path');
const { SKIN, cliExport } = require('./common');

const validator = require('gltf-validator');

const failures = [];
const fail = (what) => failures.push(what);
const near = (a, b, tol, what) => { if (!(Math.abs(a - b) <= tol * Math.max(1, Math.abs(b)))) fail(`${what}: ${a} != ${b}`); };

async function main() {
  if (!fs.existsSync(SKIN)) throw new Error(`${SKIN} is absent: build the native skin first`);
  // GLTFLoader is an ES module; in Node it parses a .gltf whose buffers are data: URIs (fetch)
  // and which has no textures. Its FileLoader reports progress with the browser's
  // ProgressEvent, which Node lacks: a minimal one.
  if (typeof globalThis.ProgressEvent === 'undefined') {
    globalThis.ProgressEvent = class ProgressEvent extends Event {
      constructor(type, init = {}) {
        super(type);
        Object.assign(this, { lengthComputable: false, loaded: 0, total: 0 }, init);
      }
    };
  }
  const { GLTFLoader } = await import('three/examples/jsm/loaders/GLTFLoader.js');
  const THREE = await import('three');
  const t0 = Date.now();
  const counts = { errors: 0, warnings: 0, infos: 0, hints: 0 };
  const unsupported = new Set();
  for (const preset of ['caucasian', 'african', 'pale']) {
    const files = cliExport('gltf', ['--preset', preset, '--solver', 'multipole'], {});
    const name = 'spectral_skin.gltf.gltf';
    if (!files[name]) { fail(`${preset}: skin export wrote ${Object.keys(files).join(' ')}`); continue; }
    const bytes = files[name];
    const doc = JSON.parse(bytes.toString('utf8'));

    // Khronos glTF-Validator: no error.
    const report = await validator.validateBytes(new Uint8Array(bytes), { uri: name, format: 'gltf', maxIssues: 0 });
    const issues = report.issues;
    counts.errors += issues.numErrors;
    counts.warnings += issues.numWarnings;
    counts.infos += issues.numInfos;
    counts.hints += issues.numHints;
    for (const m of issues.messages) {
      if (m.severity === 0) fail(`${preset}: validator error ${m.code} at ${m.pointer}: ${m.message}`);
      else if (m.code === 'UNSUPPORTED_EXTENSION') unsupported.add(doc.extensionsUsed[Number(m.pointer.split('/').pop())]);
      else console.log(`  ${preset}: validator severity ${m.severity} ${m.code} at ${m.pointer}: ${m.message}`);
    }
    if (report.info.materialCount !== 1 || report.info.drawCallCount !== 1) fail(`${preset}: validator info ${JSON.stringify(report.info)}`);

    // three.js: the scene's one mesh and its material.
    const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(bytes.toString('utf8'), '', resolve, reject));
    const meshes = [];
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
    if (meshes.length !== 1) { fail(`${preset}: three.js found ${meshes.length} meshes`); continue; }
    const mat = meshes[0].material;
    const src = doc.materials[0];
    const ext = src.extensions;
    if (!(mat instanceof THREE.MeshPhysicalMaterial)) fail(`${preset}: three.js material is ${mat.type}`);
    if (mat.name !== src.name) fail(`${preset}: material name ${mat.name}`);
    // three.js keeps colours in linear sRGB (its working colour space), as glTF's factors are.
    const base = src.pbrMetallicRoughness.baseColorFactor;
    near(mat.color.r, base[0], 1e-6, `${preset}: color.r`);
    near(mat.color.g, base[1], 1e-6, `${preset}: color.g`);
    near(mat.color.b, base[2], 1e-6, `${preset}: color.b`);
    near(mat.roughness, src.pbrMetallicRoughness.roughnessFactor, 1e-12, `${preset}: roughness`);
    near(mat.metalness, 0, 0, `${preset}: metalness`);
    near(mat.ior, ext.KHR_materials_ior.ior, 1e-12, `${preset}: ior`);
    near(mat.specularIntensity, ext.KHR_materials_specular.specularFactor, 1e-12, `${preset}: specularIntensity`);
    const vol = ext.KHR_materials_volume;
    near(mat.thickness, vol.thicknessFactor, 1e-12, `${preset}: thickness`);
    near(mat.attenuationDistance, vol.attenuationDistance, 1e-12, `${preset}: attenuationDistance`);
    ['r', 'g', 'b'].forEach((c, i) => near(mat.attenuationColor[c], vol.attenuationColor[i], 1e-6, `${preset}: attenuationColor.${c}`));
    if (!gltf.parser.json.materials[0].extras.spectral_skin.fit) fail(`${preset}: no fit report in extras`);
    const geo = meshes[0].geometry;
    if (geo.attributes.position.count !== 162 || geo.index.count !== 960) fail(`${preset}: geometry ${geo.attributes.position.count} vertices, ${geo.index.count} indices`);
  }
  const extra = [...unsupported].filter((e) => e !== 'KHR_materials_diffuse_transmission' && e !== 'KHR_materials_volume_scatter');
  if (extra.length) fail(`the validator does not know ${extra.join(', ')}`);
  console.log(`gltf: glTF-Validator ${validator.version()}: ${counts.errors} errors, ${counts.warnings} warnings, ${counts.infos} infos, ${counts.hints} hints over 3 presets` +
    ` (infos: extensions it cannot validate: ${[...unsupported].join(', ') || 'none'}); three.js r${THREE.REVISION} loaded each` +
    ` (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
}

main().then(() => {
  for (const f of failures) console.log('FAIL', f);
  if (failures.length) process.exitCode = 1;
}, (e) => { console.error(e); process.exitCode = 1; });
