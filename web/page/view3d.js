// The page's 3D view (#view3d): the skin of the current parameters on a head (the Lee Perry-Smith
// scan when the site holds it, a sphere otherwise), lit by a key, a fill and a back light of the
// page's illuminant, drawn with three.js in WebGL2. Physics comes from the module, as the page's
// other results do; this file only shades with it:
//   - the albedo is the model's colour, R_d in linear sRGB (the swatch's, `skin color`);
//   - the subsurface is the real-time export's sum of Gaussians (`skin export --target realtime`,
//     the module's "export" command): the diffuse irradiance blurred in screen space by each
//     Gaussian as two separable passes, weighted per channel by its share of R_d (d'Eon, Luebke &
//     Enderton 2007; Jimenez et al. 2009), and the light through thin parts (the ears) from the
//     same Gaussians at the thickness a depth map from the back light gives (Jimenez, Whelan,
//     Sundstedt & Gutierrez 2010): T(s) = sum_k w_k exp(-s^2 / (2 v_k));
//   - the surface is DJ06's Torrance-Sparrow lobe: Beckmann of RMS slope `roughness`, dielectric
//     Fresnel at `eta`, Cook-Torrance shadowing, scaled by `oiliness` (rho_s);
//   - each light casts shadows (its orthographic depth map, 3 x 3 samples), before the blur, so
//     that light bleeds across a shadow's edge as it does in the skin.
// A light's value is its irradiance / pi: under the key light head-on, a patch reads R_d (the
// swatch), as `skin render` draws it under irradiance pi (renderScene gives that scene).
//   - a blush or pallor brush paints k_h (the blood times 2^k_h), a tan or lighten brush k_m (the
//     melanin times 2^k_m) over the texture coordinates; the albedo is multiplied, after the
//     blur, by the model's colour at the painted values over that at the sliders' (a grid of
//     colours around them from the module via app.js, setMapColours);
//   - parameter maps of `skin fit --texture` (loadMaps, .exr) set melanin, melanin_blend and
//     hemoglobin per texel: after the blur, the model's colour at the texel's values (trilinear
//     in a grid the module computes, setMapColours) takes the place of the sliders' colour; the
//     subsurface kernels stay the sliders'.
// Not modelled: the transmission factor 1 - rho_dr at entry and exit (about 1 % at normal
// incidence for the presets), interreflections, kernels that vary over the maps.
// Frames are drawn on demand: after an update of the page, a change of the camera, or new kernels.
//
// window.skinView3d (the page and its tests): update(parameters), setKernels(export document),
// setLight(rgb), setMode('head' | 'patch'), pixels() (a frame drawn and read back, RGBA bytes,
// bottom row first), frames (count of frames drawn), lastFrame (performance.now() at its end),
// litFrames (of them, those that redrew the light before the composite), renderScene(mesh,
// material) (the view as a `skin render` scene), getCamera()/setCamera(), setLights({fill, back})
// and lights (one to three lights: the key always, the fill and the back light on or off),
// loadFile(File), setBrush('turn' | 'blush' | 'pallor' | 'tan' | 'lighten'), clearPaint(),
// loadMaps(File), mapAxes(centre, most), setMapColours(axes, colours, centre), clearMaps(), maps,
// painted, paintReady (the grid for the maps or paint is in).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { readParameterMaps } from './maps.js';

const HEAD_URL = 'mesh/LeePerrySmith.glb';
// The scan (a bust) is taken as 400 mm wide, shoulder to shoulder, which makes its head about
// 230 mm from chin to crown, an adult's; the sphere's radius is 80 mm.
const BUST_WIDTH_MM = 400;
const SPHERE_RADIUS_MM = 80;
// A mesh of one's own (loadFile) is taken as 250 mm across its largest side, a head's size (glTF
// says metres, but scans seldom keep to it, and OBJ has no unit).
const FILE_SIZE_MM = 250;
const MAX_FILE_BYTES = 64 * 1024 * 1024;
// The lights (directions towards the light in world space; y up, the face looks along +z), their
// intensity times the illuminant's colour of luminance 1: a key light, a fill, a back light.
const KEY = { dir: new THREE.Vector3(0.6, 0.45, 0.66).normalize(), intensity: 1.0 };
const FILL = { dir: new THREE.Vector3(-0.8, 0.1, 0.45).normalize(), intensity: 0.25 };
const BACK = { dir: new THREE.Vector3(-0.25, 0.25, -1).normalize(), intensity: 1.5 };
const MAX_GAUSSIANS = 8;
// The brushes: a map of (k_h, k_m) over the mesh's texture coordinates (the blood times 2^k_h and
// the melanin times 2^k_m; 0 unpainted), PAINT_MAP texels square; a stroke's dab adds DAB_STOPS x
// a Gaussian of standard deviation DAB_RADIUS (in texture coordinates) to k_h (blush +, pallor
// -) or k_m (tan +, lighten -), within [-MAX_STOPS, MAX_STOPS].
const PAINT_MAP = 256;
const BRUSHES = { turn: null, blush: [0, 1], pallor: [0, -1], tan: [1, 1], lighten: [1, -1] };
const MAX_STOPS = 2;
const DAB_STOPS = 0.5;
const DAB_RADIUS = 0.012;
const MAX_WIDTH = 480;
// Parameter maps (loadMaps): at most MAX_MAP_BYTES of file; the model's colour on MAP_NODES
// (melanin, melanin_blend, hemoglobin) nodes over their ranges (widened by the brushes' 2^+-2),
// the fractions floored at MAP_FLOOR for the logarithmic axes. The grid's ln colour is
// interpolated trilinearly: with 12 x 4 x 12 nodes over the ranges of the Lee Perry-Smith
// albedo's maps (1024 x 1024), within 0.15 dE2000 of the model at the median texel and 0.29 at
// worst (300 texels); over the whole box of those ranges 0.31 at worst (200 points; the colour
// itself interpolated: 1.2 with 12 x 3 x 12); tested within 0.5 (web/test/module.test.js). Melanin
// gets 14 nodes for its range widened by the tan and lighten brushes. The grid's 672 colours
// take ~2 s in the module.
const MAX_MAP_BYTES = 512 * 1024 * 1024;
const MAP_NODES = [14, 4, 12];
const MAP_FLOOR = 1e-4;
const BACKGROUND = [0.12, 0.12, 0.13];  // display-encoded

const canvas = document.getElementById('view3d');
const caption = document.getElementById('view3d-caption');
const fileStatus = document.getElementById('view3d-file-status');
// One line under the view about a file it was given (a mesh or parameter maps).
function sayFile(text, error) {
  if (fileStatus) { fileStatus.textContent = text; fileStatus.className = error ? 'note error' : 'note muted'; }
}

const fullscreenVertex = /* glsl */`
out vec2 vUv;
void main() { vUv = uv; gl_Position = vec4(position.xy, 0.0, 1.0); }`;

// The surface pass: to attachment 0 the diffuse irradiance (no albedo) and the view depth (alpha,
// in mesh units; 0 is the background), to attachment 1 the normal (towards the camera), to 2 the
// tint, to 3 each light's visibility (its shadow); the specular pass draws the lobe from them.
const surfaceVertex = /* glsl */`
out vec3 vNormal;
out vec3 vWorld;
out float vDepth;
out vec2 vUv;
void main() {
  vUv = uv;
  vec4 world = modelMatrix * vec4(position, 1.0);
  vWorld = world.xyz;
  vNormal = normalize(mat3(modelMatrix) * normal);
  vec4 view = viewMatrix * world;
  vDepth = -view.z;
  gl_Position = projectionMatrix * view;
}`;
const surfaceFragment = /* glsl */`
precision highp float;
in vec3 vNormal;
in vec3 vWorld;
in float vDepth;
in vec2 vUv;
layout(location = 0) out vec4 outIrradiance;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outTint;  // the painted colour over the unpainted, per channel (alpha 1), or the maps' colour (alpha 0)
layout(location = 3) out vec4 outVisible;  // the key, fill and back light's visibility
uniform bool painted;
uniform sampler2D paintMap;   // (k_h, k_m): the blood times 2^k_h, the melanin times 2^k_m
// Fitted parameter maps (loadMaps): melanin, melanin_blend, hemoglobin per texel, shaded by the
// model's colour over a grid of them (setMapColours: ln melanin, melanin_blend, ln hemoglobin
// from lutLo over lutSpan, lutSize nodes; the grid holds ln of the colour, interpolated
// trilinearly here in 32-bit floats), in place of the sliders' colour. Without maps, paint is
// the grid's colour at the painted values over its colour at the unpainted ones (lutCentre, the
// sliders' values the grid was made for), a factor on the sliders' colour.
uniform bool mapped;
uniform sampler2D paramMap;
uniform highp sampler3D lut;
uniform vec3 lutLo, lutSpan, lutCentre;
uniform ivec3 lutSize;
vec3 mapColour(vec3 x) {
  vec3 f = clamp((x - lutLo) / lutSpan, 0.0, 1.0) * vec3(lutSize - 1);
  ivec3 i0 = min(ivec3(floor(f)), max(lutSize - 2, ivec3(0)));
  vec3 w = f - vec3(i0);
  vec3 sum = vec3(0.0);
  for (int c = 0; c < 8; ++c) {
    ivec3 d = ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    vec3 wd = mix(1.0 - w, w, vec3(d));
    sum += wd.x * wd.y * wd.z * texelFetch(lut, min(i0 + d, lutSize - 1), 0).rgb;
  }
  return exp(sum);
}
uniform vec3 lightDir[3];
uniform vec3 lightColor[3];   // each light's intensity (the illuminant's colour is the composite's)
uniform float mmPerUnit;
uniform int gaussians;
uniform float variance[${MAX_GAUSSIANS}];   // mm^2
uniform vec3 share[${MAX_GAUSSIANS}];       // w_k / R_d per channel
uniform bool translucency;
// Each light's depth map (orthographic, 0-1 between its near and far planes), for its shadow and
// (the back light's) the thickness the light crosses.
uniform sampler2D keyDepth, fillDepth, backDepth;
uniform mat4 lightMatrix[3];  // world -> the light's clip space
uniform float lightNear[3], lightFar[3];
uniform float shadowOffset;   // a depth map's texel (mesh units): the normal offset and the bias
uniform bool shadows;
uniform vec3 cameraPos;
const float PI = 3.141592653589793;

vec3 transmittance(float s_mm) {
  vec3 t = vec3(0.0);
  for (int k = 0; k < ${MAX_GAUSSIANS}; ++k) {
    if (k >= gaussians) break;
    t += share[k] * exp(-s_mm * s_mm / (2.0 * variance[k]));
  }
  return t;
}
// The share of light i reaching the point world (normal n): 3 x 3 depth-map samples
// (percentage closer filtering), the point moved along its normal by a texel and a half.
float lit(sampler2D depth, int i, vec3 world, vec3 n) {
  if (!shadows) return 1.0;
  vec4 p = lightMatrix[i] * vec4(world + n * (1.5 * shadowOffset), 1.0);
  vec3 q = p.xyz / p.w * 0.5 + 0.5;
  float here = lightNear[i] + q.z * (lightFar[i] - lightNear[i]);
  vec2 texel = 1.0 / vec2(textureSize(depth, 0));
  float sum = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x) {
      float entry = lightNear[i] + texture(depth, q.xy + vec2(x, y) * texel).r * (lightFar[i] - lightNear[i]);
      sum += here <= entry + shadowOffset ? 1.0 : 0.0;
    }
  return sum / 9.0;
}
void main() {
  vec3 n = normalize(vNormal);
  vec3 wo = normalize(cameraPos - vWorld);
  if (dot(n, wo) < 0.0) n = -n;  // open meshes seen from inside
  vec3 E = vec3(0.0);
  float visible[3];
  visible[0] = dot(n, lightDir[0]) > 0.0 ? lit(keyDepth, 0, vWorld, n) : 0.0;
  visible[1] = dot(n, lightDir[1]) > 0.0 ? lit(fillDepth, 1, vWorld, n) : 0.0;
  visible[2] = dot(n, lightDir[2]) > 0.0 ? lit(backDepth, 2, vWorld, n) : 0.0;
  for (int i = 0; i < 3; ++i) {
    float ni = dot(n, lightDir[i]);
    E += lightColor[i] * max(ni, 0.0) * visible[i];
  }
  if (translucency) {
    // The back light through the skin: the thickness between this point and where the light
    // enters, from the back light's depth map, through the profile's Gaussians.
    vec4 p = lightMatrix[2] * vec4(vWorld, 1.0);
    vec3 q = p.xyz / p.w * 0.5 + 0.5;
    float entry = lightNear[2] + texture(backDepth, q.xy).r * (lightFar[2] - lightNear[2]);
    float here = lightNear[2] + q.z * (lightFar[2] - lightNear[2]);
    float s = max(here - entry, 0.0) * mmPerUnit;
    float facing = clamp(0.3 + dot(-n, lightDir[2]), 0.0, 1.0);
    E += lightColor[2] * transmittance(s) * facing;
  }
  outIrradiance = vec4(E, vDepth);
  outNormal = vec4(n, 1.0);
  outVisible = vec4(visible[0], visible[1], visible[2], 1.0);
  outTint = vec4(1.0);
  // The brushes scale the blood and the melanin (times 2^k, at most 1) of the maps or the sliders.
  vec2 k = painted ? texture(paintMap, vUv).rg : vec2(0.0);
  if (mapped) {
    vec3 q = texture(paramMap, vUv).rgb;
    float h = min(1.0, q.b * exp2(k.x)), m = min(1.0, q.r * exp2(k.y));
    vec3 c = mapColour(vec3(log(max(m, 1e-6)), q.g, log(max(h, 1e-6))));
    outTint = vec4(c, 0.0);  // (alpha 0: the colour itself, not a factor on the albedo)
  } else if (painted && k != vec2(0.0)) {
    vec3 x0 = vec3(log(max(lutCentre.x, 1e-6)), lutCentre.y, log(max(lutCentre.z, 1e-6)));
    vec3 x = vec3(log(max(min(1.0, lutCentre.x * exp2(k.y)), 1e-6)), lutCentre.y, log(max(min(1.0, lutCentre.z * exp2(k.x)), 1e-6)));
    outTint = vec4(mapColour(x) / max(mapColour(x0), vec3(1e-9)), 1.0);
  }
}`;

// The specular pass: DJ06's Torrance-Sparrow lobe of each light, from the surface pass's normal,
// visibility and depth (the direction to the camera from the pixel's ray), so that roughness and
// eta redraw this pass and the composite, not the surface pass and the blur. A light's value is
// irradiance / pi (see the composite).
const specularFragment = /* glsl */`
precision highp float;
in vec2 vUv;
out vec4 outColor;
uniform sampler2D irradiance, normals, visibility;
uniform vec3 lightDir[3];
uniform vec3 lightColor[3];
uniform float roughness, eta;
uniform bool specular;
uniform mat3 cameraRotation;   // view -> world
uniform vec2 tanHalfFov;       // x: times the aspect
const float PI = 3.141592653589793;
float fresnelDielectric(float cosi, float etaT) {
  // Unpolarised Fresnel reflectance from air into a medium of index etaT.
  float c = clamp(cosi, 0.0, 1.0);
  float s2 = max(0.0, 1.0 - c * c) / (etaT * etaT);
  if (s2 >= 1.0) return 1.0;
  float ct = sqrt(1.0 - s2);
  float rs = (c - etaT * ct) / (c + etaT * ct);
  float rp = (etaT * c - ct) / (etaT * c + ct);
  return 0.5 * (rs * rs + rp * rp);
}
// D(h) G F(wi.h) / (4 cos_i cos_o), times cos_i: the reflected radiance per unit light and unit
// rho_s.
float torranceSparrow(vec3 n, vec3 wo, vec3 wi) {
  float no = dot(n, wo), ni = dot(n, wi);
  if (no <= 0.0 || ni <= 0.0) return 0.0;
  vec3 h = normalize(wo + wi);
  float c = dot(n, h);
  if (c <= 0.0) return 0.0;
  float c2 = c * c, s2 = roughness * roughness;
  float D = exp(-(1.0 - c2) / (c2 * s2)) / (PI * s2 * c2 * c2);
  float oh = max(dot(wo, h), 1e-6);
  float G = min(1.0, min(2.0 * c * no / oh, 2.0 * c * ni / oh));
  float F = fresnelDielectric(dot(wi, h), eta);
  return D * G * F / (4.0 * no);  // (times rho_s in the composite)
}
void main() {
  if (!specular || texture(irradiance, vUv).a <= 0.0) { outColor = vec4(0.0); return; }
  vec3 n = texture(normals, vUv).xyz;
  vec3 visible = texture(visibility, vUv).rgb;
  vec3 ray = vec3((2.0 * vUv - 1.0) * tanHalfFov, -1.0);
  vec3 wo = normalize(cameraRotation * -ray);
  vec3 S = vec3(0.0);
  for (int i = 0; i < 3; ++i) S += lightColor[i] * PI * torranceSparrow(n, wo, lightDir[i]) * visible[i];
  outColor = vec4(S, 1.0);
}`;

// One separable pass of one Gaussian (standard deviation sigma mm) along `direction`, over the
// surface pass's irradiance: 13 taps out to 3 sigma, samples of the background or off the surface
// (a depth step larger than the kernel) left out and the rest renormalised, so that uniform light
// stays uniform. The pixels per mm at the centre's depth from the camera's field of view.
const blurFragment = /* glsl */`
precision highp float;
in vec2 vUv;
out vec4 outColor;
uniform sampler2D source;
uniform vec2 direction;     // (1, 0) or (0, 1)
uniform vec2 texel;         // 1 / size
uniform float sigmaMm;
uniform float pixelsPerUnitAtUnitDepth;  // height / (2 tan(fov / 2))
uniform float mmPerUnit;
uniform vec3 weight;        // the Gaussian's share per channel (vertical pass), 1 (horizontal)
void main() {
  vec4 c = texture(source, vUv);
  if (c.a <= 0.0) { outColor = vec4(0.0); return; }
  float sigmaPx = sigmaMm / mmPerUnit * pixelsPerUnitAtUnitDepth / c.a;
  float maxStep = max(3.0 * sigmaMm, 0.5) / mmPerUnit;
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  for (int i = -6; i <= 6; ++i) {
    float t = float(i) * 0.5;           // in sigmas
    vec4 s = texture(source, vUv + direction * texel * t * sigmaPx);
    float w = exp(-0.5 * t * t);
    if (s.a <= 0.0 || abs(s.a - c.a) > maxStep) continue;
    sum += w * s.rgb;
    wsum += w;
  }
  outColor = vec4(weight * sum / wsum, c.a);
}`;

// The unblurred part (the Gaussians narrower than a pixel) into the sum.
const shareFragment = /* glsl */`
precision highp float;
in vec2 vUv;
out vec4 outColor;
uniform sampler2D source;
uniform vec3 weight;
void main() { vec4 c = texture(source, vUv); outColor = vec4(weight * c.rgb, c.a); }`;

// The frame: the illuminant's colour x (albedo x scattered irradiance + rho_s x specular), encoded
// as sRGB (IEC 61966-2-1). The passes before it hold the light of white lights, per unit albedo
// and rho_s, so that a change of the colour, rho_s or the illuminant redraws this pass alone
// (render()). The tint is a factor on the albedo (alpha 1: the brush) or the colour (alpha 0:
// parameter maps).
const compositeFragment = /* glsl */`
precision highp float;
in vec2 vUv;
out vec4 outColor;
uniform sampler2D diffuse, irradiance, specular, tint;
uniform vec3 albedo, light;
uniform float rhoS;
uniform vec3 background;
float encode(float x) { x = clamp(x, 0.0, 1.0); return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
void main() {
  if (texture(irradiance, vUv).a <= 0.0) { outColor = vec4(background, 1.0); return; }
  vec4 t = texture(tint, vUv);
  vec3 a = t.a > 0.5 ? albedo * t.rgb : t.rgb;
  vec3 L = light * (a * texture(diffuse, vUv).rgb + rhoS * texture(specular, vUv).rgb);
  outColor = vec4(encode(L.r), encode(L.g), encode(L.b), 1.0);
}`;

function pass(fragmentShader, uniforms, blending = THREE.NoBlending) {
  const material = new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3, vertexShader: fullscreenVertex, fragmentShader, uniforms,
    depthTest: false, depthWrite: false, blending,
  });
  if (blending === THREE.CustomBlending) {
    Object.assign(material, { blendSrc: THREE.OneFactor, blendDst: THREE.OneFactor, blendEquation: THREE.AddEquation,
      blendSrcAlpha: THREE.ZeroFactor, blendDstAlpha: THREE.OneFactor });
  }
  const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
  mesh.frustumCulled = false;
  const scene = new THREE.Scene();
  scene.add(mesh);
  return { scene, uniforms: material.uniforms };
}

// A File as a three.js object of triangle meshes with normals, or an Error saying why not.
async function parseMesh(file) {
  const name = file.name.toLowerCase();
  const kind = name.endsWith('.glb') || name.endsWith('.gltf') ? 'gltf' : name.endsWith('.obj') ? 'obj' : '';
  if (!kind) throw new Error('not a .glb, .gltf or .obj file');
  if (file.size === 0) throw new Error('the file is empty');
  if (file.size > MAX_FILE_BYTES) throw new Error(`the file is larger than ${MAX_FILE_BYTES >> 20} MB`);
  let object;
  if (kind === 'gltf') {
    const data = await file.arrayBuffer();
    const gltf = await new Promise((resolve, reject) => {
      try {
        new GLTFLoader().parse(data, '', resolve, (e) => reject(new Error(`not a readable glTF file (${e && e.message ? e.message : e})`)));
      } catch (e) { reject(new Error(`not a readable glTF file (${e.message})`)); }
    });
    object = gltf.scene;
  } else {
    try {
      object = new OBJLoader().parse(await file.text());
    } catch (e) { throw new Error(`not a readable OBJ file (${e.message})`); }
  }
  // Only triangle meshes with finite positions; normals made where the file has none.
  const keep = [];
  object.traverse((o) => {
    if (!o.isMesh || !o.geometry || !o.geometry.attributes.position) return;
    const g = o.geometry;
    const count = g.index ? g.index.count : g.attributes.position.count;
    if (count < 3 || (o.drawMode !== undefined && o.drawMode !== THREE.TrianglesDrawMode)) return;
    const p = g.attributes.position.array;
    for (let i = 0; i < p.length; i++) if (!Number.isFinite(p[i])) throw new Error('a vertex position is not a finite number');
    if (!g.attributes.normal) g.computeVertexNormals();
    keep.push(o);
  });
  if (keep.length === 0) throw new Error('no triangles in the file');
  object.traverse((o) => { if ((o.isLine || o.isPoints) && o.parent) o.visible = false; });
  const size = new THREE.Box3().setFromObject(object).getSize(new THREE.Vector3());
  if (!(Math.max(size.x, size.y, size.z) > 0) || !Number.isFinite(size.length())) throw new Error('the mesh has no extent');
  return object;
}

function createView() {
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: false, powerPreference: 'high-performance' });
  } catch (e) {
    caption.textContent = `No 3D view: WebGL2 is not available in this browser (${e.message}).`;
    return null;
  }
  renderer.autoClear = false;
  const gl = renderer.getContext();
  const camera = new THREE.PerspectiveCamera(30, 1, 0.1, 1000);
  const ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  const controls = new OrbitControls(camera, canvas);
  controls.enableDamping = false;

  const surfaceUniforms = {
    lightDir: { value: [KEY.dir, FILL.dir, BACK.dir].map((d) => d.clone()) },
    lightColor: { value: [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()] },
    mmPerUnit: { value: 1 },
    gaussians: { value: 0 },
    variance: { value: new Array(MAX_GAUSSIANS).fill(1) },
    share: { value: Array.from({ length: MAX_GAUSSIANS }, () => new THREE.Vector3()) },
    translucency: { value: true },
    keyDepth: { value: null }, fillDepth: { value: null }, backDepth: { value: null },
    lightMatrix: { value: [new THREE.Matrix4(), new THREE.Matrix4(), new THREE.Matrix4()] },
    lightNear: { value: [0, 0, 0] }, lightFar: { value: [1, 1, 1] },
    shadowOffset: { value: 0 }, shadows: { value: true },
    painted: { value: false }, paintMap: { value: null },
    cameraPos: { value: new THREE.Vector3() },
    mapped: { value: false }, paramMap: { value: null }, lut: { value: null },
    lutLo: { value: new THREE.Vector3() }, lutSpan: { value: new THREE.Vector3(1, 1, 1) }, lutCentre: { value: new THREE.Vector3() },
    lutSize: { value: [1, 1, 1] },
  };
  const surface = new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3, vertexShader: surfaceVertex, fragmentShader: surfaceFragment,
    uniforms: surfaceUniforms, side: THREE.DoubleSide,
  });
  const depthMaterial = new THREE.MeshDepthMaterial({ side: THREE.DoubleSide });

  const scene = new THREE.Scene();
  const holder = new THREE.Group();
  scene.add(holder);
  // Each light's orthographic depth map (the key's finest: its shadows are the ones on the face).
  const lightViews = [[KEY, 2048, 'keyDepth'], [FILL, 1024, 'fillDepth'], [BACK, 1024, 'backDepth']].map(([light, size, name]) => {
    const target = new THREE.WebGLRenderTarget(size, size, {
      depthTexture: new THREE.DepthTexture(size, size, THREE.UnsignedIntType), depthBuffer: true,
    });
    surfaceUniforms[name].value = target.depthTexture;
    return { light, size, target, camera: new THREE.OrthographicCamera(-1, 1, 1, -1, 0.1, 100) };
  });

  const rt = (count = 1) => new THREE.WebGLRenderTarget(1, 1, {
    type: THREE.HalfFloatType, format: THREE.RGBAFormat, count, depthBuffer: count > 1,
    minFilter: THREE.LinearFilter, magFilter: THREE.LinearFilter,
  });
  const gbuffer = rt(4), horizontal = rt(), sum = rt(), specularTarget = rt();
  let mapTexture = null, lutTexture = null;
  // The brushes' map ((k_h, k_m) per texel; half floats, filtered).
  const paintK = new Float32Array(2 * PAINT_MAP * PAINT_MAP);
  const paintTexture = new THREE.DataTexture(new Uint16Array(2 * PAINT_MAP * PAINT_MAP), PAINT_MAP, PAINT_MAP, THREE.RGFormat, THREE.HalfFloatType);
  paintTexture.minFilter = paintTexture.magFilter = THREE.LinearFilter;
  paintTexture.wrapS = paintTexture.wrapT = THREE.ClampToEdgeWrapping;
  paintTexture.needsUpdate = true;
  surfaceUniforms.paintMap.value = paintTexture;
  const blur = pass(blurFragment, {
    source: { value: null }, direction: { value: new THREE.Vector2() }, texel: { value: new THREE.Vector2() },
    sigmaMm: { value: 1 }, pixelsPerUnitAtUnitDepth: { value: 1 }, mmPerUnit: { value: 1 }, weight: { value: new THREE.Vector3(1, 1, 1) },
  });
  const blurAdd = pass(blurFragment, blur.uniforms, THREE.CustomBlending);
  const share = pass(shareFragment, { source: { value: null }, weight: { value: new THREE.Vector3() } });
  const specularPass = pass(specularFragment, {
    irradiance: { value: gbuffer.textures[0] }, normals: { value: gbuffer.textures[1] }, visibility: { value: gbuffer.textures[3] },
    lightDir: surfaceUniforms.lightDir, lightColor: surfaceUniforms.lightColor,
    roughness: { value: 0.35 }, eta: { value: 1.4 }, specular: { value: true },
    cameraRotation: { value: new THREE.Matrix3() }, tanHalfFov: { value: new THREE.Vector2(1, 1) },
  });
  const composite = pass(compositeFragment, {
    diffuse: { value: sum.texture }, irradiance: { value: gbuffer.textures[0] }, specular: { value: specularTarget.texture }, tint: { value: gbuffer.textures[2] },
    albedo: { value: new THREE.Vector3(0.5, 0.4, 0.35) }, light: { value: new THREE.Vector3(1, 1, 1) }, rhoS: { value: 0.3 }, background: { value: new THREE.Vector3(...BACKGROUND) },
  });

  const view = {
    frames: 0, litFrames: 0, lastFrame: 0, frameTimes: [], mode: 'head', mesh: null, meshName: '',
    parameters: { oiliness: 0.3, roughness: 0.35, eta: 1.4 }, albedo: [0.5, 0.4, 0.35], light: [1, 1, 1],
    kernels: null,  // {variance: [mm^2], share: [[r, g, b]]}
    brush: 'turn', painted: false,
    lights: { fill: true, back: true },  // the key light is always on
  };
  let headObject = null, headMmPerUnit = 1, patchObject = null;

  function frameObject(object, mmPerUnit, isBust) {
    // The camera on the object (on a bust, its head: the top 60 %), the back light's depth map
    // around all of it.
    const box = new THREE.Box3().setFromObject(object);
    const centre = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3());
    const radius = size.length() / 2;
    const aim = isBust ? new THREE.Vector3(centre.x, box.max.y - 0.3 * size.y, centre.z) : centre;
    const fit = isBust ? 0.5 * size.y : radius;
    controls.target.copy(aim);
    camera.near = radius / 50;
    camera.far = radius * 20;
    camera.position.copy(aim).add(new THREE.Vector3(0.45, 0.08, 1).normalize().multiplyScalar(fit / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05));
    camera.updateProjectionMatrix();
    controls.update();
    surfaceUniforms.mmPerUnit.value = mmPerUnit;
    surfaceUniforms.shadowOffset.value = 2 * radius / lightViews[0].size;
    // The depth maps: drawn once per object (the lights stay with the object).
    scene.overrideMaterial = depthMaterial;
    lightViews.forEach(({ light, target, camera: c }, i) => {
      c.left = c.bottom = -radius;
      c.right = c.top = radius;
      c.near = 0.01 * radius;
      c.far = 4 * radius;
      c.position.copy(centre).addScaledVector(light.dir, 2 * radius);
      c.lookAt(centre);
      c.updateProjectionMatrix();
      c.updateMatrixWorld();
      surfaceUniforms.lightMatrix.value[i].multiplyMatrices(c.projectionMatrix, c.matrixWorldInverse);
      surfaceUniforms.lightNear.value[i] = c.near;
      surfaceUniforms.lightFar.value[i] = c.far;
      renderer.setRenderTarget(target);
      renderer.setClearColor(0x000000, 1);
      renderer.clear();
      renderer.render(scene, c);
    });
    scene.overrideMaterial = null;
  }

  function showObject(object, mmPerUnit, name) {
    relight();
    holder.clear();
    holder.add(object);
    object.traverse((o) => { if (o.isMesh) o.material = surface; });
    view.meshName = name;
    frameObject(object, mmPerUnit, name === 'head');
  }

  // The patch: a square facing the camera, lit head-on by the key light alone, no specular: its
  // pixels are the model's colour under the illuminant (the page's test of the view).
  function patch() {
    if (!patchObject) patchObject = new THREE.Mesh(new THREE.PlaneGeometry(100, 100));
    return patchObject;
  }

  function setUniforms() {
    const patchMode = view.mode === 'patch';
    surfaceUniforms.lightColor.value[0].setScalar(KEY.intensity);
    surfaceUniforms.lightColor.value[1].setScalar(patchMode || !view.lights.fill ? 0 : FILL.intensity);
    surfaceUniforms.lightColor.value[2].setScalar(patchMode || !view.lights.back ? 0 : BACK.intensity);
    surfaceUniforms.lightDir.value[0].copy(patchMode ? new THREE.Vector3(0, 0, 1) : KEY.dir);
    surfaceUniforms.translucency.value = !patchMode && !!view.kernels;
    surfaceUniforms.shadows.value = !patchMode;
    surfaceUniforms.mapped.value = !patchMode && !!view.maps && !!surfaceUniforms.lut.value;
    surfaceUniforms.painted.value = !patchMode && view.painted && !!surfaceUniforms.lut.value;
    specularPass.uniforms.specular.value = !patchMode;
    specularPass.uniforms.roughness.value = Math.max(view.parameters.roughness, 1e-3);
    specularPass.uniforms.eta.value = view.parameters.eta;
    surfaceUniforms.cameraPos.value.copy(camera.position);
    const k = view.kernels;
    surfaceUniforms.gaussians.value = k ? k.variance.length : 0;
    if (k) k.variance.forEach((v, i) => { surfaceUniforms.variance.value[i] = v; surfaceUniforms.share.value[i].set(...k.share[i]); });
    composite.uniforms.albedo.value.set(...view.albedo);
    composite.uniforms.light.value.set(...view.light);
    composite.uniforms.rhoS.value = patchMode ? 0 : view.parameters.oiliness;
  }

  function render() {
    if (view.paused) return;  // (page.test.js, while it traces the page's own frame time)
    const t0 = performance.now();
    // At most MAX_WIDTH pixels across (software WebGL draws every pixel on the CPU).
    const scale = Math.min(window.devicePixelRatio || 1, 2, MAX_WIDTH / Math.max(1, canvas.clientWidth));
    const w = Math.max(1, Math.round(canvas.clientWidth * scale));
    const h = Math.max(1, Math.round(canvas.clientHeight * scale));
    if (canvas.width !== w || canvas.height !== h || gbuffer.width !== w || gbuffer.height !== h) {
      renderer.setSize(w, h, false);
      for (const t of [gbuffer, horizontal, sum, specularTarget]) t.setSize(w, h);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
    }
    const patchMode = view.mode === 'patch';
    if (patchMode) {
      // Head-on, filling the view, whatever the orbit.
      const d = 200;
      camera.position.set(0, 0, d);
      camera.lookAt(0, 0, 0);
      patch().position.set(0, 0, 0);
    }
    setUniforms();
    // The light of the passes before the composite (white lights, unit albedo and rho_s) is kept
    // while nothing it depends on changes: the surface pass and the blur while the camera, the
    // canvas, the mesh and mode, the kernels, paint and maps stay (lightingVersion counts the
    // changes made through the view's functions), the specular pass while they and roughness and
    // eta stay. A slider of the colour, oiliness or the illuminant then redraws the composite
    // alone, roughness and eta the specular pass and the composite (a few ms of SwiftShader at
    // 480 x 360 instead of ~150).
    camera.updateMatrixWorld();
    const lightingKey = [lightingVersion, w, h, view.mode, ...camera.matrixWorld.elements, ...camera.projectionMatrix.elements].join(',');
    const specularKey = [lightingKey, specularPass.uniforms.roughness.value, specularPass.uniforms.eta.value].join(',');
    const lit = lightingKey !== lastLightingKey;
    if (lit) {
      lastLightingKey = lightingKey;
      lightPasses(w, h);
    }
    if (lit || specularKey !== lastSpecularKey) {
      lastSpecularKey = specularKey;
      specularPass.uniforms.cameraRotation.value.setFromMatrix4(camera.matrixWorld);
      const t = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
      specularPass.uniforms.tanHalfFov.value.set(t * camera.aspect, t);
      renderer.setRenderTarget(specularTarget);
      renderer.render(specularPass.scene, ortho);
    }
    renderer.setRenderTarget(null);
    renderer.render(composite.scene, ortho);
    finishFrame(t0, lit);
  }
  // The surface pass and the subsurface blur (render()).
  function lightPasses(w, h) {
    // The surface pass.
    renderer.setRenderTarget(gbuffer);
    renderer.setClearColor(0x000000, 0);
    renderer.clear();
    renderer.render(scene, camera);
    // The subsurface: each Gaussian wider than a fraction of a pixel blurred (two passes), the rest as is.
    const mm = surfaceUniforms.mmPerUnit.value;
    const ppu = h / (2 * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)));
    const depth = camera.position.distanceTo(controls.target) || 1;
    const k = view.kernels || { variance: [1], share: [[1, 1, 1]] };
    const narrow = [0, 0, 0];
    const wide = [];
    k.variance.forEach((v, i) => {
      const sigmaPx = Math.sqrt(v) / mm * ppu / depth;
      if (!view.kernels || sigmaPx < 0.3) { for (let c = 0; c < 3; c++) narrow[c] += k.share[i][c]; } else wide.push(i);
    });
    renderer.setRenderTarget(sum);
    renderer.setClearColor(0x000000, 0);
    renderer.clear();
    share.uniforms.source.value = gbuffer.textures[0];
    share.uniforms.weight.value.set(...narrow);
    renderer.render(share.scene, ortho);
    blur.uniforms.texel.value.set(1 / w, 1 / h);
    blur.uniforms.pixelsPerUnitAtUnitDepth.value = ppu;
    blur.uniforms.mmPerUnit.value = mm;
    for (const i of wide) {
      blur.uniforms.sigmaMm.value = Math.sqrt(k.variance[i]);
      blur.uniforms.source.value = gbuffer.textures[0];
      blur.uniforms.direction.value.set(1, 0);
      blur.uniforms.weight.value.set(1, 1, 1);
      renderer.setRenderTarget(horizontal);
      renderer.render(blur.scene, ortho);
      blur.uniforms.source.value = horizontal.texture;
      blur.uniforms.direction.value.set(0, 1);
      blur.uniforms.weight.value.set(...k.share[i]);
      renderer.setRenderTarget(sum);
      renderer.render(blurAdd.scene, ortho);
    }
    view.blurred = wide.length;
  }
  function finishFrame(t0, lit) {
    view.frames += 1;
    if (lit) view.litFrames += 1;
    view.lastFrame = performance.now();
    view.frameTimes.push(view.lastFrame - t0);
    if (view.frameTimes.length > 100) view.frameTimes.shift();
  }
  // Whatever changes the light of the passes before the composite, other than the camera, the
  // canvas, roughness and eta (which the key holds), counts here.
  let lightingVersion = 0, lastLightingKey = '', lastSpecularKey = '';
  const relight = () => { lightingVersion += 1; };

  let scheduled = false;
  function requestRender() {
    if (scheduled) return;
    scheduled = true;
    requestAnimationFrame(() => { scheduled = false; render(); });
  }
  controls.addEventListener('change', requestRender);
  // The brush: a stroke on the mesh (pointer down and moved) paints k at the texture
  // coordinates under the pointer, + for blush, - for pallor.
  const raycaster = new THREE.Raycaster();
  function dab(u, v, [channel, sign]) {
    const r = DAB_RADIUS * PAINT_MAP, reach = Math.ceil(3 * r);
    const cx = u * PAINT_MAP - 0.5, cy = v * PAINT_MAP - 0.5;
    const data = paintTexture.image.data;
    for (let y = Math.max(0, Math.floor(cy - reach)); y <= Math.min(PAINT_MAP - 1, Math.ceil(cy + reach)); y++) {
      for (let x = Math.max(0, Math.floor(cx - reach)); x <= Math.min(PAINT_MAP - 1, Math.ceil(cx + reach)); x++) {
        const w = Math.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * r * r));
        if (w < 1e-3) continue;
        const i = 2 * (y * PAINT_MAP + x) + channel;
        paintK[i] = Math.max(-MAX_STOPS, Math.min(MAX_STOPS, paintK[i] + sign * DAB_STOPS * w));
        data[i] = THREE.DataUtils.toHalfFloat(paintK[i]);
      }
    }
    paintTexture.needsUpdate = true;
    relight();
  }
  function strokeAt(event) {
    const rect = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1, 1 - ((event.clientY - rect.top) / rect.height) * 2);
    raycaster.setFromCamera(ndc, camera);
    const hit = raycaster.intersectObject(holder, true).find((h) => h.uv);
    if (!hit) return false;
    if (!view.painted) {
      view.painted = true;
      if (window.skinMapColours) window.skinMapColours();
    }
    dab(hit.uv.x, hit.uv.y, BRUSHES[view.brush]);
    requestRender();
    return true;
  }
  let stroking = false;
  canvas.addEventListener('pointerdown', (e) => {
    if (view.brush === 'turn' || view.mode !== 'head') return;
    stroking = true;
    canvas.setPointerCapture(e.pointerId);
    strokeAt(e);
  });
  canvas.addEventListener('pointermove', (e) => { if (stroking) strokeAt(e); });
  const endStroke = () => { stroking = false; };
  canvas.addEventListener('pointerup', endStroke);
  canvas.addEventListener('pointercancel', endStroke);
  for (const radio of document.querySelectorAll('input[name="view3d-brush"]')) {
    radio.addEventListener('change', () => { if (radio.checked) view.setBrush(radio.value); });
  }
  const clearButton = document.getElementById('view3d-clear');
  if (clearButton) clearButton.addEventListener('click', () => view.clearPaint());
  const clearMapsButton = document.getElementById('view3d-clear-maps');
  if (clearMapsButton) clearMapsButton.addEventListener('click', () => view.clearMaps());

  // A mesh dropped on the view, or chosen with the file picker under it.
  canvas.addEventListener('dragover', (e) => { e.preventDefault(); e.stopPropagation(); });
  canvas.addEventListener('drop', (e) => {
    e.preventDefault();
    e.stopPropagation();
    document.body.classList.remove('dragging');
    const file = e.dataTransfer && e.dataTransfer.files[0];
    if (file) view.loadFile(file);
  });
  const picker = document.getElementById('view3d-file');
  if (picker) {
    picker.addEventListener('change', async () => {
      const file = picker.files[0];
      if (file) await view.loadFile(file);
      picker.value = '';  // the same file chosen again loads again
    });
  }
  new ResizeObserver(requestRender).observe(canvas);

  Object.assign(view, {
    // The page's update (app.js, inside its animation frame): drawn at once, in the same frame.
    update(albedo, parameters) {
      view.albedo = albedo;
      Object.assign(view.parameters, parameters);
      render();
    },
    setLight(rgb) { view.light = rgb; requestRender(); },
    // The lights on: the key always, the fill and the back light as given (booleans); their
    // boxes under the view follow.
    setLights({ fill = view.lights.fill, back = view.lights.back } = {}) {
      if (typeof fill !== 'boolean' || typeof back !== 'boolean') throw new Error('lights: fill and back must be true or false');
      if (fill === view.lights.fill && back === view.lights.back) return;
      relight();
      view.lights = { fill, back };
      for (const [id, on] of [['view3d-fill', fill], ['view3d-back', back]]) {
        const box = document.getElementById(id);
        if (box) box.checked = on;
      }
      requestRender();
    },
    // The realtime export's document (its "gaussians": variance in mm^2 and weight per channel):
    // each Gaussian's share of the channel's total.
    setKernels(doc) {
      relight();
      if (!doc) { view.kernels = null; requestRender(); return; }
      const total = [0, 1, 2].map((c) => doc.gaussians.reduce((s, g) => s + g.weight[c], 0));
      view.kernels = {
        variance: doc.gaussians.map((g) => g.variance),
        share: doc.gaussians.map((g) => g.weight.map((w, c) => (total[c] > 0 ? w / total[c] : 0))),
      };
      requestRender();
    },
    setMode(mode) {
      relight();
      view.mode = mode;
      if (mode === 'patch') showObject(patch(), 1, 'patch');
      else if (headObject) showObject(headObject, headMmPerUnit, view.meshName0);
      controls.enabled = mode !== 'patch' && view.brush === 'turn';
      render();
    },
    // A frame drawn and read back at once (RGBA bytes, bottom row first), for tests.
    pixels() {
      render();
      const out = new Uint8Array(canvas.width * canvas.height * 4);
      gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, out);
      return { width: canvas.width, height: canvas.height, data: Array.from(out) };
    },
    requestRender,
    // The brush: 'turn' (the orbit), 'blush' (more blood), 'pallor' (less), 'tan' (more
    // melanin) or 'lighten' (less).
    setBrush(brush) {
      if (!(brush in BRUSHES)) throw new Error(`brush '${brush}': allowed are ${Object.keys(BRUSHES).join(', ')}`);
      view.brush = brush;
      controls.enabled = brush === 'turn' && view.mode !== 'patch';
      const radio = document.querySelector(`input[name="view3d-brush"][value="${brush}"]`);
      if (radio) radio.checked = true;
    },
    clearPaint() {
      relight();
      paintK.fill(0);
      paintTexture.image.data.fill(0);
      paintTexture.needsUpdate = true;
      view.painted = false;
      requestRender();
    },
    // A mesh of one's own (a File: .glb, .gltf with its buffers embedded, or .obj) in place of the
    // head, in this skin. A file that is not one gives one line in #view3d-file-status and
    // leaves the view as it was. Resolves to true when the mesh is shown.
    async loadFile(file) {
      if (/\.exr$/i.test(file.name)) return view.loadMaps(file);
      try {
        const object = await parseMesh(file);
        const size = new THREE.Box3().setFromObject(object).getSize(new THREE.Vector3());
        const largest = Math.max(size.x, size.y, size.z);
        headObject = object;
        headMmPerUnit = FILE_SIZE_MM / largest;
        view.clearPaint();
        view.meshName0 = 'file';
        if (view.mode === 'head') showObject(object, headMmPerUnit, 'file');
        document.getElementById('view3d-credit').hidden = true;
        let triangles = 0;
        object.traverse((o) => { if (o.isMesh) triangles += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3; });
        sayFile(`Showing ${file.name}: ${triangles} triangles, taken as ${FILE_SIZE_MM} mm across.`, false);
        render();
        return true;
      } catch (e) {
        sayFile(`Not loaded: ${file.name}: ${e.message}. The view takes a .glb, a .gltf with its data embedded, or an .obj.`, true);
        return false;
      }
    },
    // Parameter maps of `skin fit --texture` (a File, .exr; docs/parameter-maps.md) over the
    // mesh's texture coordinates (row 0 of the maps, the texture's top row, at v = 1, as
    // `skin render` and three.js's image textures read a texture; the Lee Perry-Smith head's
    // coordinates follow it, and with row 0 at v = 0 its lips land on its chin): melanin,
    // melanin_blend and hemoglobin per texel, the other parameters the sliders'. Shaded once the
    // page has given the model's colours over the maps' ranges (window.skinMapColours, app.js,
    // which calls setMapColours). A file that is not such maps gives one line in
    // #view3d-file-status and leaves the view as it was. Resolves to true when loaded.
    async loadMaps(file) {
      let maps;
      try {
        if (file.size > MAX_MAP_BYTES) throw new Error(`${file.name}: ${(file.size / 1048576).toFixed(0)} MB: at most ${MAX_MAP_BYTES / 1048576} MB is allowed`);
        maps = readParameterMaps(await file.arrayBuffer(), file.name);
      } catch (e) {
        sayFile(`Not loaded: ${e.message}.`, true);
        return false;
      }
      const { width, height } = maps;
      const texels = new Uint16Array(4 * width * height);
      const range = { melanin: [Infinity, -Infinity], melanin_blend: [Infinity, -Infinity], hemoglobin: [Infinity, -Infinity] };
      const keys = Object.keys(range);
      const one = THREE.DataUtils.toHalfFloat(1);
      keys.forEach((key, c) => {
        const plane = maps[key], r = range[key];
        for (let y = 0; y < height; y++) {
          const from = (height - 1 - y) * width;  // (v = 1 - y: the maps' row 0 at the top)
          for (let x = 0; x < width; x++) {
            const v = plane[from + x], i = y * width + x;
            texels[4 * i + c] = THREE.DataUtils.toHalfFloat(v);
            texels[4 * i + 3] = one;
            if (v < r[0]) r[0] = v;
            if (v > r[1]) r[1] = v;
          }
        }
      });
      if (mapTexture) mapTexture.dispose();
      mapTexture = new THREE.DataTexture(texels, width, height, THREE.RGBAFormat, THREE.HalfFloatType);
      mapTexture.minFilter = mapTexture.magFilter = THREE.LinearFilter;
      mapTexture.wrapS = mapTexture.wrapT = THREE.ClampToEdgeWrapping;
      mapTexture.needsUpdate = true;
      surfaceUniforms.paramMap.value = mapTexture;
      surfaceUniforms.lut.value = null;  // until setMapColours
      relight();
      view.maps = { name: file.name, width, height, range };
      const span = (key, digits = 3) => range[key].map((v) => v.toPrecision(digits)).join('–');
      sayFile(`Parameter maps ${file.name}: ${width} x ${height} texels, melanin ${span('melanin')}, melanin blend ${span('melanin_blend', 2)}, ` +
        `hemoglobin ${span('hemoglobin')}; these three come from the maps, the other parameters from the sliders.`, false);
      if (window.skinMapColours) window.skinMapColours();
      render();
      return true;
    },
    // The grid the page computes the model's colour on for the maps or the paint (app.js, the
    // module's color_grid): logarithmic in melanin and hemoglobin, linear in the blend. With
    // maps, over their ranges, melanin's and hemoglobin's widened by the brushes' 2^-2-2^2; with
    // paint alone, around the sliders' values `centre` ({melanin, melanin_blend, hemoglobin}):
    // 2^-2-2^2 of each in half stops. The fractions at most `most` (1 less the epidermal blood:
    // the epidermis' volume fractions add to at most 1 for melanin). Null with neither.
    mapAxes(centre, most = 1) {
      const axis = (lo, hi, n, log) => {
        if (!(hi > lo)) return [lo];
        return Array.from({ length: n }, (_, i) => (log ? lo * (hi / lo) ** (i / (n - 1)) : lo + (hi - lo) * i / (n - 1)));
      };
      const around = (lo, hi, cap, n) => axis(Math.max(lo / 4, MAP_FLOOR), Math.min(cap, Math.max(4 * hi, MAP_FLOOR)), n, true);
      if (view.maps) {
        const r = view.maps.range;
        return {
          melanin: around(r.melanin[0], r.melanin[1], most, MAP_NODES[0]),
          melanin_blend: axis(r.melanin_blend[0], r.melanin_blend[1], MAP_NODES[1], false),
          hemoglobin: around(r.hemoglobin[0], r.hemoglobin[1], 1, MAP_NODES[2]),
        };
      }
      if (!view.painted || !centre) return null;
      return {
        melanin: centre.melanin > 0 ? around(centre.melanin, centre.melanin, most, 9) : [MAP_FLOOR],
        melanin_blend: [centre.melanin_blend],
        hemoglobin: centre.hemoglobin > 0 ? around(centre.hemoglobin, centre.hemoglobin, 1, 9) : [MAP_FLOOR],
      };
    },
    // The model's colour (linear sRGB) at every node of mapAxes(centre) (melanin fastest, then
    // the blend, then hemoglobin): the maps and the paint are shaded from then on.
    setMapColours(axes, colours, centre) {
      const [nm, nb, nh] = [axes.melanin.length, axes.melanin_blend.length, axes.hemoglobin.length];
      if (colours.length !== 3 * nm * nb * nh) throw new Error('setMapColours: one colour per node');
      // ln of the colour, 32-bit, read texel by texel (no filtering: the shader interpolates).
      const data = new Float32Array(4 * nm * nb * nh);
      for (let i = 0; i < nm * nb * nh; i++) {
        for (let c = 0; c < 3; c++) data[4 * i + c] = Math.log(Math.max(colours[3 * i + c], 1e-9));
        data[4 * i + 3] = 0;
      }
      if (lutTexture) lutTexture.dispose();
      lutTexture = new THREE.Data3DTexture(data, nm, nb, nh);
      lutTexture.format = THREE.RGBAFormat;
      lutTexture.type = THREE.FloatType;
      lutTexture.minFilter = lutTexture.magFilter = THREE.NearestFilter;
      lutTexture.wrapS = lutTexture.wrapT = lutTexture.wrapR = THREE.ClampToEdgeWrapping;
      lutTexture.unpackAlignment = 1;
      lutTexture.needsUpdate = true;
      const lo = [Math.log(axes.melanin[0]), axes.melanin_blend[0], Math.log(axes.hemoglobin[0])];
      const hi = [Math.log(axes.melanin[nm - 1]), axes.melanin_blend[nb - 1], Math.log(axes.hemoglobin[nh - 1])];
      surfaceUniforms.lut.value = lutTexture;
      surfaceUniforms.lutLo.value.set(...lo);
      surfaceUniforms.lutSpan.value.set(...lo.map((l, i) => (hi[i] > l ? hi[i] - l : 1)));
      surfaceUniforms.lutSize.value = [nm, nb, nh];
      surfaceUniforms.lutCentre.value.set(centre.melanin, centre.melanin_blend, centre.hemoglobin);
      relight();
      requestRender();
    },
    clearMaps() {
      relight();
      view.maps = null;
      surfaceUniforms.lut.value = null;
      surfaceUniforms.paramMap.value = null;
      if (view.painted && window.skinMapColours) window.skinMapColours();  // the paint's own grid
      sayFile('', false);
      requestRender();
    },
    // The camera (mesh units; fov vertical, degrees), as the orbit leaves it or set (tests).
    getCamera() {
      const v = (x) => [x.x, x.y, x.z];
      return { eye: v(camera.position), target: v(controls.target), fov: camera.fov };
    },
    setCamera({ eye, target, fov }) {
      camera.position.set(...eye);
      controls.target.set(...target);
      camera.fov = fov;
      camera.updateProjectionMatrix();
      controls.update();
      render();
    },
    // The view as a scene for `skin render` (docs/scene-format.md): the same camera (eye, target,
    // vertical field of view, the canvas's size), the mesh at the view's scale (unit_mm), and the
    // three lights as directional lights. A light of the view is the irradiance pi x its value:
    // the view's diffuse radiance is albedo x (value x cos), a Lambertian R_d / pi x irradiance x
    // cos. `material` is the scene's skin material; `mesh` the path to the mesh file.
    renderScene(mesh, material) {
      render();
      const v = (x) => [x.x, x.y, x.z];
      const on = [KEY, ...(view.lights.fill ? [FILL] : []), ...(view.lights.back ? [BACK] : [])];
      const lights = on.map((l) => ({
        type: 'directional', direction: v(l.dir.clone().negate()),
        irradiance: view.light.map((c) => Math.PI * c * l.intensity),
      }));
      return {
        description: 'the 3D view of the page (web/page/view3d.js), for skin render',
        unit_mm: surfaceUniforms.mmPerUnit.value,
        camera: { eye: v(camera.position), look_at: v(controls.target), up: v(camera.up), fov: camera.fov, resolution: [canvas.width, canvas.height] },
        render: { max_depth: 4, tone_map: 'clip', exposure: 0 },
        materials: { skin: material },
        objects: [{ mesh, material: 'skin' }],
        lights,
      };
    },
  });

  // The head, or the sphere without it.
  headObject = new THREE.Mesh(new THREE.SphereGeometry(1, 96, 64));
  headMmPerUnit = SPHERE_RADIUS_MM;
  view.meshName0 = 'sphere';
  showObject(headObject, headMmPerUnit, 'sphere');
  new GLTFLoader().load(HEAD_URL, (gltf) => {
    const head = gltf.scene;
    const size = new THREE.Box3().setFromObject(head).getSize(new THREE.Vector3());
    headObject = head;
    headMmPerUnit = BUST_WIDTH_MM / size.x;
    view.meshName0 = 'head';
    if (view.mode === 'head') showObject(head, headMmPerUnit, 'head');
    caption.dataset.mesh = 'head';
    document.getElementById('view3d-credit').hidden = false;
    view.ready = true;
    requestRender();
  }, undefined, () => {
    caption.dataset.mesh = 'sphere';
    view.ready = true;
    requestRender();
  });
  // The grid for the maps or the paint is in (setMapColours; cleared with new maps).
  Object.defineProperty(view, 'paintReady', { get: () => !!surfaceUniforms.lut.value });
  return view;
}

const view = createView();
window.skinView3d = view;
if (view && window.skinView3dPending) window.skinView3dPending(view);
