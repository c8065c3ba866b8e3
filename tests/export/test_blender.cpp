// The Cycles export proved in Cycles itself: Blender renders the exported material on two scenes
// and the images are compared with this project's own prediction for the same scenes.
// Skipped, with a message, where `blender` is not installed (scripts/install-deps.sh installs it).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>

#include "skin/color/color.hpp"
#include "skin/image/image.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/render/microfacet.hpp"
#include "skin_test_paths.hpp"

using namespace skin;
using skin::util::Rgb;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::RgbProfile;
using skin::model::skin_rgb_profile;
using skin::model::skin_spectrum;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
namespace fs = std::filesystem;

namespace {

bool have_blender() { return std::system("blender --version > /dev/null 2>&1") == 0; }

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("skin-blender-" + name + "-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

void run(const std::string& cmd) {
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

image::Image blender_render(const fs::path& material, const std::string& scene, const fs::path& out,
                            int w, int h, double half_width_m, int samples) {
  const std::string cmd = "blender --background --factory-startup --python " +
                          std::string(SKIN_CYCLES_SCENE) + " -- " + material.string() + " " + scene +
                          " " + out.string() + " " + std::to_string(w) + " " + std::to_string(h) +
                          " " + std::to_string(half_width_m) + " " + std::to_string(samples) +
                          " > " + (out.string() + ".log") + " 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << " (log: " << out << ".log)";
  return image::read_image(out.string(), false);
}

double delta_e(const Rgb& a, const Rgb& b) {
  const color::Xyz white = color::srgb_linear_to_xyz({1.0, 1.0, 1.0});
  return color::delta_e_2000(color::xyz_to_lab(color::srgb_linear_to_xyz(a), white),
                             color::xyz_to_lab(color::srgb_linear_to_xyz(b), white));
}

class Blender : public ::testing::TestWithParam<const char*> {};

// What each preset is held to: Cycles' render against our prediction, measured here (Blender 3.4
// from Debian, the seeds and sample counts below; 2026-12-03) times 1.5, rounded up. Colour under
// uniform light: dE2000 0.14 (caucasian), 0.36 (african). Bleed into the shadow, largest error
// over the channels: 2.3 % (caucasian, blue), 10.6 % (african, red).
struct Held {
  std::string_view preset;
  double delta_e_2000;  // uniform light
  double bleed;         // relative error of the shadow's bleed width, per channel
};
constexpr Held kHeld[] = {{"caucasian", 0.22, 0.035}, {"african", 0.55, 0.16}};

const Held& held(std::string_view preset) {
  for (const Held& h : kHeld)
    if (h.preset == preset) return h;
  throw std::invalid_argument("no measured bounds for preset " + std::string(preset));
}

}  // namespace

TEST_P(Blender, CyclesRenderOfTheExportMatchesOurPrediction) {
  if (!have_blender()) GTEST_SKIP() << "blender is not installed (scripts/install-deps.sh installs it)";
  const std::string preset = GetParam();
  const fs::path dir = temp_dir(preset);
  const fs::path material = dir / "skin.py";
  run(std::string(SKIN_BINARY) + " export --target cycles --units m --preset " + preset + " -o " +
      material.string() + " > /dev/null");
  const SkinParameters p = find_preset(preset).parameters;
  const Held& bound = held(preset);

  // 1. Uniform white light, seen from straight above. Our prediction (the closed form our own
  // renderer reproduces to 1 %, tests/render/test_known_answer.cpp): the surface reflects
  // rho_dr(0) and the subsurface term adds (1 - rho_dr(0)) R_d (1 - rho_dr_mean).
  {
    const image::Image img = blender_render(material, "uniform", dir / "uniform.exr", 16, 16, 0.01, 64);
    const Rgb cycles = img.mean(0, 0, img.width, img.height);
    const render::SpecularAlbedo albedo(p.roughness, p.eta);
    const double rho_o = p.oiliness * albedo.rho_dr(1.0), rho_mean = p.oiliness * albedo.mean();
    const Rgb R_d = skin_spectrum(p).color.srgb_linear;
    Rgb ours;
    for (int c = 0; c < 3; ++c) ours[c] = rho_o + (1 - rho_o) * R_d[c] * (1 - rho_mean);
    const double dE = delta_e(cycles, ours);
    RecordProperty("uniform_delta_e_2000", std::to_string(dE));
    EXPECT_LE(dE, bound.delta_e_2000) << "Cycles " << cycles << " ours " << ours;
  }

  // 2. A vertical sun, the half x < 0 in a sharp shadow. The light bleeding into the shadow,
  // integrated over the distance from the edge and divided by the lit level far from it, is
  // int_0^inf I dx / I_lit = m / pi for the mean exit radius m of the profile (each point of the
  // lit half-plane sends R(rho) to the shadow point at distance x only when x < -rho cos(phi)).
  {
    ProfileSolver solver(RadialGrid::logarithmic(1e-5, 60.0, 400));
    const RgbProfile prof = skin_rgb_profile(p, WavelengthGrid{}, solver);
    std::array<double, 3> predicted{};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> R(prof.R[c]);
      for (double& v : R) v = std::max(v, 0.0);
      double total = 0, moment = 0;
      for (std::size_t j = 1; j < R.size(); ++j) {
        const double r0 = solver.radii().r[j - 1], r1 = solver.radii().r[j];
        const double a = R[j - 1] * r0 * r0, b = R[j] * r1 * r1, dl = std::log(r1 / r0);
        total += 0.5 * (a + b) * dl;
        moment += 0.5 * (a * r0 + b * r1) * dl;
      }
      predicted[c] = moment / total / std::numbers::pi;  // [mm]
    }
    // The view spans +-12 mean radii of the widest channel in 4096 columns, so that the
    // narrowest channel's bleed covers ~10 columns.
    const double m_max = std::numbers::pi * *std::max_element(predicted.begin(), predicted.end());
    const double half_width_m = 12.0 * m_max / 1000.0;
    const int w = 4096, h = 2;
    const image::Image img = blender_render(material, "shadow", dir / "shadow.exr", w, h, half_width_m, 64);
    const double dx_mm = 2 * half_width_m * 1000 / w;
    const Rgb lit = img.mean(w - w / 8, 0, w, h);  // x > 7.5 mm
    const Rgb shadow = img.mean(0, 0, w / 2, h);   // x < 0, averaged
    for (int c = 0; c < 3; ++c) {
      const double measured = shadow[c] * (w / 2) * dx_mm / lit[c];      // [mm]
      RecordProperty(std::string("shadow_width_mm_") + "rgb"[c], std::to_string(measured));
      RecordProperty(std::string("shadow_width_predicted_mm_") + "rgb"[c],
                     std::to_string(predicted[c]));
      EXPECT_NEAR(measured, predicted[c], bound.bleed * predicted[c])
          << "channel " << c << ": light bleeding into the shadow, Cycles vs our profile";
    }
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(LightAndDark, Blender, ::testing::Values("caucasian", "african"));

namespace {
// For sh: in single quotes, each ' as '\''.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

TEST(BlenderHostileName, TheCyclesScriptOfAHostileFileNameRunsNothing) {
  // Issue 29: a file name ending the script's string literal ran its code when Blender opened
  // the script. The script of that name, run by Blender as a user runs it, loads the textures
  // by their names and runs nothing else.
  if (!have_blender()) GTEST_SKIP() << "blender is not installed (scripts/install-deps.sh installs it)";
  const fs::path dir = temp_dir("hostile");
  image::write_exr_planes((dir / "maps.exr").string(),
                          {1, 1, {"melanin", "melanin_blend", "hemoglobin"}, {{0.05f}, {0.5f}, {0.01f}}},
                          {}, "parameter maps");
  const std::string stem = "q\"+__import__(\"os\").system(\"touch PWNED\")+\"q";
  run("cd " + quoted(dir.string()) + " && " + SKIN_BINARY +
      " export --target cycles --solver multipole --parameter-maps maps.exr -o " +
      quoted(stem + ".py") + " > /dev/null");
  const std::string list =
      "import bpy; print('IMAGES', sorted(bpy.path.basename(i.filepath) for i in bpy.data.images if i.filepath))";
  run("cd " + quoted(dir.string()) + " && blender --background --factory-startup --python " +
      quoted(stem + ".py") + " --python-expr " + quoted(list) + " > blender.log 2>&1");
  std::ifstream in(dir / "blender.log");
  const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(fs::exists(dir / "PWNED")) << log;
  EXPECT_NE(log.find("material 'spectral_skin' ready"), std::string::npos) << log;
  EXPECT_NE(log.find("IMAGES ['" + stem + ".subsurface_color.png', '" + stem +
                     ".subsurface_radius.exr']"),
            std::string::npos)
      << log;
  fs::remove_all(dir);
}
