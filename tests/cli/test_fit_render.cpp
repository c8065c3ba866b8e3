// The fit -> render seam: `skin fit --texture` writes EXR channels named by parameter key, and a
// scene's parameter_maps entry keyed by parameter reads the channel of its own name. A uniform
// texture of a preset's colour, fitted and rendered, matches a render of the preset within
// 1 dE2000 in the mean over the object's pixels (same seed: the difference is the parameters').
#include <gtest/gtest.h>

#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli_fixture.hpp"
#include "skin/color/color.hpp"
#include "skin/image/image.hpp"
#include "skin/physics/spectrum.hpp"

namespace {
using json = nlohmann::json;
using skin_test::Cli;
using skin_test::CmdResult;

std::string scene(const std::string& material) {
  return R"({"unit_mm": 10, "camera": {"eye": [0, 0, 6], "look_at": [0, 0, 0], "fov": 30,
             "resolution": [40, 40]},
  "render": {"spp": 16, "max_depth": 3},
  "materials": {"m": )" + material + R"(},
  "objects": [{"sphere": {"center": [0, 0, 0], "radius": 1}, "material": "m"}],
  "lights": [{"type": "directional", "direction": [-0.3, -0.4, -1], "irradiance": 2}],
  "environment": {"radiance": 0.3}})";
}

TEST_F(Cli, FittedParameterMapsRenderLikeThePreset) {
  const json c = json::parse(run("color --preset caucasian --format json").out)["color"];
  skin::image::Image tex(8, 8);
  for (std::size_t i = 0; i < tex.rgb.size(); ++i) tex.rgb[i] = c["srgb_linear"][i % 3].get<float>();
  skin::image::write_image((dir_ / "albedo.png").string(), tex);
  const CmdResult fit = run("fit --texture albedo.png -o params.exr --format json");
  ASSERT_EQ(fit.code, 0) << fit.err;
  EXPECT_LT(json::parse(fit.out)["error_delta_e_2000"]["max"].get<double>(), 1.0) << fit.out;

  std::ofstream(dir_ / "preset.json") << scene(R"({"type": "skin", "preset": "caucasian"})");
  std::ofstream(dir_ / "fitted.json") << scene(R"({"type": "skin", "preset": "caucasian",
      "parameter_maps": {"melanin": {"texture": "params.exr"}, "melanin_blend": {"texture": "params.exr"},
                         "hemoglobin": {"texture": "params.exr"}}})");
  ASSERT_EQ(run("render preset.json -o preset.exr --seed 3").code, 0);
  const CmdResult r = run("render fitted.json -o fitted.exr --seed 3");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto a = skin::image::read_image((dir_ / "preset.exr").string(), false);
  const auto b = skin::image::read_image((dir_ / "fitted.exr").string(), false);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  const skin::color::Colorimetry cm{skin::physics::WavelengthGrid{}};
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
    const skin::color::Rgb pa{a.rgb[i], a.rgb[i + 1], a.rgb[i + 2]}, pb{b.rgb[i], b.rgb[i + 1], b.rgb[i + 2]};
    // The sphere's image: radius tan(asin(1/6)) / tan(15 deg) x 20 = 12.6 pixels about the
    // centre; keep the pixels well inside it (the background is the same in both renders).
    const double x = double(i / 3 % 40) + 0.5 - 20, y = double(i / 3 / 40) + 0.5 - 20;
    if (x * x + y * y > 11.0 * 11.0) continue;
    if (pa.r + pa.g + pa.b < 0.02) continue;  // deep shadow: Lab is noise there
    sum += skin::color::delta_e_2000(skin::color::summarize_rgb(cm, pa).lab,
                                     skin::color::summarize_rgb(cm, pb).lab);
    ++n;
  }
  ASSERT_GT(n, 250);  // about 380 pixels inside radius 11
  EXPECT_LT(sum / n, 1.0) << "mean dE2000 over " << n << " pixels";
  std::printf("mean dE2000 %.3f over %d pixels\n", sum / n, n);
}

TEST_F(Cli, ExtendedMapsCarryTheirColourIntoTheExport) {
  // fit -> export with the extended model: a texture of skin with a thin epidermis (#b48c80, the
  // colour of melanin 2 %, blood 2 %, 0.06 mm of epidermis, 1.5x the scattering; 3.5 dE2000
  // beyond the paper model's gamut) fitted with --model extended gives the thickness, oxygenation
  // and scattering maps as more channels, and the export reads them with the others, so the exported
  // skin's R_d is the texture's colour (within 0.3 dE2000); the paper model's maps of the same
  // texture export the paper fit's colour, more than 1 dE2000 away. (Before, the export read the
  // three named maps only.) The seven default free parameters: their table is built in, so the
  // fit costs little here and under the sanitizers (three free built a table of 768 nodes: 63 s
  // of this test under the sanitizers).
  const skin::color::Rgb target = skin::color::Rgb{skin::color::srgb_decode(0xb4 / 255.0), skin::color::srgb_decode(0x8c / 255.0),
                                                   skin::color::srgb_decode(0x80 / 255.0)};
  skin::image::Image tex(4, 4);
  for (std::size_t i = 0; i < tex.rgb.size(); ++i) tex.rgb[i] = static_cast<float>(target[static_cast<int>(i % 3)]);
  skin::image::write_image((dir_ / "albedo.png").string(), tex);
  const skin::color::Colorimetry cm{skin::physics::WavelengthGrid{}};
  const auto exported_delta_e = [&](const std::string& model, const std::string& free, std::size_t channels) {
    const CmdResult fit = run("fit --texture albedo.png --model " + model + free + " -o " + model + ".exr --format json");
    EXPECT_EQ(fit.code, 0) << fit.err;
    EXPECT_EQ(json::parse(fit.out)["channels"].size(), channels) << fit.out;
    const CmdResult ex = run("export --target openpbr --parameter-maps " + model + ".exr -o " + model + ".mtlx");
    EXPECT_EQ(ex.code, 0) << ex.err;
    std::ifstream in(dir_ / (model + ".fit.json"));
    const json r = json::parse(in)["R_d_ours"];
    const skin::color::Rgb ours{r["r"].get<double>(), r["g"].get<double>(), r["b"].get<double>()};
    return skin::color::delta_e_2000(skin::color::summarize_rgb(cm, ours).lab, skin::color::summarize_rgb(cm, target).lab);
  };
  const double extended = exported_delta_e("extended", "", 8);
  const double paper = exported_delta_e("paper", "", 4);
  EXPECT_LT(extended, 0.3);
  EXPECT_GT(paper, 1.0);
  std::printf("exported R_d to the texture: extended maps %.3f dE2000, paper maps %.3f\n", extended, paper);
}

TEST_F(Cli, ParameterMapChannelsByName) {
  // A map whose channel is missing is an error naming the file and channel; a paper symbol
  // works as the map's key; a map holding values outside the parameter's range is refused.
  skin::image::Image tex(4, 4);
  for (auto& v : tex.rgb) v = 0.5f;
  skin::image::write_image((dir_ / "rgb.exr").string(), tex);
  std::ofstream(dir_ / "missing.json") << scene(R"({"type": "skin",
      "parameter_maps": {"melanin": {"texture": "rgb.exr"}}})");
  const CmdResult m = run("render missing.json -o x.png");
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("channel 'melanin' is missing"), std::string::npos) << m.err;
  std::ofstream(dir_ / "red.json") << scene(R"({"type": "skin",
      "parameter_maps": {"C_m": {"texture": "rgb.exr", "channel": "R", "min": 0, "max": 0.2, "levels": 2}}})");
  EXPECT_EQ(run("render red.json -o red.png --spp 1").code, 0);
  for (auto& v : tex.rgb) v = 1.5f;
  skin::image::write_image((dir_ / "big.exr").string(), tex);
  std::ofstream(dir_ / "big.json") << scene(R"({"type": "skin",
      "parameter_maps": {"hemoglobin": {"texture": "big.exr", "channel": "G"}}})");
  const CmdResult big = run("render big.json -o big.png");
  EXPECT_EQ(big.code, 2);
  EXPECT_NE(big.err.find("hemoglobin (C_h) = 1.5, outside its range [0, 1]"), std::string::npos) << big.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "big.png"));
}

TEST_F(Cli, SceneTakesEveryParameterKeyAndSymbol) {
  std::ofstream(dir_ / "s.json") << scene(R"({"type": "skin", "melanin": 0.1, "beta_m": 0.3,
      "g": 0.85, "bilirubin": 20, "scattering_scale": 1.1, "solver": "multipole"})");
  EXPECT_EQ(run("render s.json -o s.png --spp 1").code, 0);
  std::ofstream(dir_ / "twice.json") << scene(R"({"type": "skin", "melanin": 0.1, "C_m": 0.2})");
  const CmdResult t = run("render twice.json -o t.png");
  EXPECT_EQ(t.code, 2);
  EXPECT_NE(t.err.find("sets melanin a second time"), std::string::npos) << t.err;
}

// Every row of `skin parameters` is a scene key: a value outside its range is refused naming the
// parameter (so the key is read and checked), and the symbol works as well as the key.
TEST_F(Cli, EveryParameterIsASceneKey) {
  const json table = json::parse(run("parameters --format json").out);
  ASSERT_EQ(table.size(), 15u);
  for (const auto& row : table) {
    const std::string key = row["key"];
    const double bad = row["max"].is_null() ? row["min"].get<double>() - 1.0 : row["max"].get<double>() + 1.0;
    std::ofstream(dir_ / "bad.json") << scene(R"({"type": "skin", ")" + key + R"(": )" + json(bad).dump() + "}");
    const CmdResult r = run("render bad.json -o bad.png");
    EXPECT_EQ(r.code, 2) << key;
    EXPECT_NE(r.err.find(row["flag"].get<std::string>().substr(2) + " "), std::string::npos) << key << ": " << r.err;
    if (!row["symbol"].is_null()) {
      std::ofstream(dir_ / "sym.json") << scene(R"({"type": "skin", ")" + row["symbol"].get<std::string>() +
                                               R"(": )" + json(bad).dump() + "}");
      const CmdResult s = run("render sym.json -o sym.png");
      EXPECT_EQ(s.code, 2) << row["symbol"];
      EXPECT_NE(s.err.find(row["symbol"].get<std::string>()), std::string::npos) << s.err;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "bad.png"));
}
}  // namespace
