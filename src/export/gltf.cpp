// glTF 2.0 (gltf): one material for the Khronos material extensions, on a small sphere that
// previews it (docs/export.md, "glTF"). The subsurface is OpenPBR's random-walk fit
// (materialx.cpp) in the extensions' terms:
// - KHR_materials_volume: attenuationDistance and attenuationColor give the extinction
//   coefficient sigma_t = -ln(attenuationColor) / attenuationDistance per channel; with
//   KHR_materials_volume_scatter it counts absorption and scattering. The distance is the
//   largest mean free path 1 / sigma_t, each channel's colour exp(-distance sigma_t).
// - KHR_materials_volume_scatter (a draft: Khronos glTF pull request #2453): the multi-scatter
//   albedo, from which the draft derives the single-scattering albedo by the same formula as
//   OpenPBR's renderers (Chiang et al. 2016 eq. 3, which the draft credits to Kulla & Conty
//   2017), and the anisotropy of the walk that formula assumes: 0.
// - KHR_materials_diffuse_transmission: all light that is not reflected specularly enters the
//   volume (the draft's configuration for dense media such as skin).
// glTF's lengths are metres: the file is written in m (times --world-scale) and refuses another
// unit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fits.hpp"
#include "report.hpp"
#include "skin/util/error.hpp"

namespace skin::exporting::detail {

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::parameter_table;
using skin::util::InputError;
using skin::util::Rgb;

namespace {

// The draft of KHR_materials_volume_scatter this file follows (stated in the file and the docs).
constexpr const char* kScatterDraft =
    "KHR_materials_volume_scatter, draft of Khronos glTF pull request #2453 (README revision "
    "4608553, Copyright 2018-2025: multiscatterColor; renamed multiscatterColorFactor in the "
    "pull request's 2026 revision): both names are written";

// The preview: an icosphere of radius kPreviewRadius metres, its icosahedron subdivided twice
// (162 vertices, 320 triangles).
constexpr double kPreviewRadius = 0.05;
constexpr int kSubdivisions = 2;

struct Mesh {
  std::vector<std::array<double, 3>> unit;  // points on the unit sphere
  std::vector<std::array<std::uint16_t, 3>> triangles;  // counter-clockwise seen from outside
};

std::array<double, 3> normalised(const std::array<double, 3>& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

Mesh icosphere() {
  Mesh m;
  // The icosahedron's 12 vertices: the cyclic permutations of (0, +-1, +-phi); its faces are the
  // triples of mutually adjacent vertices (edge length 2), each turned to face outwards.
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> v;
  for (int axis = 0; axis < 3; ++axis)
    for (double a : {-1.0, 1.0})
      for (double b : {-phi, phi}) {
        std::array<double, 3> p{};
        p[(axis + 1) % 3] = a;
        p[(axis + 2) % 3] = b;
        v.push_back(p);
      }
  auto dist2 = [&](std::size_t i, std::size_t j) {
    double s = 0;
    for (int k = 0; k < 3; ++k) s += (v[i][k] - v[j][k]) * (v[i][k] - v[j][k]);
    return s;
  };
  auto adjacent = [&](std::size_t i, std::size_t j) { return std::abs(dist2(i, j) - 4.0) < 1e-9; };
  for (const auto& p : v) m.unit.push_back(normalised(p));
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j)
      for (std::size_t k = j + 1; k < v.size(); ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        std::array<double, 3> e1{}, e2{}, c{};
        for (int d = 0; d < 3; ++d) {
          e1[d] = v[j][d] - v[i][d];
          e2[d] = v[k][d] - v[i][d];
          c[d] = v[i][d] + v[j][d] + v[k][d];
        }
        const double outward = (e1[1] * e2[2] - e1[2] * e2[1]) * c[0] +
                                (e1[2] * e2[0] - e1[0] * e2[2]) * c[1] +
                                (e1[0] * e2[1] - e1[1] * e2[0]) * c[2];
        const auto a = static_cast<std::uint16_t>(i);
        const auto b = static_cast<std::uint16_t>(j);
        const auto d = static_cast<std::uint16_t>(k);
        m.triangles.push_back(outward > 0 ? std::array<std::uint16_t, 3>{a, b, d}
                                          : std::array<std::uint16_t, 3>{a, d, b});
      }
  // Each subdivision splits a triangle into four at its edges' midpoints (shared between the
  // two triangles of an edge), pushed out to the sphere.
  for (int s = 0; s < kSubdivisions; ++s) {
    std::map<std::pair<int, int>, std::uint16_t> midpoints;
    auto midpoint = [&](std::uint16_t a, std::uint16_t b) {
      const std::pair<int, int> key = std::minmax<int>(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      std::array<double, 3> p{};
      for (int d = 0; d < 3; ++d) p[d] = m.unit[a][d] + m.unit[b][d];
      m.unit.push_back(normalised(p));
      const auto index = static_cast<std::uint16_t>(m.unit.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<std::uint16_t, 3>> finer;
    for (const auto& t : m.triangles) {
      const std::uint16_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                          ca = midpoint(t[2], t[0]);
      finer.push_back({t[0], ab, ca});
      finer.push_back({ab, t[1], bc});
      finer.push_back({ca, bc, t[2]});
      finer.push_back({ab, bc, ca});
    }
    m.triangles = std::move(finer);
  }
  return m;
}

// Little-endian bytes of the buffer (glTF's byte order).
void put_float(std::vector<unsigned char>& out, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(u >> (8 * i)));
}
void put_u16(std::vector<unsigned char>& out, std::uint16_t v) {
  out.push_back(static_cast<unsigned char>(v & 0xff));
  out.push_back(static_cast<unsigned char>(v >> 8));
}

// RFC 4648 base64 with padding.
std::string base64(const std::vector<unsigned char>& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  s.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t w = 0;
    for (std::size_t k = 0; k < 3; ++k) w = (w << 8) | (k < n ? bytes[i + k] : 0u);
    for (std::size_t k = 0; k < 4; ++k)
      s += k <= n ? kAlphabet[(w >> (18 - 6 * k)) & 0x3f] : '=';
  }
  return s;
}

// The preview sphere's buffer (positions, normals, indices) and the accessors, buffer views and
// buffer describing it. Coordinates carry 6 significant digits (rounded), so that the CLI and
// the web page write the same bytes; the accessors' bounds are those of the floats written.
void add_preview(json& j, double radius) {
  const Mesh m = icosphere();
  std::vector<unsigned char> bytes;
  std::array<double, 3> lo{}, hi{};
  lo.fill(HUGE_VAL);
  hi.fill(-HUGE_VAL);
  for (const auto& u : m.unit)
    for (int d = 0; d < 3; ++d) {
      const float x = static_cast<float>(rounded(radius * u[d]));
      put_float(bytes, x);
      lo[d] = std::min(lo[d], static_cast<double>(x));
      hi[d] = std::max(hi[d], static_cast<double>(x));
    }
  const std::size_t positions = bytes.size();
  for (const auto& u : m.unit)
    for (int d = 0; d < 3; ++d) put_float(bytes, static_cast<float>(rounded(u[d])));
  const std::size_t normals = bytes.size() - positions;
  for (const auto& t : m.triangles)
    for (std::uint16_t i : t) put_u16(bytes, i);
  const std::size_t indices = bytes.size() - positions - normals;
  const std::size_t vertices = m.unit.size();
  j["accessors"] = json::array(
      {{{"bufferView", 0}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"},
        {"min", json::array({lo[0], lo[1], lo[2]})}, {"max", json::array({hi[0], hi[1], hi[2]})}},
       {{"bufferView", 1}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}},
       {{"bufferView", 2}, {"componentType", 5123}, {"count", 3 * m.triangles.size()},
        {"type", "SCALAR"}}});
  j["bufferViews"] = json::array(
      {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions}, {"target", 34962}},
       {{"buffer", 0}, {"byteOffset", positions}, {"byteLength", normals}, {"target", 34962}},
       {{"buffer", 0}, {"byteOffset", positions + normals}, {"byteLength", indices},
        {"target", 34963}}});
  j["buffers"] = json::array(
      {{{"byteLength", bytes.size()},
        {"uri", "data:application/octet-stream;base64," + base64(bytes)}}});
}

json rgb_json(const Rgb& c, double (*round)(double)) {
  return {{"r", round(c.r)}, {"g", round(c.g)}, {"b", round(c.b)}};
}
json rgb_json(const std::array<double, 3>& c, double (*round)(double)) {
  return rgb_json(Rgb{c[0], c[1], c[2]}, round);
}

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  if (ctx.unit != Unit::m)
    throw InputError("units = '" + std::string(unit_name(ctx.unit)) +
                     "' is not allowed for gltf: glTF's lengths are metres (give m, or "
                     "--world-scale for a scene in other units)");
  const SkinParameters& p = ref.parameters;
  const WalkFit w = fit_walk(ref, [](double A) { return chiang_alpha(A); }, 1.0);
  const double scale = ctx.scale();
  const double d_max_mm = std::max({w.d_mm.r, w.d_mm.g, w.d_mm.b});
  // sigma_t = -ln(colour) / distance = 1 / d per channel, with distance = d_max.
  Rgb attenuation;
  for (int c = 0; c < 3; ++c) attenuation[c] = std::exp(-d_max_mm / w.d_mm[c]);
  const double distance = d_max_mm * scale;
  const double radius = kPreviewRadius * 1000.0 * scale;  // the preview sphere, in the file
  const double thickness = 2.0 * radius;

  Export e;
  e.report = fit_report(ctx,
                        "glTF KHR_materials_volume + KHR_materials_volume_scatter (draft) "
                        "random-walk subsurface as OpenPBR's: extinction sigma_t = "
                        "-ln(attenuationColor) / attenuationDistance = 1 / mean free path, "
                        "multiscatterColor = multiple-scattering albedo inverted by Chiang et al. "
                        "2016 eq. 3 (the draft's formula), isotropic walk, index-matched boundary",
                        w.R_d, w.R);
  if (w.clamped) {
    e.report.representable = false;
    e.report.notes.push_back("a channel's R_d is beyond the albedo range the target reaches");
  }
  e.report.values = {{"baseColorFactor", vec(ref.R_d)},
                     {"metallicFactor", {0.0}},
                     {"roughnessFactor", {perceptual_roughness(p)}},
                     {"ior", {p.eta}},
                     {"specularFactor", {p.oiliness}},
                     {"thicknessFactor", {thickness}},
                     {"attenuationDistance", {distance}},
                     {"attenuationColor", vec(attenuation)},
                     {"diffuseTransmissionFactor", {1.0}},
                     {"multiscatterColorFactor", vec(w.A)},
                     {"scatterAnisotropy", {0.0}}};

  const std::string name = json_text(o.name, kName);
  json material;
  material["name"] = name;
  material["pbrMetallicRoughness"] = {
      {"baseColorFactor", {ref.R_d.r, ref.R_d.g, ref.R_d.b, 1.0}},
      {"metallicFactor", 0.0},
      {"roughnessFactor", perceptual_roughness(p)}};
  material["extensions"] = {
      {"KHR_materials_diffuse_transmission",
       {{"diffuseTransmissionFactor", 1.0}, {"diffuseTransmissionColorFactor", {1.0, 1.0, 1.0}}}},
      {"KHR_materials_ior", {{"ior", p.eta}}},
      {"KHR_materials_specular",
       {{"specularFactor", p.oiliness}, {"specularColorFactor", {1.0, 1.0, 1.0}}}},
      {"KHR_materials_volume",
       {{"thicknessFactor", thickness},
        {"attenuationDistance", distance},
        {"attenuationColor", vec(attenuation)}}},
      {"KHR_materials_volume_scatter",
       {{"multiscatterColorFactor", vec(w.A)},
        {"multiscatterColor", vec(w.A)},
        {"scatterAnisotropy", 0.0}}}};
  material = rounded(std::move(material));

  // Our parameters (as given) and the fit report (FILE.fit.json's keys and numbers).
  const FitReport& r = e.report;
  json fit;
  fit["target_model"] = r.target_model;
  fit["representable"] = r.representable;
  fit["notes"] = r.notes;
  fit["R_d_ours"] = rgb_json(r.R_d_ours, report_number);
  fit["R_d_target"] = rgb_json(r.R_d_target, report_number);
  fit["delta_e_2000"] = report_error(r.delta_e_2000);
  fit["profile_l1"] = rgb_json(r.profile_l1, report_error);
  fit["mean_radius_mm"] = rgb_json(r.mean_radius_mm, report_number);
  fit["mean_radius_error"] = rgb_json(r.mean_radius_error, report_error);
  json parameters = json::object();
  for (const ParameterInfo& info : parameter_table())
    parameters[std::string(info.key)] = p.*(info.member);
  std::string lengths = "m";
  if (o.world_scale != 1.0) lengths += " x world scale " + num(o.world_scale);
  material["extras"] = {
      {"spectral_skin",
       {{"format", "Spectral Skin export: glTF 2.0 material (docs/export.md)"},
        {"parameters", parameters},
        {"solver", std::string(ref.model->name())},
        {"units", {{"lengths", lengths}, {"mean_radius_mm", "mm"},
                   {"colors", "linear Rec.709 (sRGB primaries, D65)"}}},
        {"extinction_mean_free_path_mm", rgb_json(w.d_mm, rounded)},
        {"scatter_anisotropy_note",
         "scatterAnisotropy is 0: the fit is of an isotropic walk (the draft derives the "
         "single-scattering albedo by a formula for g = 0); the model's own g is in parameters"},
        {"volume_scatter_draft", kScatterDraft},
        {"fit", fit}}}};

  json j;
  j["asset"] = {{"version", "2.0"},
                {"generator", "Spectral Skin (skin export --target gltf)"}};
  j["extensionsUsed"] = {"KHR_materials_diffuse_transmission", "KHR_materials_ior",
                         "KHR_materials_specular", "KHR_materials_volume",
                         "KHR_materials_volume_scatter"};
  j["scene"] = 0;
  j["scenes"] = json::array({{{"name", name}, {"nodes", {0}}}});
  j["nodes"] = json::array({{{"name", name + "_preview"}, {"mesh", 0}}});
  j["meshes"] = json::array(
      {{{"name", name + "_preview"},
        {"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}},
                                     {"indices", 2},
                                     {"material", 0},
                                     {"mode", 4}}})}}});
  j["materials"] = json::array({material});
  add_preview(j, radius);
  e.files.push_back({"", j.dump(2) + "\n", false});
  return e;
}

}  // namespace

TargetSpec gltf_target() {
  return {"gltf",
          "glTF 2.0 material (KHR_materials_volume, _diffuse_transmission, the draft "
          "_volume_scatter) on a preview sphere",
          ".gltf", Unit::m, write};
}

}  // namespace skin::exporting::detail
