// skin::export: the targets' models against closed forms and brute-force numerics, and every
// target for every preset.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string_view>

#include "skin/export/export.hpp"
#include "skin/mc/mc.hpp"
#include "skin/mc/tabulate.hpp"
#include "skin/transport/random_walk_table.hpp"
#include "skin/util/error.hpp"

using namespace skin;
using skin::util::InputError;
using skin::physics::Preset;
using skin::physics::SkinParameters;
using skin::physics::find_preset;
using skin::physics::presets;
using skin::physics::paper_presets;
using namespace skin::exporting;

TEST(ExportModels, BurleyProfileIsNormalisedWithMeanRadius2point5d) {
  // int R 2 pi r dr = 1 and int r R 2 pi r dr = 2.5 d (Christensen & Burley 2015), by the
  // trapezoid rule in ln r over 1e-7 d .. 200 d (tails beyond: < 1e-20).
  for (double d : {0.1, 1.0, 3.0}) {
    double total = 0, moment = 0;
    const int n = 200000;
    const double a = std::log(1e-7 * d), b = std::log(200 * d), h = (b - a) / n;
    for (int i = 0; i <= n; ++i) {
      const double r = std::exp(a + i * h), w = (i == 0 || i == n) ? 0.5 : 1.0;
      const double f = burley_profile(d, r) * 2 * std::numbers::pi * r * r * h * w;
      total += f;
      moment += f * r;
    }
    EXPECT_NEAR(total, 1.0, 1e-6) << d;
    EXPECT_NEAR(moment / total, 2.5 * d, 1e-5 * d) << d;
  }
}

TEST(ExportModels, AlbedoInversionsAreMonotoneAndMatchTheWalk) {
  // Both inversions were fitted so that the random walk's total reflectance is the albedo A:
  // through our Monte Carlo table of that walk they give R(alpha(A)) = A for A in [0.1, 0.8]
  // (skin's channels lie there) within their fits' own accuracy, and increase with A. Measured
  // here (2026-12-03, data/random_walk_g0.csv): Chiang's largest |R / A - 1| 2.10 % (A = 0.1),
  // Cycles' 1.44 % (A = 0.8); held to 2.5 % and 1.8 % (1.2x and 1.25x).
  const auto& table = transport::RandomWalkTable::builtin();
  double prev_c = -1, prev_y = -1;
  for (double A = 0.1; A <= 0.8001; A += 0.05) {
    const double ac = chiang_alpha(A), ay = cycles_alpha(A, 0.0);
    EXPECT_GT(ac, prev_c);
    EXPECT_GT(ay, prev_y);
    prev_c = ac;
    prev_y = ay;
    EXPECT_NEAR(table.reflectance(ac), A, 0.025 * A) << A;
    EXPECT_NEAR(table.reflectance(ay), A, 0.018 * A) << A;
  }
}

TEST(ExportModels, RandomWalkTableAgreesWithAFreshMonteCarloRun) {
  // The embedded table against an independent run (another seed) at an off-node albedo:
  // R_d within 4 standard errors + 0.5 % (interpolation); measured 0.67 standard errors. Mean
  // radius: measured 0.47 % (2026-12-03), about the run's own standard error (the exit radius
  // spreads ~1.8 mean free paths around its mean of 1.6 over ~6e4 exiting photons: ~0.45 %);
  // held to 1.5 % (3x: about 3 standard errors).
  const auto& table = transport::RandomWalkTable::builtin();
  mc::RandomWalkOptions o;
  o.alpha = {0.95, 0.96};
  o.photons = 100000;
  o.seed = 12345;
  const transport::RandomWalkTable fresh = mc::tabulate_random_walk(o);
  EXPECT_NEAR(table.reflectance(0.95), fresh.R_d[0], 4 * fresh.R_d_se[0] + 0.005 * fresh.R_d[0]);
  EXPECT_NEAR(table.mean_rho(0.95), fresh.mean_rho(0.95), 0.015 * fresh.mean_rho(0.95));
}

TEST(ExportModels, RandomWalkTableRoundTripsThroughCsv) {
  const auto& t = transport::RandomWalkTable::builtin();
  const auto u = transport::RandomWalkTable::from_csv(t.to_csv(), "round trip");
  ASSERT_EQ(u.alpha.size(), t.alpha.size());
  for (std::size_t i = 0; i < t.alpha.size(); ++i) EXPECT_NEAR(u.R_d[i], t.R_d[i], 1e-6);
  EXPECT_THROW(transport::RandomWalkTable::from_csv("# g: 0\nalpha,R_d\n0.5,0.2\n", "bad"), InputError);
  // Physically impossible rows (the fuzzer found a negative R_d read as it was): R_d outside
  // [0, 1], annuli holding more than R_d.
  const std::string head = "# provenance: test\n# g: 0\n# rho_edges: 0,0.1,1,10\nalpha,R_d,R_d_se,f_0,f_1,f_2\n0.05,0.01,1e-5,0.001,0.001,0.001\n";
  EXPECT_NO_THROW(transport::RandomWalkTable::from_csv(head + "0.9,0.5,1e-4,0.1,0.2,0.1\n", "good"));
  for (const char* row : {"0.9,-0.5,1e-4,0.1,0.2,0.1\n", "0.9,1.5,1e-4,0.1,0.2,0.1\n", "0.9,0.5,-1,0.1,0.2,0.1\n",
                          "0.9,0.3,1e-4,0.1,0.2,0.1\n"})
    EXPECT_THROW(transport::RandomWalkTable::from_csv(head + row, "bad"), InputError) << row;
}

namespace {

// Per target, how far its export may be from our skin, per linear sRGB channel: the largest value
// over the six presets, measured with the accurate solver (2026-12-03; this test's own numbers,
// also in FILE.fit.json of `skin export --target all --preset P` to 6 digits and in
// docs/export.md, "Measured error"), times 1.25 rounded up to two digits. Colours matched by
// construction (bisection to double precision: measured <= 3.5e-13) are held to 1e-9; targets
// whose profile is ours (mitsuba3's media are our layers, profile is our table) to exactly 0.
struct Held {
  std::string_view target;
  double delta_e_2000;
  std::array<double, 3> profile_l1, mean_radius_error;  // |relative error|
};
constexpr double kExact = 1e-9;
constexpr Held kHeld[] = {
    // Random walk (its shape; the mean radius matched up to the table's interpolation).
    {"openpbr", kExact, {0.33, 0.20, 0.26}, {3.9e-5, 3.4e-5, 3.2e-5}},
    {"standard-surface", kExact, {0.33, 0.20, 0.26}, {3.9e-5, 3.4e-5, 3.2e-5}},
    {"cycles", kExact, {0.34, 0.21, 0.27}, {3.5e-5, 4.3e-5, 2.3e-5}},
    // Burley (its shape; the mean radius set in closed form, 2.5 d, measured on the radial grid).
    {"unreal", kExact, {0.32, 0.23, 0.29}, {3.9e-4, 7.4e-4, 1.8e-3}},
    {"unity", kExact, {0.32, 0.23, 0.29}, {3.9e-4, 7.4e-4, 1.8e-3}},
    // An effective half-space fitted per wavelength, then projected to RGB: measured largest
    // dE 0.032 (ear), L1 0.42 (asian, red), mean radius 9.3 % (tanned, blue).
    {"pbrt-v4", 0.040, {0.53, 0.39, 0.17}, {2.2e-3, 0.062, 0.12}},
    {"mitsuba3", 0, {0, 0, 0}, {0, 0, 0}},
    // Gaussians fitted to the shape (least L1), not to the mean radius: asian's red 36.9 %.
    {"realtime", kExact, {0.22, 0.15, 0.20}, {0.47, 0.090, 0.15}},
    {"profile", 0, {0, 0, 0}, {0, 0, 0}},
    // OpenPBR's random walk in glTF's extensions (the same fit).
    {"gltf", kExact, {0.33, 0.20, 0.26}, {3.9e-5, 3.4e-5, 3.2e-5}},
};

}  // namespace

TEST(Export, EveryTargetForEveryPresetIsHeldToItsMeasuredError) {
  const transport::Model& model = transport::default_model();
  ASSERT_EQ(std::size(kHeld), targets().size()) << "a target without its measured bounds";
  for (const Held& held : kHeld) {
    const Target& t = find_target(held.target);
    for (const Preset& preset : paper_presets()) {
      SCOPED_TRACE(std::string(preset.name) + " / " + std::string(t.name));
      const Export e = export_skin(t.name, preset.parameters, model, Options{});
      ASSERT_FALSE(e.files.empty());
      EXPECT_FALSE(e.files[0].content.empty());
      const FitReport& r = e.report;
      EXPECT_TRUE(r.representable);
      EXPECT_LE(r.delta_e_2000, held.delta_e_2000);
      for (int c = 0; c < 3; ++c) {
        EXPECT_LE(r.profile_l1[c], held.profile_l1[c]) << "channel " << "rgb"[c];
        EXPECT_LE(std::abs(r.mean_radius_error[c]), held.mean_radius_error[c])
            << "channel " << "rgb"[c];
      }
    }
  }
}

TEST(Export, BadOptionsGiveOneLine) {
  const SkinParameters p;
  const transport::Model& m = transport::default_model();
  Options o;
  EXPECT_THROW(export_skin("renderman", p, m, o), InputError);
  o.world_scale = -1;
  EXPECT_THROW(export_skin("cycles", p, m, o), InputError);
  o = Options{};
  o.name = "1bad name";
  EXPECT_THROW(export_skin("cycles", p, m, o), InputError);
  o = Options{};
  o.taps = 4;
  EXPECT_THROW(export_skin("realtime", p, m, o), InputError);
  EXPECT_THROW(parse_unit("km"), InputError);
  ParameterMapsInput maps{"maps.exr", 1, 1, {"melanin"}, {{0.1f}}};
  EXPECT_THROW(export_skin("unity", p, m, Options{}, &maps), InputError);
  maps.values[0][0] = 2.0f;  // melanin outside [0, 1]
  EXPECT_THROW(export_skin("cycles", p, m, Options{}, &maps), InputError);
}

TEST(Export, ParameterMapsGiveOneFitPerTexel) {
  // A 2 x 1 map of two skins: the textures hold each texel's own fit (the colour of the light
  // texel is the light skin's single export).
  const transport::Model& m = transport::default_model();
  const SkinParameters light = find_preset("caucasian").parameters;
  const SkinParameters dark = find_preset("african").parameters;
  ParameterMapsInput maps{"maps.exr", 2, 1, {"melanin", "melanin_blend", "hemoglobin"},
                          {{float(light.melanin), float(dark.melanin)},
                           {float(light.melanin_blend), float(dark.melanin_blend)},
                           {float(light.hemoglobin), float(dark.hemoglobin)}}};
  SkinParameters base = light;
  const Export e = export_skin("cycles", base, m, Options{}, &maps);
  ASSERT_EQ(e.images.size(), 2u);
  EXPECT_EQ(e.report.texels, 2u);
  const Export single = export_skin("cycles", light, m, Options{});
  const auto& vals = single.report.values[0].second;  // subsurface_color
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.images[0].rgb.at(0, 0)[c], vals[c], 1e-5) << c;
  EXPECT_LT(e.images[0].rgb.at(1, 0)[1], 0.5 * e.images[0].rgb.at(0, 0)[1]);  // darker
}
