// The glTF target (src/export/gltf.cpp): a glTF 2.0 document whose material carries OpenPBR's
// random-walk fit in the Khronos extensions' terms (lengths in metres), our parameters and the
// fit report in its extras, and a preview sphere whose buffer holds what its accessors say.
// Khronos' glTF-Validator and three.js read the file in web/test/gltf.test.js.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "skin/export/export.hpp"
#include "skin/util/error.hpp"

using namespace skin;
using namespace skin::exporting;
using json = nlohmann::json;
using skin::physics::Preset;
using skin::physics::ParameterInfo;
using skin::physics::parameter_table;
using skin::physics::SkinParameters;
using skin::physics::find_preset;
using skin::physics::presets;
using skin::util::InputError;

namespace {

json gltf_of(const SkinParameters& p, const Options& o = {}) {
  const Export e = export_skin("gltf", p, transport::find_model("multipole"), o);
  EXPECT_EQ(e.files.size(), 1u);
  return json::parse(e.files.at(0).content);
}

// The three numbers of OpenPBR's `<input name="NAME" ... value="a, b, c" />`.
std::vector<double> mtlx_values(const std::string& mtlx, const std::string& name) {
  const std::string key = "<input name=\"" + name + "\"";
  const std::size_t at = mtlx.find(key);
  EXPECT_NE(at, std::string::npos) << name;
  const std::size_t v = mtlx.find("value=\"", at) + 7;
  std::string text = mtlx.substr(v, mtlx.find('"', v) - v);
  for (char& c : text)
    if (c == ',') c = ' ';
  std::istringstream in(text);
  std::vector<double> out;
  for (double x; in >> x;) out.push_back(x);
  return out;
}

// Every value of the document: numbers finite, no null (nlohmann writes a NaN or an infinity as
// null).
void expect_finite(const json& j, const std::string& where = "") {
  if (j.is_null()) ADD_FAILURE() << "null at " << where;
  if (j.is_number()) {
    EXPECT_TRUE(std::isfinite(j.get<double>())) << where;
  }
  if (j.is_object())
    for (const auto& [k, v] : j.items()) expect_finite(v, where + "/" + k);
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) expect_finite(j[i], where + "/" + std::to_string(i));
}

std::vector<unsigned char> base64_decode(const std::string& s) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  std::uint32_t bits = 0;
  int n = 0;
  for (char c : s) {
    if (c == '=') break;
    const int v = value(c);
    if (v < 0) {
      ADD_FAILURE() << "not base64: " << c;
      return out;
    }
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    if ((n += 6) >= 8) {
      n -= 8;
      out.push_back(static_cast<unsigned char>((bits >> n) & 0xff));
    }
  }
  return out;
}

float float_at(const std::vector<unsigned char>& b, std::size_t offset) {
  std::uint32_t u = 0;
  for (int i = 0; i < 4; ++i) u |= static_cast<std::uint32_t>(b.at(offset + i)) << (8 * i);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

}  // namespace

TEST(Gltf, IsGltf2WithTheMaterialExtensions) {
  const json j = gltf_of(find_preset("caucasian").parameters);
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_NE(j["asset"]["generator"].get<std::string>().find("Spectral Skin"), std::string::npos);
  const std::vector<std::string> used = j["extensionsUsed"];
  EXPECT_EQ(used, (std::vector<std::string>{"KHR_materials_diffuse_transmission", "KHR_materials_ior",
                                            "KHR_materials_specular", "KHR_materials_volume",
                                            "KHR_materials_volume_scatter"}));
  EXPECT_FALSE(j.contains("extensionsRequired"));  // a core renderer shows the base colour
  ASSERT_EQ(j["materials"].size(), 1u);
  const json& m = j["materials"][0];
  EXPECT_EQ(m["name"], "spectral_skin");
  for (const std::string& ext : used) EXPECT_TRUE(m["extensions"].contains(ext)) << ext;
  EXPECT_EQ(m["extensions"].size(), used.size());
  // The one mesh uses the material; the scene shows it.
  EXPECT_EQ(j["scene"], 0);
  EXPECT_EQ(j["meshes"][0]["primitives"][0]["material"], 0);
  expect_finite(j);
}

TEST(Gltf, ValuesAreOpenPbrsFitInMetres) {
  // Every preset, both solvers' worth of shapes: the material holds OpenPBR's fitted values
  // (multi-scatter albedo to 1e-12, the mean free path per channel converted mm -> m), the
  // surface as the other targets map it, and the fit report of the export.
  const transport::Model& model = transport::find_model("multipole");
  for (const Preset& preset : presets()) {
    SCOPED_TRACE(preset.name);
    const SkinParameters& p = preset.parameters;
    const auto ours = prepare(p, model);
    const Export g = export_prepared("gltf", *ours, Options{});
    const Export o = export_prepared("openpbr", *ours, Options{});  // its usual unit: m
    const json j = json::parse(g.files[0].content);
    const std::string mtlx = o.files[0].content;
    const json& ext = j["materials"][0]["extensions"];
    const json& scatter = ext["KHR_materials_volume_scatter"];
    const std::vector<double> A = mtlx_values(mtlx, "subsurface_color");
    ASSERT_EQ(A.size(), 3u);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(scatter["multiscatterColorFactor"][c].get<double>(), A[c], 1e-12) << c;
      EXPECT_NEAR(scatter["multiscatterColor"][c].get<double>(), A[c], 1e-12) << c;
    }
    EXPECT_EQ(scatter["scatterAnisotropy"], 0.0);  // the walk the fit and the draft's formula assume
    // Extinction: sigma_t = -ln(attenuationColor) / attenuationDistance = 1 / d, d OpenPBR's
    // subsurface_radius x subsurface_radius_scale (m).
    const json& volume = ext["KHR_materials_volume"];
    const double radius = mtlx_values(mtlx, "subsurface_radius").at(0);
    const std::vector<double> scale = mtlx_values(mtlx, "subsurface_radius_scale");
    EXPECT_EQ(volume["attenuationDistance"].get<double>(), radius);
    const json& extras = j["materials"][0]["extras"]["spectral_skin"];
    double d_max_mm = 0;
    for (int c = 0; c < 3; ++c) {
      const double colour = volume["attenuationColor"][c];
      EXPECT_GT(colour, 0.0);
      EXPECT_LE(colour, 1.0);
      const double d_m = -volume["attenuationDistance"].get<double>() / std::log(colour);
      EXPECT_NEAR(d_m / (radius * scale[c]), 1.0, 1e-5) << c;
      const double d_mm = extras["extinction_mean_free_path_mm"][std::string(1, "rgb"[c])];
      EXPECT_NEAR(d_m / (d_mm * 1e-3), 1.0, 1e-5) << c;
      d_max_mm = std::max(d_max_mm, d_mm);
    }
    EXPECT_NEAR(volume["attenuationDistance"].get<double>(), d_max_mm * 1e-3, 1e-12);
    EXPECT_GT(volume["thicknessFactor"].get<double>(), 0.0);  // a volume, not thin-walled
    EXPECT_EQ(ext["KHR_materials_diffuse_transmission"]["diffuseTransmissionFactor"], 1.0);
    // The surface: IOR eta, specular weight = oiliness, GGX roughness sqrt(Beckmann m), as
    // OpenPBR's.
    EXPECT_EQ(ext["KHR_materials_ior"]["ior"].get<double>(), mtlx_values(mtlx, "specular_ior").at(0));
    EXPECT_EQ(ext["KHR_materials_specular"]["specularFactor"].get<double>(),
              mtlx_values(mtlx, "specular_weight").at(0));
    const json& pbr = j["materials"][0]["pbrMetallicRoughness"];
    EXPECT_EQ(pbr["roughnessFactor"].get<double>(), mtlx_values(mtlx, "specular_roughness").at(0));
    EXPECT_EQ(pbr["metallicFactor"], 0.0);
    // The base colour: our R_d (the colour under uniform white light), as the report states it.
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(pbr["baseColorFactor"][c].get<double>(), report_number(g.report.R_d_ours[c])) << c;
    EXPECT_EQ(pbr["baseColorFactor"][3], 1.0);
    // The fit is OpenPBR's: the same colour and errors.
    EXPECT_EQ(g.report.R_d_target, o.report.R_d_target);
    EXPECT_EQ(g.report.profile_l1, o.report.profile_l1);
    EXPECT_EQ(g.report.representable, o.report.representable);
    // Extras: the parameters as given, the solver and the report's numbers.
    for (const ParameterInfo& info : parameter_table())
      EXPECT_EQ(extras["parameters"][std::string(info.key)].get<double>(), p.*(info.member)) << info.key;
    EXPECT_EQ(extras["solver"], "multipole");
    EXPECT_EQ(extras["fit"]["delta_e_2000"].get<double>(), report_error(g.report.delta_e_2000));
    EXPECT_EQ(extras["fit"]["profile_l1"]["b"].get<double>(), report_error(g.report.profile_l1[2]));
    EXPECT_EQ(extras["fit"]["target_model"], g.report.target_model);
    EXPECT_NE(extras["volume_scatter_draft"].get<std::string>().find("#2453"), std::string::npos);
    expect_finite(j);
  }
}

TEST(Gltf, LengthsAreMetresTimesTheWorldScale) {
  const SkinParameters p = find_preset("african").parameters;
  Options scaled;
  scaled.world_scale = 2.5;
  const json a = gltf_of(p), b = gltf_of(p, scaled);
  const json& va = a["materials"][0]["extensions"]["KHR_materials_volume"];
  const json& vb = b["materials"][0]["extensions"]["KHR_materials_volume"];
  EXPECT_NEAR(vb["attenuationDistance"].get<double>() / va["attenuationDistance"].get<double>(), 2.5, 1e-5);
  EXPECT_NEAR(vb["thicknessFactor"].get<double>() / va["thicknessFactor"].get<double>(), 2.5, 1e-12);
  EXPECT_EQ(va["attenuationColor"], vb["attenuationColor"]);
  EXPECT_NEAR(b["accessors"][0]["max"][0].get<double>() / a["accessors"][0]["max"][0].get<double>(), 2.5, 1e-6);
  EXPECT_EQ(b["materials"][0]["extras"]["spectral_skin"]["units"]["lengths"], "m x world scale 2.5");
  // glTF's lengths are metres: another unit is refused with one line naming it.
  for (Unit u : {Unit::mm, Unit::cm}) {
    Options o;
    o.unit = u;
    try {
      export_skin("gltf", p, transport::find_model("multipole"), o);
      ADD_FAILURE() << "unit " << unit_name(u) << " accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("units = '" + std::string(unit_name(u)) + "' is not allowed for gltf", 0), 0u) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  Options metres;
  metres.unit = Unit::m;
  EXPECT_EQ(gltf_of(p, metres), a);
}

TEST(Gltf, NamesAreJsonStringsAndHostileNamesAreRefused) {
  // The material, scene, node and mesh names come from --name, written by nlohmann-json; a name
  // that is not an identifier is refused before anything is made (as for every target), and
  // hostile file names (the -o stem) do not reach the document (tests/export/test_escape.cpp:
  // EveryTargetHoldsHostileFileNames parses the .gltf for each).
  Options o;
  o.name = "Skin_2";
  const json j = gltf_of(SkinParameters{}, o);
  EXPECT_EQ(j["materials"][0]["name"], "Skin_2");
  EXPECT_EQ(j["scenes"][0]["name"], "Skin_2");
  EXPECT_EQ(j["meshes"][0]["name"], "Skin_2_preview");
  for (const std::string name : {"a\"b", "x\ny", "<m>", "\xc3\xa9t\xc3\xa9", "a\\u0022"}) {
    Options bad;
    bad.name = name;
    try {
      gltf_of(SkinParameters{}, bad);
      ADD_FAILURE() << "name accepted: " << name;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("name = '", 0), 0u) << e.what();
    }
  }
}

TEST(Gltf, PreviewSphereBufferHoldsWhatItsAccessorsSay) {
  const json j = gltf_of(SkinParameters{});
  const std::string uri = j["buffers"][0]["uri"];
  const std::string head = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(head, 0), 0u);
  const std::vector<unsigned char> bytes = base64_decode(uri.substr(head.size()));
  ASSERT_EQ(bytes.size(), j["buffers"][0]["byteLength"].get<std::size_t>());
  const json& acc = j["accessors"];
  const json& views = j["bufferViews"];
  const std::size_t n = acc[0]["count"];
  EXPECT_EQ(acc[1]["count"], n);
  ASSERT_EQ(views[0]["byteLength"].get<std::size_t>(), 12 * n);
  ASSERT_EQ(views[1]["byteLength"].get<std::size_t>(), 12 * n);
  const std::size_t pos = views[0]["byteOffset"], nor = views[1]["byteOffset"], idx = views[2]["byteOffset"];
  const double r = j["materials"][0]["extensions"]["KHR_materials_volume"]["thicknessFactor"].get<double>() / 2;
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  std::vector<std::array<double, 3>> P(n);
  for (std::size_t v = 0; v < n; ++v) {
    double len2 = 0, dot = 0;
    for (int d = 0; d < 3; ++d) {
      P[v][d] = float_at(bytes, pos + 12 * v + 4 * d);
      const double normal = float_at(bytes, nor + 12 * v + 4 * d);
      lo[d] = std::min(lo[d], P[v][d]);
      hi[d] = std::max(hi[d], P[v][d]);
      len2 += normal * normal;
      dot += normal * P[v][d];
    }
    EXPECT_NEAR(std::sqrt(len2), 1.0, 1e-5) << v;  // unit normals
    EXPECT_NEAR(dot, r, 1e-5 * r) << v;           // on the sphere, pointing out
  }
  for (int d = 0; d < 3; ++d) {  // the bounds are the data's, exactly (the validator checks)
    EXPECT_EQ(acc[0]["min"][d].get<double>(), lo[d]);
    EXPECT_EQ(acc[0]["max"][d].get<double>(), hi[d]);
  }
  // Indices: triangles of the vertices, counter-clockwise seen from outside (glTF's front face).
  const std::size_t k = acc[2]["count"];
  ASSERT_EQ(k % 3, 0u);
  ASSERT_EQ(views[2]["byteLength"].get<std::size_t>(), 2 * k);
  EXPECT_EQ(k / 3, 320u);
  for (std::size_t t = 0; t < k / 3; ++t) {
    std::array<std::size_t, 3> i{};
    for (int c = 0; c < 3; ++c) {
      i[c] = bytes.at(idx + 6 * t + 2 * c) | (bytes.at(idx + 6 * t + 2 * c + 1) << 8);
      ASSERT_LT(i[c], n);
    }
    std::array<double, 3> e1{}, e2{}, centre{};
    for (int d = 0; d < 3; ++d) {
      e1[d] = P[i[1]][d] - P[i[0]][d];
      e2[d] = P[i[2]][d] - P[i[0]][d];
      centre[d] = P[i[0]][d] + P[i[1]][d] + P[i[2]][d];
    }
    const double outward = (e1[1] * e2[2] - e1[2] * e2[1]) * centre[0] +
                           (e1[2] * e2[0] - e1[0] * e2[2]) * centre[1] +
                           (e1[0] * e2[1] - e1[1] * e2[0]) * centre[2];
    EXPECT_GT(outward, 0.0) << t;
  }
}
