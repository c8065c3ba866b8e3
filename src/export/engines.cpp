// The game engines' Burley profiles: Unreal Engine's Subsurface Profile and Unity HDRP's
// Diffusion Profile, both Christensen-Burley normalized diffusion fitted by fit_burley
// (docs/export.md, "Burley targets").
#include <algorithm>
#include <sstream>

#include "fits.hpp"
#include "report.hpp"
#include "skin/color/color.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting::detail {

using skin::util::Rgb;


using skin::physics::SkinParameters;


namespace {

// Christensen & Burley 2015, eq. 6 (perpendicular incidence): d = l / s(A) for the mean free
// path l; Unreal's Burley subsurface profile takes l (its "mean free path").
double burley_s_perpendicular(double A) { return 1.9 - A + 3.5 * (A - 0.8) * (A - 0.8); }

Export write_unreal(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const BurleyFit b = fit_burley(ref);
  const SkinParameters& p = ref.parameters;
  Rgb l_cm;
  for (int c = 0; c < 3; ++c) l_cm[c] = burley_s_perpendicular(b.A[c]) * b.d_mm[c] * 0.1;
  const double l_max = std::max({l_cm.r, l_cm.g, l_cm.b});
  const Rgb l_rel = {l_cm.r / l_max, l_cm.g / l_max, l_cm.b / l_max};
  // Unreal's world unit is a centimetre; world_unit_scale = cm per world unit of the scene.
  const double world_unit_scale = 1.0 / (per_mm(unit) * 10.0) / o.world_scale;
  Export e;
  e.report = fit_report(ctx,
                        "Unreal Burley subsurface profile: Christensen-Burley normalized diffusion, "
                        "R = A (e^{-r/d} + e^{-r/3d}) / (8 pi d r), d = mean free path / s(A), "
                        "s(A) = 1.9 - A + 3.5 (A - 0.8)^2; surface albedo = A",
                        b.R_d, b.R);
  e.report.values = {{"surface_albedo", vec(b.A)},
                     {"mean_free_path_color", vec(l_rel)},
                     {"mean_free_path_distance", {l_max}},
                     {"world_unit_scale", {world_unit_scale}},
                     {"tint", {1.0, 1.0, 1.0}},
                     {"transmission_tint_color", {1.0, 1.0, 1.0}},
                     {"ior", {p.eta}}};
  json j = document_head("Spectral Skin export: Unreal Engine Subsurface Profile (Burley)", o);
  j["units"] = {{"mean_free_path_distance", "cm"}, {"world_unit_scale", "cm per world unit"}};
  j["settings"] = values_json(e.report);
  j["settings"]["enable_burley"] = true;
  e.files.push_back({"", rounded(j).dump(2) + "\n", false});
  std::ostringstream s;
  s << header_lines("#", e, ctx);
  s << "# Run inside the Unreal Editor (Python Editor Script Plugin): creates or updates the\n"
       "# Subsurface Profile asset /Game/NAME.\nimport unreal\n\n";
  s << "NAME = " << util::escape::python_string(o.name, kName) << "\n";
  s << "SETTINGS = {\n"
    << "    \"enable_burley\": True,\n"
    << "    \"surface_albedo\": unreal.LinearColor(" << triple(b.A) << ", 1.0),\n"
    << "    \"mean_free_path_color\": unreal.LinearColor(" << triple(l_rel) << ", 1.0),\n"
    << "    \"mean_free_path_distance\": " << num(l_max) << ",  # cm\n"
    << "    \"world_unit_scale\": " << num(world_unit_scale) << ",\n"
    << "    \"tint\": unreal.LinearColor(1.0, 1.0, 1.0, 1.0),\n"
    << "    \"transmission_tint_color\": unreal.LinearColor(1.0, 1.0, 1.0, 1.0),\n"
    << "    \"ior\": " << num(p.eta) << ",\n}\n";
  s << R"PY(

def make_profile(path="/Game"):
    tools = unreal.AssetToolsHelpers.get_asset_tools()
    asset = unreal.EditorAssetLibrary.load_asset(path + "/" + NAME)
    if asset is None:
        asset = tools.create_asset(NAME, path, unreal.SubsurfaceProfile, unreal.SubsurfaceProfileFactory())
    settings = asset.get_editor_property("settings")
    missing = []
    for key, value in SETTINGS.items():
        try:
            settings.set_editor_property(key, value)
        except Exception:  # a property this engine version does not have
            missing.append(key)
    asset.set_editor_property("settings", settings)
    unreal.EditorAssetLibrary.save_loaded_asset(asset)
    if missing:
        unreal.log_warning("spectral_skin: not set in this engine version: " + ", ".join(missing))
    return asset


if __name__ == "__main__":
    make_profile()
)PY";
  e.files.push_back({".py", s.str(), false});
  return e;
}

Export write_unity(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const BurleyFit b = fit_burley(ref);
  const SkinParameters& p = ref.parameters;
  const double d_max = std::max({b.d_mm.r, b.d_mm.g, b.d_mm.b});
  const Rgb d_rel = {b.d_mm.r / d_max, b.d_mm.g / d_max, b.d_mm.b / d_max};
  // HDRP: scattering distance in mm; world scale = metres per world unit.
  const double world_scale = per_mm(unit) == 1.0 ? 0.001 : per_mm(unit) == 0.1 ? 0.01 : 1.0;
  const double world = world_scale / o.world_scale;
  const double thickness_mm = p.epidermis_thickness + 5.0;
  Export e;
  e.report = fit_report(ctx,
                        "HDRP diffusion profile: Christensen-Burley normalized diffusion with shape "
                        "S = 1 / (scattering distance x multiplier), albedo = the material's base "
                        "colour (pre- and post-scatter)",
                        b.R_d, b.R);
  e.report.values = {{"base_color", vec(b.A)},
                     {"scattering_distance", vec(d_rel)},
                     {"scattering_distance_multiplier", {d_max}},
                     {"transmission_tint", {1.0, 1.0, 1.0}},
                     {"thickness_remap", {0.0, thickness_mm}},
                     {"ior", {p.eta}},
                     {"world_scale", {world}}};
  std::ostringstream s;
  s << header_lines("//", e, ctx);
  // The name is also the class's (Options::validate: an identifier); in strings it is escaped.
  s << "// Put this file in an Editor folder of an HDRP project; run Tools > Spectral Skin > "
       "Create " << o.name << ".\n// The material's base colour (linear): " << triple(b.A)
    << " (sRGB " << color::hex(color::srgb8(b.A)) << ").\n";
  s << "using UnityEditor;\nusing UnityEngine;\nusing UnityEngine.Rendering.HighDefinition;\n\n";
  s << "public static class SpectralSkin_" << o.name << "\n{\n";
  s << "    [MenuItem(" << util::escape::csharp_string("Tools/Spectral Skin/Create " + o.name, kName)
    << ")]\n";
  s << "    public static void Create()\n    {\n";
  s << "        var asset = ScriptableObject.CreateInstance<DiffusionProfileSettings>();\n";
  s << "        AssetDatabase.CreateAsset(asset, "
    << util::escape::csharp_string("Assets/" + o.name + ".asset", kName) << ");\n";
  s << "        var so = new SerializedObject(asset);\n";
  s << "        so.FindProperty(\"profile.scatteringDistance\").colorValue = new Color(" << num(d_rel.r)
    << "f, " << num(d_rel.g) << "f, " << num(d_rel.b) << "f, 1f);\n";
  s << "        so.FindProperty(\"profile.scatteringDistanceMultiplier\").floatValue = " << num(d_max)
    << "f; // mm\n";
  s << "        so.FindProperty(\"profile.transmissionTint\").colorValue = Color.white;\n";
  s << "        so.FindProperty(\"profile.thicknessRemap\").vector2Value = new Vector2(0f, "
    << num(thickness_mm) << "f); // mm\n";
  s << "        so.FindProperty(\"profile.ior\").floatValue = " << num(p.eta) << "f;\n";
  s << "        so.FindProperty(\"profile.worldScale\").floatValue = " << num(world)
    << "f; // metres per world unit\n";
  s << "        so.ApplyModifiedProperties();\n        AssetDatabase.SaveAssets();\n    }\n}\n";
  e.files.push_back({"", s.str(), false});
  json j = document_head("Spectral Skin export: Unity HDRP Diffusion Profile", o);
  j["units"] = {{"scattering_distance_multiplier", "mm"},
                {"thickness_remap", "mm"},
                {"world_scale", "m per world unit"}};
  j["profile"] = values_json(e.report);
  e.files.push_back({".json", rounded(j).dump(2) + "\n", false});
  return e;
}

}  // namespace

TargetSpec unreal_target() {
  return {"unreal", "Unreal Engine Subsurface Profile (Burley): JSON and an editor Python script",
          ".json", Unit::cm, write_unreal};
}

TargetSpec unity_target() {
  return {"unity", "Unity HDRP Diffusion Profile: an editor C# script making the asset, and JSON",
          ".cs", Unit::m, write_unity};
}

}  // namespace skin::exporting::detail
