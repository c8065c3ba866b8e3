// The adding-doubling solver and the accurate radial response against the project's Monte Carlo
// reference (skin::mc::simulate, MCML's method), fixed seeds. Totals: 2 % (the accuracy
// goal) plus three standard errors of the Monte Carlo estimate, with photons enough that three
// standard errors are at most 2 % (checked), so no total passes more than 4 % off. Profiles:
// 10 % plus three standard errors where the standard error is at most 5 % (so at most 25 % off
// at one annulus), and an r-weighted L1 error below 10 %. The diffusion (multipole) model is
// shown to fail the same checks where it is known to be poor, so the tests can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "skin/transport/accurate.hpp"
#include "skin/mc/mc.hpp"
#include "skin/mc/validation.hpp"
#include "skin/transport/profile.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/stack.hpp"
#include "test_support.hpp"

namespace {

using skin::physics::Layer;
using skin::physics::LayerStack;

skin::mc::Result run_mc(const LayerStack& s, std::uint64_t photons, std::uint64_t seed,
                        double r_max = 10.0, std::size_t bins = 200) {
  skin::mc::Options o;
  o.photons = photons;
  o.seed = seed;
  o.r_max = r_max;
  o.bins = bins;
  return skin::mc::simulate(s, o);
}

bool within(double model, double mc, double se, double rel) {
  return std::abs(model - mc) <= rel * mc + 3 * se;
}

// The largest relative standard error of the totals (R_d, and T_d for a slab): 3 SE <= 2 %.
constexpr double kMaxRelSe = 0.02 / 3;
double rel_se(const LayerStack& s, const skin::mc::Result& r) {
  double x = r.R_d_se / r.R_d;
  if (!s.semi_infinite()) x = std::max(x, r.T_d_se / r.T_d);
  return x;
}

// Monte Carlo totals with a relative standard error of at most kMaxRelSe: a pilot run of 20 000
// photons, then as many as the pilot's error says are needed (SE ~ 1 / sqrt(photons)), plus 20 %.
// Dark skin needs millions (R_d ~ 0.005), but its photons are absorbed within a few steps.
skin::mc::Result run_mc_precise(const LayerStack& s, std::uint64_t seed) {
  constexpr double pilot = 20000;
  auto mc = run_mc(s, static_cast<std::uint64_t>(pilot), seed);
  const double ratio = rel_se(s, mc) / kMaxRelSe;
  if (ratio > 1) mc = run_mc(s, static_cast<std::uint64_t>(1.2 * pilot * ratio * ratio), seed);
  return mc;
}

struct PresetCase {
  const char* preset;
  double lambda;
};

// The preset checks: the five presets at 450, 550 and 650 nm.
const std::vector<PresetCase> kPresetCases = [] {
  std::vector<PresetCase> v;
  for (const char* name : {"caucasian", "asian", "african", "pale", "tanned"})
    for (double lambda : {450.0, 550.0, 650.0}) v.push_back({name, lambda});
  return v;
}();
std::string preset_case_name(const ::testing::TestParamInfo<PresetCase>& info) {
  return std::string(info.param.preset) + "_" + std::to_string(int(info.param.lambda));
}

class PresetTotals : public ::testing::TestWithParam<PresetCase> {};

TEST_P(PresetTotals, RdWithinTwoPercentAndThreeSEOfMonteCarlo) {
  const auto [name, lambda] = GetParam();
  const auto st = skin::physics::skin_layer_stack(skin::physics::find_preset(name).parameters, lambda);
  const auto mc = run_mc_precise(st, 42);
  ASSERT_LE(rel_se(st, mc), kMaxRelSe) << name << " " << lambda << " nm: MC " << mc.R_d << " +- " << mc.R_d_se;
  const auto ad = skin::transport::accurate::adding_doubling(st);
  EXPECT_NEAR(ad.R_specular, mc.R_specular, 1e-12);
  EXPECT_TRUE(within(ad.R_d, mc.R_d, mc.R_d_se, 0.02))
      << name << " " << lambda << " nm: AD " << ad << " MC " << mc.R_d << " +- " << mc.R_d_se;
}

INSTANTIATE_TEST_SUITE_P(
    Presets, PresetTotals,
    ::testing::ValuesIn(kPresetCases), preset_case_name);

// The same check fails for diffusion in dark skin (it overstates R_d about 3.5 times at 450 nm).
TEST(PresetTotals, MultipoleFailsTheSameCheckInDarkSkin) {
  const auto st = skin::physics::skin_layer_stack(skin::physics::find_preset("african").parameters, 450);
  const auto mc = run_mc_precise(st, 42);
  EXPECT_FALSE(within(skin::transport::DiffusionStack(st).R_d(), mc.R_d, mc.R_d_se, 0.02));
  EXPECT_GT(skin::transport::DiffusionStack(st).R_d() / mc.R_d, 2.0);
}

// Generic stacks: sigma in 1/mm; one transport mean free path is 1 / (sigma_a + sigma_s').
struct GenericCase {
  const char* label;
  LayerStack stack;
};

LayerStack one(double sigma_a, double sigma_s_prime, double d, double n, double g,
               double n_out = 1.0) {
  LayerStack s;
  s.layers = {Layer{sigma_a, sigma_s_prime, d, n, g}};
  s.eta_above = n_out;
  s.eta_below = n_out;
  return s;
}

std::vector<GenericCase> generic_cases() {
  std::vector<GenericCase> c;
  // Semi-infinite, reduced albedo 0.1 .. 0.999, matched and mismatched.
  c.push_back({"semi_albedo0.1_n1.0", one(0.9, 0.1, skin::physics::kInfinity, 1.0, 0.9)});
  c.push_back({"semi_albedo0.5_n1.4", one(0.5, 0.5, skin::physics::kInfinity, 1.4, 0.9)});
  c.push_back({"semi_albedo0.999_n1.4", one(0.001, 0.999, skin::physics::kInfinity, 1.4, 0.9)});
  c.push_back({"semi_albedo0.9_n1.5_g0", one(0.1, 0.9, skin::physics::kInfinity, 1.5, 0.0)});
  c.push_back({"semi_albedo0.86_n1.03", one(0.415918, 2.51028, skin::physics::kInfinity, 1.03, 0.9)});
  // Slabs of 0.1 to 20 transport mean free paths.
  c.push_back({"slab0.1mfp_albedo0.9_n1.4", one(0.1, 0.9, 0.1, 1.4, 0.9)});
  c.push_back({"slab1mfp_albedo0.3_n1.33", one(0.7, 0.3, 1.0, 1.33, 0.8)});
  c.push_back({"slab20mfp_albedo0.99_n1.0", one(0.01, 0.99, 20.0, 1.0, 0.9)});
  c.push_back({"mcml_slab_n1.5", one(1.0, 2.25, 0.2, 1.5, 0.75)});
  // Bright over dark, dark over bright, and an internal index step.
  LayerStack bd;
  bd.layers = {Layer{0.01, 2.0, 0.3, 1.4, 0.9}, Layer{2.0, 0.5, skin::physics::kInfinity, 1.4, 0.9}};
  c.push_back({"bright_over_dark", bd});
  LayerStack db;
  db.layers = {Layer{3.0, 1.0, 0.1, 1.4, 0.9}, Layer{0.005, 1.5, skin::physics::kInfinity, 1.4, 0.9}};
  c.push_back({"dark_over_bright", db});
  LayerStack step;
  step.layers = {Layer{0.1, 2.0, 0.2, 1.5, 0.9}, Layer{0.05, 1.0, 0.5, 1.33, 0.8}};
  step.eta_above = 1.0;
  step.eta_below = 1.0;
  c.push_back({"index_step_1.5_1.33", step});
  // An index step above a half-space (the interface between the last two layers).
  LayerStack step_half;
  step_half.layers = {Layer{0.373415, 0.933955, 0.447847, 1.31763, 0.5},
                      Layer{0.0190289, 2.42362, skin::physics::kInfinity, 1.09022, 0.5}};
  c.push_back({"index_step_over_half_space", step_half});
  // Random stacks with index steps between every layer (docs/validation/accurate-solver-history.md
  // sec. 1; the automatic quadrature uses 16 points per panel for them).
  LayerStack r3;
  r3.layers = {Layer{0.3761, 0.6239, 0.1031, 1.2511, 0.9}, Layer{0.0073, 0.9927, 0.2425, 1.4988, 0.9},
               Layer{0.6417, 0.3583, 0.5708, 1.2411, 0.9}};
  r3.eta_above = 1.2255;
  r3.eta_below = 1.0250;
  c.push_back({"random_three_index_steps", r3});
  LayerStack r2;
  r2.layers = {Layer{0.6108, 0.3892, 0.4975, 1.1546, 0.9}, Layer{0.1925, 0.8075, 0.2665, 1.4715, 0.5}};
  r2.eta_above = 1.0885;
  r2.eta_below = 1.3383;
  c.push_back({"random_dark_low_index_over_bright", r2});
  return c;
}

class GenericTotals : public ::testing::TestWithParam<GenericCase> {};

TEST_P(GenericTotals, RdAndTdWithinTwoPercentAndThreeSEOfMonteCarlo) {
  const auto& [label, stack] = GetParam();
  const auto mc = run_mc_precise(stack, 7);
  ASSERT_LE(rel_se(stack, mc), kMaxRelSe) << label << ": MC R_d " << mc.R_d << " +- " << mc.R_d_se
                                          << ", T_d " << mc.T_d << " +- " << mc.T_d_se;
  const auto ad = skin::transport::accurate::adding_doubling(stack);
  EXPECT_NEAR(ad.R_specular, mc.R_specular, 1e-12);
  EXPECT_TRUE(within(ad.R_d, mc.R_d, mc.R_d_se, 0.02))
      << label << ": AD " << ad << " MC R_d " << mc.R_d << " +- " << mc.R_d_se;
  if (!stack.semi_infinite()) {
    EXPECT_TRUE(within(ad.T_d, mc.T_d, mc.T_d_se, 0.02))
        << label << ": AD " << ad << " MC T_d " << mc.T_d << " +- " << mc.T_d_se;
  }
}

INSTANTIATE_TEST_SUITE_P(Stacks, GenericTotals, ::testing::ValuesIn(generic_cases()),
                         [](const auto& param_info) {
                           std::string s = param_info.param.label;
                           for (char& ch : s)
                             if (ch == '.') ch = '_';
                           return s;
                         });

// The anisotropy matters beyond sigma_s': at equal reduced coefficients, g = 0 and g = 0.9
// differ measurably in a thin, dark epidermis, and the solver follows the Monte Carlo in both.
TEST(Anisotropy, SolverFollowsMonteCarloForBothG) {
  for (double g : {0.0, 0.9}) {
    auto st = skin::physics::skin_layer_stack(skin::physics::find_preset("asian").parameters, 500);
    for (auto& l : st.layers) l.g = g;
    const auto mc = run_mc_precise(st, 3);
    ASSERT_LE(rel_se(st, mc), kMaxRelSe) << "g=" << g;
    const auto ad = skin::transport::accurate::adding_doubling(st);
    EXPECT_TRUE(within(ad.R_d, mc.R_d, mc.R_d_se, 0.02))
        << "g=" << g << " AD " << ad << " MC " << mc.R_d << " +- " << mc.R_d_se;
  }
}

// Profiles against the Monte Carlo annulus averages over 0.1 - 5 mm (200 annuli of 25 um; the
// model is averaged over each annulus like the tally: 8 sub-radii, area weights). Two measures:
// - pointwise: every annulus whose Monte Carlo estimate has a relative standard error below 5 %
//   must be within 5 % + 3 standard errors for the accurate model (issue 15's goal plus the
//   noise: at most 20 % where the standard error is 5 %, 8 % where it is 1 %) and 10 % + 3 SE for
//   the multipole (the check it fails);
// - r-weighted L1 beyond the noise, sum max(0, |model - MC| - 2 SE) r / sum MC r, below 0.10
//   (in dark skin the Monte Carlo tail beyond 0.3 mm is mostly noise, 10^-5 of the peak).
// Measured with 10^6 photons at 400-700 nm (docs/validation/accurate-solver-history.md,
// section 3; the top-layer tables of the time): the accurate solver's L1 is 0.01-0.06 with no
// annulus beyond 10 % + 3 SE; the multipole's L1 is 0.2-2.
struct ProfileErrors {
  double accurate = 0, multipole = 0;  // r-weighted L1 beyond the noise
  int checked = 0, accurate_bad = 0, multipole_bad = 0;  // annuli, and those beyond 5 / 10 % + 3 SE
  std::string worst;                                     // the accurate solver's worst annulus
};

// Photons: enough for ~8000 reflected (40 000 to 800 000; dark skin's photons are cheap, they
// are absorbed within a few steps).
ProfileErrors profile_errors(const LayerStack& st) {
  const double R_d = skin::transport::accurate::adding_doubling(st).R_d;
  const auto photons = static_cast<std::uint64_t>(std::clamp(8000 / R_d, 4e4, 8e5));
  constexpr double r_max = 5.0;
  constexpr std::size_t bins = 200;
  constexpr int sub = 8;
  const double dr = r_max / bins;
  const auto mc = run_mc(st, photons, 99, r_max, bins);
  std::vector<double> radii;
  for (std::size_t b = 0; b < bins; ++b)
    for (int s = 0; s < sub; ++s) radii.push_back((static_cast<double>(b) + (s + 0.5) / sub) * dr);
  skin::transport::ProfileSolver solver(skin::transport::RadialGrid::from(radii));
  const skin::transport::accurate::AccurateStack acc(st);
  const skin::transport::DiffusionStack mp(st);
  const auto Ra = solver.profile(acc);
  const auto Rm = solver.profile(mp);
  ProfileErrors e;
  double norm = 0, worst = 0;
  for (std::size_t b = 0; b < bins; ++b) {
    if (mc.r_mm[b] < 0.1 || mc.r_mm[b] > 5.0) continue;
    double a = 0, m = 0, w = 0;
    for (int s = 0; s < sub; ++s) {
      const double r = radii[b * sub + s];
      a += Ra[b * sub + s] * r;
      m += Rm[b * sub + s] * r;
      w += r;
    }
    a /= w;
    m /= w;
    e.accurate += std::max(0.0, std::abs(a - mc.R[b]) - 2 * mc.R_se[b]) * mc.r_mm[b];
    e.multipole += std::max(0.0, std::abs(m - mc.R[b]) - 2 * mc.R_se[b]) * mc.r_mm[b];
    norm += mc.R[b] * mc.r_mm[b];
    if (!(mc.R_se[b] < 0.05 * mc.R[b])) continue;
    ++e.checked;
    if (!within(a, mc.R[b], mc.R_se[b], 0.05)) ++e.accurate_bad;
    if (!within(m, mc.R[b], mc.R_se[b], 0.10)) ++e.multipole_bad;
    const double rel = std::abs(a / mc.R[b] - 1);
    if (rel > worst) {
      worst = rel;
      e.worst = "r=" + std::to_string(mc.r_mm[b]) + " mm: model " + std::to_string(a) + ", MC " +
                std::to_string(mc.R[b]) + " +- " + std::to_string(mc.R_se[b]);
    }
  }
  e.accurate /= norm;
  e.multipole /= norm;
  return e;
}

ProfileErrors profile_errors(const char* name, double lambda, double g = 0.9,
                             double dermis_scattering_scale = 0.5) {
  auto params = skin::physics::find_preset(name).parameters;
  params.g = g;
  params.dermis_scattering_scale = dermis_scattering_scale;
  return profile_errors(skin::physics::skin_layer_stack(params, lambda));
}

class PresetProfiles : public ::testing::TestWithParam<PresetCase> {};

TEST_P(PresetProfiles, WithinFivePercentAndThreeSEOfMonteCarloFrom0_1To5mm) {
  const auto [name, lambda] = GetParam();
  const auto e = profile_errors(name, lambda);
  EXPECT_GT(e.checked, 0);
  EXPECT_EQ(e.accurate_bad, 0) << name << " " << lambda << " nm: " << e.accurate_bad << " of "
                               << e.checked << " annuli beyond 5 % + 3 SE; worst " << e.worst;
  EXPECT_LT(e.accurate, 0.10) << name << " " << lambda << " nm: L1 " << e.accurate
                              << " (multipole " << e.multipole << ")";
}

INSTANTIATE_TEST_SUITE_P(
    Presets, PresetProfiles,
    ::testing::ValuesIn(kPresetCases), preset_case_name);

// Dark skin's far field at short wavelengths, read from the skin table: asian skin at 450 nm over
// 0.3-0.7 mm, where the light from below takes over from the epidermis' own (the profile falls to
// ~1e-6 of its value at 0.025 mm). Until 2026-12-05 the table's light from below was the
// difference of two solved profiles, noise there, and the table read -5 % at 0.4-0.5 mm and -29 %
// over 0.6-0.7 mm (this test then failed there; against MCML 1.2.2 -10 % to -41 % at 0.45-0.59 mm,
// docs/accurate-solver.md, sec. 6); it now reads within 2 % of FrequencyStack up to 0.6 mm. 4 x
// 10^6 photons (~4 s), 0.1 mm annuli: standard errors 0.8-2.9 %; every annulus with one below
// 3 % within 5 % + 3 SE.
// Each response averaged (weight r, 16 points) over the Monte Carlo's annuli of width
// r_max / bins whose centre is in [r_lo, r_hi] and whose standard error is below 3 %, held to
// 5 % + 3 SE of it; at least 4 annuli checked per response.
void expect_annuli_within(const skin::mc::Result& mc, double r_max, std::size_t bins, double r_lo, double r_hi,
                          std::initializer_list<std::pair<const char*, const skin::transport::RadialResponse*>> responses) {
  constexpr int sub = 16;
  const double dr = r_max / static_cast<double>(bins);
  std::vector<double> radii;
  for (std::size_t b = 0; b < bins; ++b)
    for (int s = 0; s < sub; ++s) radii.push_back((static_cast<double>(b) + (s + 0.5) / sub) * dr);
  skin::transport::ProfileSolver solver(skin::transport::RadialGrid::from(radii));
  for (const auto& [name, response] : responses) {
    const std::vector<double> R = solver.profile(*response);
    int checked = 0;
    for (std::size_t b = 0; b < bins; ++b) {
      if (mc.r_mm[b] < r_lo || mc.r_mm[b] > r_hi || !(mc.R_se[b] < 0.03 * mc.R[b])) continue;
      double a = 0, w = 0;
      for (int s = 0; s < sub; ++s) {
        a += R[b * sub + s] * radii[b * sub + s];
        w += radii[b * sub + s];
      }
      a /= w;
      ++checked;
      EXPECT_TRUE(within(a, mc.R[b], mc.R_se[b], 0.05))
          << name << ", r = " << mc.r_mm[b] << " mm: " << a << ", Monte Carlo " << mc.R[b] << " +- " << mc.R_se[b]
          << " (" << 100 * (a / mc.R[b] - 1) << " %)";
    }
    EXPECT_GE(checked, 4) << name;
  }
}

TEST(DarkSkinFarField, AsianAt450nmWithinFivePercentAndThreeSEOfMonteCarlo) {
  const LayerStack st = skin::physics::skin_layer_stack(skin::physics::find_preset("asian").parameters, 450);
  const skin::transport::accurate::AccurateStack acc(st);
  ASSERT_TRUE(acc.skin_table());
  expect_annuli_within(run_mc(st, 4000000, 2026, 1.0, 10), 1.0, 10, 0.3, 0.7, {{"table", &acc}});
}

// The same far field under a more scattering dermis (asian skin at 450 nm, the dermis 1.4 times
// as scattering as the epidermis; off the paper's geometry, read from the skin table with the
// dermis ratio's offsets), from the solver and the table, over 0.2-0.8 mm (1e-3 to 1e-6 of the
// profile at 0.025 mm). Until 2026-12-05 both failed here: the solver's orders stepped from 4 to
// 8 across its frequencies and it rang, -37 % over 0.5-0.6 mm (-160 % to +230 % in 20 um annuli);
// the table's dermis-ratio offsets were differences of two solved profiles, noise there, +22 %
// over 0.5-0.6 mm (+400 % at 0.87 mm); solved again, they were held beyond 1e-9 of the node's
// peak and read +28 % over 0.6-0.7 mm (+14 % to +62 % in 20 um annuli of 5 x 10^7 photons; 5 % +
// 3 SE allow 11 % there), now within +3 to +7 % in those annuli. 10^7 photons (~15 s on 2 cores),
// 0.1 mm annuli: standard errors 0.5-2 % up to 0.7 mm.
TEST(DarkSkinFarField, UnderAScatteringDermisBothSolversWithinFivePercentAndThreeSE) {
  skin::physics::SkinParameters p = skin::physics::find_preset("asian").parameters;
  p.dermis_scattering_scale = 1.4;
  const LayerStack st = skin::physics::skin_layer_stack(p, 450);
  const skin::transport::accurate::AccurateStack acc(st);
  ASSERT_TRUE(acc.skin_table());
  const skin::transport::accurate::FrequencyStack sfd(st);
  expect_annuli_within(run_mc(st, 10000000, 2026, 0.8, 8), 0.8, 8, 0.2, 0.8, {{"table", &acc}, {"solver", &sfd}});
}

// A two-layer skin stack in the skin table's reduced units (the epidermis' sigma_s' s per mm, tau =
// s d, a_e and a_d over s, g, index, dermis ratio), which the accurate model must solve rather
// than read (AccurateStack::skin_table() false), held like expect_annuli_within to a Monte Carlo
// of `photons` over annuli of r_max / bins within [r_lo, r_hi].
struct ReducedSkin {
  double s, tau, a_e, a_d, g, eta, ratio;
};
LayerStack stack_of(const ReducedSkin& c) {
  return skin::test::reduced_stack(c.s, c.tau, c.a_e, c.a_d, c.g, c.eta, c.ratio);
}
void expect_solved_within_monte_carlo(const ReducedSkin& c, std::uint64_t photons, double r_max, std::size_t bins,
                                      double r_lo, double r_hi) {
  const LayerStack st = stack_of(c);
  const skin::transport::accurate::AccurateStack acc(st);
  EXPECT_FALSE(acc.skin_table());
  expect_annuli_within(run_mc(st, photons, 2026, r_max, bins), r_max, bins, r_lo, r_hi, {{"accurate", &acc}});
}

// The thinnest epidermis with another g and dermis ratio, near the beam: a 0.066 mm epidermis
// with s 1.19 /mm (tau 0.078, a_e 2.8; over a dermis with a_d 0.10; g 0.76, index 1.41, ratio
// 0.26: a domain skin at 717 nm), where the skin table's nodes end. Read from the table with the
// g and dermis-ratio cross terms it was +28 % off the solver at 0.017 mm and +34 % off 4 x 10^6
// photons at 0.015-0.02 mm (5 % + 3 SE allow 10.6 %): at the thinnest tau nodes the solves' split
// into the two parts rings within about tau of the beam, and the cross terms turned that into a
// bump. Since 2026-12-07 such skin is solved under tau below 0.117 (SkinStackTable::gap). 2 x 10^6
// photons (~2.5 s with the solve), 10 um annuli over 0.01-0.06 mm, those with a standard error
// below 3 % checked.
TEST(ThinnestEpidermis, AnotherGAndDermisRatioNearTheBeamWithinFivePercentAndThreeSE) {
  expect_solved_within_monte_carlo({1.19, 0.0781, 2.8129, 0.1004, 0.7607, 1.4148, 0.2614}, 2000000, 0.1, 10, 0.01, 0.06);
}

// g above 0.955 with a low dermis ratio just under tau 0.45: a bright domain skin at 476 nm (s
// 20.1 /mm, tau 0.40, a_e 0.33, a_d 0.084, g 0.97, index 1.40, ratio 0.23). Read from the skin
// table with the g 0.7 cross terms continued through the base, its far field was -75 % off 2 x
// 10^6 photons at 1.4 mm, 5.6 times what 5 % + 3 SE allow (10 annuli beyond; the solver 0.34 of
// it), and still -75 % with the g 0.95 corners: the table's rows there are at the solver's floor.
// With the far field's rules of SkinStackOffsets::add (2026-12-07) it read +13 % at 1.4 mm, 1.04
// times: such skin (g above 0.91, ratio below 0.35, tau below 0.45) is solved (SkinStackTable::gap).
// 5 x 10^5 photons, 0.1 mm annuli over 0.5-2 mm. Release only (scripts/test.sh: the solve at g
// 0.97 takes 16 directions per panel).
TEST(ThickerEpidermis, GAbove0955WithAnotherDermisRatioWithinFivePercentAndThreeSE) {
  expect_solved_within_monte_carlo({20.1, 0.4022, 0.3288, 0.0844, 0.97, 1.3958, 0.2308}, 500000, 2.0, 20, 0.5, 2.0);
}

// The same class read (tau 0.45 or more): a domain skin at 423 nm (s 23.2 /mm, tau 0.46, a_e 1.84,
// a_d 0.38, g 0.97, index 1.47, ratio 0.2), read with the g 0.95 corners. Before the far field's
// rules of SkinStackOffsets::add its read was -27 % at 0.53 mm against 2 x 10^6 photons (4
// annuli beyond, 2.24 times what 5 % + 3 SE allow): there the dermis ratio's offsets carried the
// noise of the table's rows, near the solver's floor; with them 0.39 times. 10^6 photons, 0.05 mm
// annuli over 0.2-1 mm (1e-3 to 1e-6 of R(0.02 mm)).
TEST(GAboveTheTable, ALowDermisRatioFarFieldReadWithinFivePercentAndThreeSE) {
  const LayerStack st = stack_of({23.2, 0.464, 1.8386, 0.3802, 0.97, 1.4685, 0.2});
  const skin::transport::accurate::AccurateStack acc(st);
  ASSERT_TRUE(acc.skin_table());
  expect_annuli_within(run_mc(st, 1000000, 2026, 1.2, 24), 1.2, 24, 0.2, 1.0, {{"accurate", &acc}});
}

// Half-spaces of skin's index and g under air (the half-space part of the skin table): the same
// pointwise check, over 0.1-5 transport mean free paths (sigma_t' = 1/mm).
TEST(HalfSpaceProfiles, WithinFivePercentAndThreeSEOfMonteCarlo) {
  for (double alpha : {0.5, 0.9, 0.99}) {
    LayerStack s;
    s.layers = {Layer{1 - alpha, alpha, skin::physics::kInfinity, 1.4, 0.9}};
    constexpr std::size_t bins = 100;
    constexpr int sub = 8;
    const double dr = 5.0 / bins;
    const auto mc = run_mc(s, alpha < 0.9 ? 400000 : 100000, 5, 5.0, bins);  // dark: cheap photons
    std::vector<double> radii;
    for (std::size_t b = 0; b < bins; ++b)
      for (int k = 0; k < sub; ++k) radii.push_back((static_cast<double>(b) + (k + 0.5) / sub) * dr);
    skin::transport::ProfileSolver solver(skin::transport::RadialGrid::from(radii));
    const skin::transport::accurate::AccurateStack acc(s);
    ASSERT_TRUE(acc.skin_table());
    const auto R = solver.profile(acc);
    int checked = 0;
    for (std::size_t b = 0; b < bins; ++b) {
      if (mc.r_mm[b] < 0.1 || !(mc.R_se[b] < 0.05 * mc.R[b])) continue;
      double m = 0, w = 0;
      for (int k = 0; k < sub; ++k) {
        m += R[b * sub + k] * radii[b * sub + k];
        w += radii[b * sub + k];
      }
      ++checked;
      EXPECT_TRUE(within(m / w, mc.R[b], mc.R_se[b], 0.05))
          << "alpha'=" << alpha << " r=" << mc.r_mm[b] << ": model " << m / w << ", MC " << mc.R[b]
          << " +- " << mc.R_se[b];
    }
    EXPECT_GT(checked, 3) << alpha;
  }
}

// A dark epidermis that hides the dermis (AccurateStack::hides_below; the skin domain's sample,
// seed 7: a_e 15.45, g 0.763, index 1.45, tau 0.625, here at s = 2 /mm), read from the half-space
// table as its half-space: every 10 um annulus over 0.02-0.3 mm whose standard error is below 3 %
// within 5 % + 3 SE of 2 x 10^7 photons (~1.2 s on 2 cores; 5 x 10^6 under the sanitizers), out to
// 0.11 mm, ~3e-3 of R(0.02 mm). Measured: within -2.0 to +2.6 % there, as the whole stack solved
// (within 0.2 % of the read); at s = 10 /mm against 3 x 10^8 photons the read is within 1 SE out to
// 0.08 mm (~1e-5 of R(0.02 mm)), where the solved stack rings (+16 % to +430 % beyond 0.075 mm).
TEST(HalfSpaceTable, ADarkEpidermisReadWithinFivePercentAndThreeSEOfMonteCarlo) {
  const LayerStack st = skin::test::reduced_stack(2.0, 0.625, 15.45, 0.343, 0.763, 1.45, 1.49);
  const skin::transport::accurate::AccurateStack acc(st);
  ASSERT_TRUE(acc.half_space_table());
  expect_annuli_within(run_mc(st, skin::test::kUnderSanitizers ? 5000000 : 20000000, 2026, 0.3, 30), 0.3, 30, 0.02, 0.3,
                       {{"half-space table", &acc}});
}

// A dark epidermis that nearly hides the dermis (AccurateStack::nearly_hides_below, 7.24 e-folds;
// the skin domain's sample, seed 7: a_e 17.28, g 0.763, index 1.45, ratio 1.49, here at s = 2 /mm),
// read as the two layers' half-spaces: every 10 um annulus over 0.02-0.3 mm whose standard error is
// below 3 % within 5 % + 3 SE of 2 x 10^7 photons (~1 s on 2 cores; 5 x 10^6 under the
// sanitizers), out to ~0.1 mm, ~4e-3 of R(0.02 mm). Measured against 5 x 10^8 photons (29 s, not
// run here): 0.35 of that allowance at worst out to 0.195 mm, 3.1e-5 of R(0.02 mm).
TEST(HalfSpaceTable, ANearlyHiddenDermisReadWithinFivePercentAndThreeSEOfMonteCarlo) {
  const LayerStack st = skin::test::reduced_stack(2.0, 0.396, 17.28, 2.083, 0.763, 1.45, 1.49);
  const skin::transport::accurate::AccurateStack acc(st);
  ASSERT_TRUE(acc.below_as_half_space());
  expect_annuli_within(run_mc(st, skin::test::kUnderSanitizers ? 5000000 : 20000000, 2026, 0.3, 30), 0.3, 30, 0.02, 0.3,
                       {{"two half-spaces", &acc}});
}

// Skin of another anisotropy or dermis scattering, read from the skin table with its offsets
// (docs/accurate-solver.md, sec. 4; until 2026-12-04 solved in the frequency domain), against
// the Monte Carlo. The top-layer tables these stacks read before that solver (removed) were 3-11 %
// off (caucasian at 650 nm +10 % at 4 mm, african at 550 nm with g = 0.95 -16 % at 0.2 mm).
TEST(PresetProfilesOffTheSkinTable, WithinFivePercentAndThreeSEOfMonteCarlo) {
  struct Variant { double g, dermis_scattering_scale; };
  // Three of the six (another g each way, another dermis); the first only under the sanitizers
  // (each ~75 CPU-s there).
  using Case = std::tuple<const char*, double, Variant>;
  for (const auto& [name, lambda, v] : skin::test::sanitized<Case>({{"caucasian", 650.0, Variant{0.75, 0.5}},
                                                                   {"african", 550.0, Variant{0.8, 0.5}},
                                                                   {"caucasian", 650.0, Variant{0.9, 0.25}}})) {
    auto params = skin::physics::find_preset(name).parameters;
    params.g = v.g;
    params.dermis_scattering_scale = v.dermis_scattering_scale;
    EXPECT_TRUE(skin::transport::accurate::AccurateStack(skin::physics::skin_layer_stack(params, lambda)).skin_table())
        << name << " g " << v.g << " dermis " << v.dermis_scattering_scale << ": read with the offsets";
    const auto e = profile_errors(name, lambda, v.g, v.dermis_scattering_scale);
    const std::string what = std::string(name) + " " + std::to_string(lambda) + " nm, g=" +
                             std::to_string(v.g) + " scale=" + std::to_string(v.dermis_scattering_scale);
    EXPECT_GT(e.checked, 0) << what;
    EXPECT_EQ(e.accurate_bad, 0) << what << ": worst " << e.worst;
    EXPECT_LT(e.accurate, 0.10) << what;
  }
}

// The same checks fail for the diffusion model (the paper's multipole), so they can fail.
TEST(PresetProfilesMultipole, FailsTheSameChecks) {
  for (const auto& [name, lambda] : {PresetCase{"caucasian", 550}, PresetCase{"asian", 550},
                                     PresetCase{"african", 650}}) {
    const auto e = profile_errors(name, lambda);
    EXPECT_GT(e.multipole_bad, 0) << name << " " << lambda;
    EXPECT_GT(e.multipole, 0.15) << name << " " << lambda;
  }
}

}  // namespace

// Cases 20 and 51 of `skin validate --domain 60 --domain-seed 2026` as they were drawn before
// 2026-12-04, when the skin domain's epidermal blood was [0, 1] (it is [0, 0.1] now, so the same
// seed draws a tenth of it: the same uniform numbers): the stacks of these tests. (Case 20's
// melanin 0.5 + epidermal blood 1.0 is above 1, which SkinParameters::validate refuses as skin;
// as a layer stack it is a dark top of g 0.97 over index 1.33, a valid transport case.)
static LayerStack domain_2026_case(std::size_t i) {
  const skin::mc::ValidationCase c = skin::mc::domain_cases(60, 2026)[i];
  skin::physics::SkinParameters p = *c.parameters;
  p.epidermal_hemoglobin *= 10;
  return skin::physics::skin_layer_stack(p, c.wavelength);
}

// Strong forward scattering at a low index: the totals need 16 directions per panel. Two dark
// cases of the skin domain (skin validate --domain 60 --domain-seed 2026: cases 20 and 51, g =
// 0.97, index 1.33) had R_d 4.3 and 2.9 % low with 12 (-5.6 and -4.6 standard errors against 2 x
// 10^6 photons); within 0.5 % + 3 SE of 10^6 photons now, and the same check fails with 12 points.
TEST(DomainTotals, StrongForwardScatteringAtLowIndexWithinHalfAPercentAndThreeSE) {
  for (std::size_t i : {19u, 50u}) {
    const LayerStack s = domain_2026_case(i);
    const std::string id = "domain-" + std::to_string(i + 1);
    ASSERT_EQ(s.layers.front().g, 0.97);
    ASSERT_EQ(s.layers.front().eta, 1.33);
    const auto mc = run_mc(s, 1000000, 11);
    const double tol = 0.005 * mc.R_d + 3 * mc.R_d_se;
    const double rd = skin::transport::accurate::adding_doubling(s).R_d;
    EXPECT_NEAR(rd, mc.R_d, tol) << id << ": MC " << mc.R_d << " +- " << mc.R_d_se;
    const double rd12 = skin::transport::accurate::adding_doubling(s, skin::transport::accurate::Options{12}).R_d;
    EXPECT_GT(std::abs(rd12 - mc.R_d), tol) << id << ": 12 points pass too";
  }
}

// The profile near the beam in the same regime (case 20: epidermis 51 um with sigma_a 166 /mm,
// g 0.97, index 1.33, 380 nm): the annuli of 0.02 mm within 0.02-0.1 mm whose Monte Carlo
// relative standard error is below 3 % within 5 % + 3 SE with 16 points per panel (kStrongForwardG);
// with the 12 of g <= 0.95 the first was +21 % (the check below fails with them).
TEST(DomainProfiles, StrongForwardScatteringNearTheBeam) {
  const LayerStack s = domain_2026_case(19);
  const auto mc = run_mc(s, 2000000, 13, 0.1, 5);
  auto annuli = [&](const skin::transport::RadialResponse& model) {
    std::vector<double> radii;
    constexpr int sub = 8;
    for (std::size_t b = 0; b < 5; ++b)
      for (int k = 0; k < sub; ++k) radii.push_back(0.02 * (static_cast<double>(b) + (k + 0.5) / sub));
    skin::transport::ProfileSolver ps(skin::transport::RadialGrid::from(radii));
    const auto R = ps.profile(model);
    std::vector<double> out;
    for (std::size_t b = 0; b < 5; ++b) {
      double m = 0, w = 0;
      for (int k = 0; k < sub; ++k) m += R[b * sub + k] * radii[b * sub + k], w += radii[b * sub + k];
      out.push_back(m / w);
    }
    return out;
  };
  skin::transport::accurate::FrequencyProfileOptions twelve;
  twelve.transport.totals.quadrature_points = 12;
  const auto R = annuli(skin::transport::accurate::AccurateStack(s));
  const auto R12 = annuli(skin::transport::accurate::FrequencyStack(s, twelve));
  int checked = 0, bad12 = 0;
  for (std::size_t b = 1; b < 5; ++b) {
    if (!(mc.R_se[b] < 0.03 * mc.R[b])) continue;
    ++checked;
    EXPECT_TRUE(within(R[b], mc.R[b], mc.R_se[b], 0.05))
        << "r = " << mc.r_mm[b] << " mm: model " << R[b] << ", MC " << mc.R[b] << " +- " << mc.R_se[b];
    bad12 += !within(R12[b], mc.R[b], mc.R_se[b], 0.05);
  }
  EXPECT_GE(checked, 1);
  EXPECT_GE(bad12, 1) << "12 points pass too";
}
