// The tabulated frequency-domain profiles of the skin geometry and of the half-space of skin's
// medium (skin_stack_table.hpp): the built-in table holds FrequencyStack's profiles at its nodes,
// agrees with FrequencyStack between them on the skin presets and on half-spaces, integrates to
// the adding-doubling R_d, covers every preset and names what it does not cover, and refuses
// malformed files.
#include <gtest/gtest.h>
#include <iostream>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>

#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/profile.hpp"
#include "skin/transport/skin_stack_table.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"
#include "skin/util/table.hpp"
#include "skin_test_paths.hpp"
#include "test_support.hpp"

namespace {
using skin::physics::Layer;
using skin::transport::accurate::SkinStackTable;
using skin::transport::accurate::SkinStackOffsets;
using skin::transport::accurate::SkinStackCross;

skin::physics::LayerStack preset_stack(const char* name, double lambda) {
  return skin::physics::skin_layer_stack(skin::physics::find_preset(name).parameters, lambda);
}

TEST(SkinStackTable, BuiltinHasTheDefaultNodesAndGeometry) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const SkinStackTable d = SkinStackTable::default_nodes();
  EXPECT_EQ(t.eta, 1.4);
  EXPECT_EQ(t.g, 0.9);
  EXPECT_EQ(t.dermis_ratio, 0.5);
  for (const auto& [a, b] : {std::pair{&t.tau, &d.tau}, {&t.a_e, &d.a_e}, {&t.a_d, &d.a_d}, {&t.x, &d.x}, {&t.a_h, &d.a_h}}) {
    ASSERT_EQ(a->size(), b->size());
    for (std::size_t i = 0; i < a->size(); ++i) EXPECT_NEAR((*a)[i] / (*b)[i], 1.0, 1e-6);
  }
  EXPECT_EQ(t.ln_rho.size(), t.tau.size() * t.a_e.size() * t.a_d.size() * t.x.size());
  EXPECT_EQ(t.ln_rho_top.size(), t.tau.size() * t.a_e.size() * t.x.size());
  EXPECT_EQ(t.ln_rho_half.size(), t.a_h.size() * t.x.size());
}

// `skin tabulate-skin-profiles --reuse`: a table with more a_d nodes copies every row the reused
// one holds and solves only the new a_d's light from below (with the top layer's R(k) solved again
// for it), as solve_low() does (new tau or a_e nodes: their top layer too). One node of tau 4.5,
// a_e 0.4, a_d 0.126 (the built-in file's rows), then a_d 1.28 added. (The comparison with
// solve_low() in Release only.)
TEST(SkinStackTable, ReuseSolvesOnlyTheNewNodes) {
  const SkinStackTable stored = SkinStackTable::parse(skin::util::data::embedded("skin_stack_profiles.csv"), "profiles");
  auto index = [](const std::vector<double>& v, double x) {
    const auto i = static_cast<std::size_t>(std::min_element(v.begin(), v.end(), [x](double a, double b) { return std::abs(a - x) < std::abs(b - x); }) - v.begin());
    EXPECT_NEAR(v[i], x, 1e-3 * x);
    return i;
  };
  const std::size_t i_t = index(stored.tau, 4.5), i_e = index(stored.a_e, 0.4), i_d = index(stored.a_d, 0.1265), n_x = stored.x.size();
  SkinStackTable one = SkinStackTable::default_nodes();
  one.tau = {stored.tau[i_t]};
  one.a_e = {stored.a_e[i_e]};
  one.a_d = {stored.a_d[i_d]};
  one.a_h.clear();
  const std::size_t kt = i_t * stored.a_e.size() + i_e, k = kt * stored.a_d.size() + i_d;
  one.ln_rho_top.assign(stored.ln_rho_top.begin() + static_cast<std::ptrdiff_t>(kt * n_x), stored.ln_rho_top.begin() + static_cast<std::ptrdiff_t>((kt + 1) * n_x));
  one.ln_rho.assign(stored.ln_rho.begin() + static_cast<std::ptrdiff_t>(k * n_x), stored.ln_rho.begin() + static_cast<std::ptrdiff_t>((k + 1) * n_x));
  SkinStackTable more = one;
  more.a_d = {one.a_d[0], 1.282456};
  std::size_t total = 0, calls = 0;
  more.compute([&](std::size_t, std::size_t n) { total = n; ++calls; }, &one);
  EXPECT_EQ(total, 3u);  // 1 top + 2 a_d
  EXPECT_EQ(calls, 3u);
  ASSERT_EQ(more.ln_rho.size(), 2 * n_x);
  EXPECT_TRUE(std::equal(one.ln_rho.begin(), one.ln_rho.end(), more.ln_rho.begin()));
  EXPECT_EQ(one.ln_rho_top, more.ln_rho_top);
  if (skin::test::kUnderSanitizers) return;
  const std::vector<double> solved = more.solve_low(4.5, 0.4, 1.282456);
  EXPECT_TRUE(std::equal(solved.begin(), solved.end(), more.ln_rho.begin() + static_cast<std::ptrdiff_t>(n_x)));
}

// Three nodes solved again (a bright epidermis over a bright dermis; african skin's epidermis over
// its dermis; a 0.078-deep epidermis over a bright dermis; the first only under the sanitizers):
// each of the table's two parts is its own solve (the top layer to its 4 stored decimals, the light
// from below within the change of the solver's orders), and their sum the stack's solve.
TEST(SkinStackTable, NodesAreTheFrequencyDomainProfiles) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const auto i_01 = static_cast<std::size_t>(std::lower_bound(t.x.begin(), t.x.end(), 0.1) - t.x.begin());
  // Each part is its own solve: the top layer alone over the absorber, and the light from below
  // (R(k) of the stack minus the top layer's, inverted): the top to the table's 4 decimals of ln
  // rho, the light from below within the change of the solver's orders (below).
  // (tau 2, 1.33 and 0.078: the thinnest epidermis; tau 4.5, a_e 1.58, a_d 0.78: a dark epidermis whose
  // light from below is ~e^-32 of the peak.) Their sum is the stack's FrequencyStack profile
  // within 2.5 % from x = 0.1 (r >= 1.4 um in skin) where that is above 1e-6 of rho(0.1).
  // Measured with the solver's orders of 2026-12-05 (the same at every k): the stored nodes 6e-4
  // at most, the thinnest 1.6 % (at x = 20; it differs by up to 5.3 % at x = 0.01-0.075, nearer
  // the beam than a tenth of its depth). With the earlier orders, which grew with k, the stack's
  // own solve rang and differed from the sum by 2.2 % at x = 3.7 of the dark node.
  constexpr double kWholeTol = 0.025;
  for (const auto& [i, j, l] : skin::test::sanitized(
           {std::tuple{8u, 4u, 3u}, std::tuple{7u, 20u, 7u}, std::tuple{0u, 12u, 5u}, std::tuple{10u, 13u, 9u}})) {
    const std::vector<double> top = t.solve_top(t.tau[i], t.a_e[j]);
    const std::vector<double> low = t.solve_low(t.tau[i], t.a_e[j], t.a_d[l]);
    const std::size_t first_top = (i * t.a_e.size() + j) * t.x.size(), first_low = ((i * t.a_e.size() + j) * t.a_d.size() + l) * t.x.size();
    const double low_peak = *std::max_element(low.begin(), low.end());
    int compared = 0;
    for (std::size_t m = 0; m < t.x.size(); ++m) {
      if (top[m] >= top[i_01] + std::log(1e-8)) {
        EXPECT_NEAR(t.ln_rho_top[first_top + m], top[m], 6e-5) << "top " << i << ',' << j << " x = " << t.x[m];
      }
      if (low[m] >= low_peak + std::log(1e-6)) {  // (below, the inversion's rounding: 4e-4 at 1e-8)
        // The stored light from below was solved with the orders of before 2026-12-05 (growing
        // with k: docs/accurate-solver.md, sec. 3), which rang; solved again with today's it
        // differs by up to 1.4e-3 in ln rho above 1e-2 of its peak, 5.8e-3 down to 1e-4 and
        // 0.025 down to 1e-6 (the whole profile is within kWholeTol of the stack's solve).
        const double rel = low[m] - low_peak;
        const double tol = rel > std::log(1e-2) ? 2e-3 : rel > std::log(1e-4) ? 1e-2 : 0.04;
        EXPECT_NEAR(t.ln_rho[first_low + m], low[m], tol) << "low " << i << ',' << j << ',' << l << " x = " << t.x[m];
        ++compared;
      }
    }
    EXPECT_GT(compared, 10);
    const std::vector<double> stored = t.node(i, j, l);
    const std::vector<double> solved = t.solve_node(t.tau[i], t.a_e[j], t.a_d[l]);
    for (std::size_t m = 0; m < solved.size(); ++m) {
      if (solved[m] < solved[i_01] + std::log(1e-6) || t.x[m] < 0.1) continue;
      EXPECT_NEAR(stored[m], solved[m], kWholeTol) << "node " << i << ',' << j << ',' << l << " x = " << t.x[m];
    }
  }
}

// Two half-space nodes solved again (alpha' 0.99 and 0.1): the stored values within the change of
// the solver's azimuthal orders on 2026-12-05 (docs/accurate-solver.md, sec. 3; the half-spaces
// were solved with the earlier orders, which grew with k and rang): measured 1.2e-3 in ln rho
// above 1e-2 of rho(0.1) and 0.019 down to 1e-4 (at alpha' 0.64, a node, the stored profile is 8 %
// below a 2 x 10^7-photon Monte Carlo at 5.5-5.7 mm, 1e-4 of rho(0.1), the solver within 1.6 %;
// beyond 1e-4 the stored values differ from today's solve by up to 52 %: not compared).
TEST(SkinStackTable, HalfSpaceNodesAreTheFrequencyDomainProfiles) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const auto i_01 = static_cast<std::size_t>(std::lower_bound(t.x.begin(), t.x.end(), 0.1) - t.x.begin());
  for (const std::size_t i : skin::test::sanitized({16u, 48u})) {
    const std::vector<double> solved = t.solve_half_space(t.a_h[i]);
    int compared = 0;
    for (std::size_t m = 0; m < solved.size(); ++m) {
      const double rel = solved[m] - solved[i_01];
      if (rel < std::log(1e-4)) continue;
      EXPECT_NEAR(t.ln_rho_half[i * t.x.size() + m], solved[m], rel > std::log(1e-2) ? 3e-3 : 0.03) << "a = " << t.a_h[i] << " x = " << t.x[m];
      ++compared;
    }
    EXPECT_GT(compared, 20);
  }
}

// Between the nodes, on half-spaces of skin's medium (sigma_t' = 1 /mm, alpha' midway between
// nodes in sqrt a): within 1 % of FrequencyStack where R is above 1e-4 of its value at 0.02 mm
// (measured over alpha' 0.04-0.9993 and sigma_t' 1, 5, 20 /mm: up to 0.75 % at sigma_t' = 1;
// where that level lies beyond x = r sigma_t' = 6, at alpha' 0.3-0.85 and sigma_t' 20, up to 7 %,
// where FrequencyStack solved at another scale differs from itself by several per cent).
TEST(SkinStackTable, HalfSpaceProfilesMatchTheSolverBetweenNodes) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 60);
  for (const double alpha : {0.55, 0.9, 0.985}) {
    skin::physics::LayerStack s;
    s.layers = {Layer{1 - alpha, alpha, skin::physics::kInfinity, 1.4, 0.9}};
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << alpha;
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const std::vector<double> a = ps.profile(table), b = ps.profile(solved);
    double worst = 0;
    for (std::size_t i = 0; i < b.size(); ++i)
      if (b[i] > 1e-4 * b[0]) worst = std::max(worst, std::abs(a[i] / b[i] - 1));
    EXPECT_LT(worst, 0.01) << "alpha' = " << alpha;
  }
}

// The largest |a / b - 1| where b is above 1e-4 and above 1e-5 of b[0] (the profile at the
// first radius).
namespace {
std::pair<double, double> worst_relative(const std::vector<double>& a, const std::vector<double>& b) {
  double worst4 = 0, worst5 = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double e = std::abs(a[i] / b[i] - 1);
    if (b[i] > 1e-4 * b[0]) worst4 = std::max(worst4, e);
    if (b[i] > 1e-5 * b[0]) worst5 = std::max(worst5, e);
  }
  return {worst4, worst5};
}

// A preset with another g, index, dermis ratio and epidermis thickness, at one wavelength.
struct GeometryCase {
  const char* preset;
  double g, eta, ratio, thickness, lambda;
};
skin::physics::LayerStack geometry_stack(const GeometryCase& c) {
  skin::physics::SkinParameters p = skin::physics::find_preset(c.preset).parameters;
  p.g = c.g;
  p.eta = c.eta;
  p.dermis_scattering_scale = c.ratio;
  p.epidermis_thickness = c.thickness;
  return skin::physics::skin_layer_stack(p, c.lambda);
}
// Prints a case's worst deviations from the solver and expects them within 3 % above 1e-4 of
// R(0.02 mm) and 10 % above 1e-5.
void expect_near_the_solver(const GeometryCase& c, double worst4, double worst5) {
  std::cout << c.preset << " g " << c.g << " eta " << c.eta << " ratio " << c.ratio << ' ' << c.thickness << " mm at "
            << c.lambda << " nm: worst " << 100 * worst4 << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
  EXPECT_LT(worst4, 0.03) << c.preset << " at " << c.lambda << " nm";
  EXPECT_LT(worst5, 0.10) << c.preset << " at " << c.lambda << " nm";
}
// The worst relative deviations (above 1e-4 and 1e-5 of R(0.02 mm)) of the profile `t` reads for
// `s` from FrequencyStack's, at `radii`.
std::pair<double, double> read_against_the_solver(const SkinStackTable& t, const skin::physics::LayerStack& s,
                                                  const skin::transport::RadialGrid& radii) {
  const skin::transport::accurate::FrequencyStack solved(s);
  const skin::transport::accurate::SkinStackProfile read(t, s, solved.total());
  std::vector<double> table_R;
  for (double r : radii.r) table_R.push_back(read(r));
  skin::transport::ProfileSolver ps(radii);
  return worst_relative(table_R, ps.profile(solved));
}
using skin::test::reduced_stack;
// The index of the node of v nearest to x.
std::size_t nearest_index(const std::vector<double>& v, double x) {
  return static_cast<std::size_t>(std::min_element(v.begin(), v.end(), [x](double p, double q) { return std::abs(p - x) < std::abs(q - x); }) - v.begin());
}
}  // namespace

// Between the nodes, on skin: the accurate model's profile (the table) against FrequencyStack
// (sfd) solved for the same stack over 0.02-10 mm: within 1 % where R is above 1e-4 of its value
// at 0.02 mm, within 3 % above 1e-5 (measured over the presets the table covers at 400-700 nm
// every 50 nm: up to 1.9 % above 1e-4, in tanned skin at 450 nm at 1.1 mm, and 2.3 % above 1e-5;
// 0.6 % above 1e-5 in caucasian, pale and ear skin, 0.2 % at 650 nm; further out both are at
// FrequencyStack's inversion noise; asian skin at 590-650 nm, a_e 0.4-0.56, within 0.9 % and
// 0.8 %). The four stacks checked here: 0.5 % and 2.3 %.
TEST(SkinStackTable, PresetProfilesMatchTheSolverBetweenNodes) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  // (The first only under the sanitizers.)
  for (const auto& [name, lambda] : skin::test::sanitized<std::pair<const char*, double>>(
           {{"caucasian", 650.0}, {"pale", 450.0}, {"tanned", 400.0}, {"asian", 600.0}})) {
    const skin::physics::LayerStack s = preset_stack(name, lambda);
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << name;
    const skin::transport::accurate::FrequencyStack solved(s);
    EXPECT_NEAR(table.total(), solved.total(), 1e-12);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    EXPECT_LT(worst4, 0.01) << name << " at " << lambda << " nm";
    EXPECT_LT(worst5, 0.03) << name << " at " << lambda << " nm";
  }
}

// A thin epidermis, between the nodes the table gained on 2026-12-04 (tau 0.078-0.39, 2 x 1.5^k
// for k = -8..-4): the table against FrequencyStack solved for the same stack over 0.02-10 mm,
// held to the criterion of the presets above (1 % above 1e-4 of R(0.02 mm), 3 % above 1e-5).
// Caucasian skin with a 0.06 mm epidermis (tau 0.25-0.87) at 450 and 650 nm, african skin with
// a 0.1 mm one at 500 nm (its dark epidermis) and caucasian with 0.03 mm at 700 nm (tau ~0.13).
TEST(SkinStackTable, ThinEpidermisProfilesMatchTheSolverBetweenNodes) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  struct Case {
    const char* preset;
    double thickness, lambda;
  };
  for (const Case& c : skin::test::sanitized<Case>(
           {{"caucasian", 0.06, 650.0}, {"caucasian", 0.06, 450.0}, {"african", 0.1, 500.0}, {"caucasian", 0.03, 700.0}})) {
    skin::physics::SkinParameters p = skin::physics::find_preset(c.preset).parameters;
    p.epidermis_thickness = c.thickness;
    const skin::physics::LayerStack s = skin::physics::skin_layer_stack(p, c.lambda);
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.preset << ' ' << c.thickness << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    std::cout << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm: worst " << 100 * worst4
              << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
    EXPECT_LT(worst4, 0.01) << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm";
    EXPECT_LT(worst5, 0.03) << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm";
  }
}

// A thick epidermis, between the nodes the table gained on 2026-12-06 (tau 6.75, 10.1, 15.2 and
// 22.8, 2 x 1.5^k for k = 3-6), held to the same criterion (1 % above 1e-4 of R(0.02 mm), 3 % above
// 1e-5). Measured: caucasian skin with a 0.6 mm epidermis at 450 nm (tau 5.5) 0.25 % and 0.33 %,
// tanned with 0.9 mm at 420 nm (tau 9.9) 0.14 % and 0.21 %, caucasian with 1 mm at 450 nm (tau 9.2)
// 0.40 % and 0.82 %, with 1.5 mm (tau 13.8) and 2.2 mm (tau 20.3) 0.23 % and 0.31 % above 1e-4.
// (The first only under the sanitizers.)
TEST(SkinStackTable, ThickEpidermisProfilesMatchTheSolverBetweenNodes) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  struct Case {
    const char* preset;
    double thickness, lambda;
  };
  for (const Case& c : skin::test::sanitized<Case>({{"caucasian", 0.6, 450.0},
                                                    {"tanned", 0.9, 420.0},
                                                    {"caucasian", 1.0, 450.0},
                                                    {"caucasian", 1.5, 450.0},
                                                    {"caucasian", 2.2, 450.0}})) {
    skin::physics::SkinParameters p = skin::physics::find_preset(c.preset).parameters;
    p.epidermis_thickness = c.thickness;
    const skin::physics::LayerStack s = skin::physics::skin_layer_stack(p, c.lambda);
    const double tau = s.layers[0].sigma_s_prime * s.layers[0].thickness;
    EXPECT_GT(tau, 4.5) << c.preset << ' ' << c.thickness;  // beyond the nodes before 2026-12-06
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.preset << ' ' << c.thickness << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    std::cout << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm (tau " << tau << "): worst " << 100 * worst4
              << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
    EXPECT_LT(worst4, 0.01) << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm";
    EXPECT_LT(worst5, 0.03) << c.preset << ' ' << c.thickness << " mm at " << c.lambda << " nm";
  }
}

// Thicker than the offsets' last tau node (10.1; the table's reach 22.8 since 2026-12-06), where
// the offsets and cross terms hold their values at that node: as tau grows the top layer tends to
// a half-space and its offsets with it, and the light from below has crossed ten transport mean
// free paths of epidermis twice. Against the solver, held to expect_near_the_solver's 3 % above
// 1e-4 of R(0.02 mm) and 10 % above 1e-5. Measured 2026-12-06: bright caucasian skin (a_e 0.06)
// with g 0.8, index 1.45 and dermis ratio 1.2 under 1.5 mm (tau 13.8) 0.29 % and 0.42 %, with g
// 0.75, index 1.33 and ratio 2 under 2.2 mm (tau 20.3) 0.30 % and 0.62 %, asian with g 0.75, index
// 1.5 and ratio 0.3 under 1.2 mm at 450 nm 0.22 % and 1.2 %, tanned with g 0.85, index 1.5 and
// ratio 0.3 under 1.4 mm at 430 nm 0.12 % and 0.51 %; 24 random domain skins with tau 10.1-22.8
// at most 1.5 % above 1e-6 of R(1 um) (docs/accurate-solver.md, sec. 4). (Dark skin's 1e-5 of
// R(0.02 mm) lies where the solver itself is not converged: african with 1.2 mm at 420 nm,
// a_e 5.3, read 2.1 % and 10.7 % off.)
TEST(SkinStackOffsets, ThickerEpidermisThanTheOffsetsMatchesTheSolver) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  for (const GeometryCase& c : skin::test::sanitized<GeometryCase>({{"caucasian", 0.8, 1.45, 1.2, 1.5, 450.0},
                                                                    {"caucasian", 0.75, 1.33, 2.0, 2.2, 450.0},
                                                                    {"asian", 0.75, 1.5, 0.3, 1.2, 450.0},
                                                                    {"tanned", 0.85, 1.5, 0.3, 1.4, 430.0}})) {
    const skin::physics::LayerStack s = geometry_stack(c);
    const double tau = s.layers[0].sigma_s_prime * s.layers[0].thickness;
    EXPECT_GT(tau, 10.2) << c.preset;  // beyond the offsets' last tau node
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.preset << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    expect_near_the_solver(c, worst4, worst5);
  }
}

// The least absorbing skin, between the nodes the table gained below 0.004 on 2026-12-06 (a_e and
// a_d 0.00126 and 0.00225), held to the same criterion: the lightest tone presets' red light (their
// values of 2026-12-06, before the dermis' scattering was fitted: MST 1 and 5), and skin with no
// melanin or blood at the domain's largest scattering scale, 4 (a_e = a_d = 0.00155, near the
// domain's least, 0.0015). Measured 2026-12-06: worst 0.34 % above 1e-4 and 1e-5 (MST 5, 740 nm);
// 0.05 % and 0.26 % for the least absorbing. Before those nodes the table refused all three.
// (The first only under the sanitizers.)
TEST(SkinStackTable, LeastAbsorbingSkinProfilesMatchTheSolverBetweenNodes) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  struct Case {
    const char* preset;
    double melanin, hemoglobin, epidermis_thickness, oxygenation, scattering_scale, lambda;
  };
  for (const Case& c : skin::test::sanitized<Case>({{"MST 1", 0.0005, 0.002, 0.15, 0.8304, 2, 700.0},
                                                     {"MST 5", 0.03143, 0.002, 0.04, 0.6, 2, 740.0},
                                                     {"MST 1", 0.0, 0.0, 0.15, 0.8304, 4.0, 760.0}})) {
    skin::physics::SkinParameters p;
    p.melanin = c.melanin;
    p.melanin_blend = 0.3;
    p.hemoglobin = c.hemoglobin;
    p.epidermis_thickness = c.epidermis_thickness;
    p.oxygenation = c.oxygenation;
    p.scattering_scale = c.scattering_scale;
    const skin::physics::LayerStack s = skin::physics::skin_layer_stack(p, c.lambda);
    const double sp = s.layers[0].sigma_s_prime, ae = s.layers[0].sigma_a / sp, ad = s.layers[1].sigma_a / sp;
    EXPECT_LT(std::min(ae, ad), 0.004) << c.preset << ' ' << c.lambda;  // below the nodes before 2026-12-06
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.preset << ' ' << c.lambda << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    std::cout << c.preset << " at " << c.lambda << " nm (a_e " << ae << ", a_d " << ad << "): worst " << 100 * worst4
              << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
    EXPECT_LT(worst4, 0.01) << c.preset << ' ' << c.lambda;
    EXPECT_LT(worst5, 0.03) << c.preset << ' ' << c.lambda;
  }
}

// An epidermis darker than any preset's, between the a_e nodes the table gained on 2026-12-06
// (0.125 apart in sqrt a_e from 6.93, the last before, to 16.06): african skin with 1.5-2.8 times
// its melanin at 380-500 nm (a_e 7.0-13.2), at the paper's geometry (the table alone) and under
// another g, index and dermis ratio, whose offsets and cross terms end at a_e 6.93 and hold their
// values beyond it, read so up to a_e 12 (beyond, such skin is solved: checked here).
// Against FrequencyStack over 0.02-10 mm, where R is above 1e-4 of R(0.02 mm) and above 1e-6 of
// R(1 um): a dark epidermis' profile falls so fast that 1e-4 of R(0.02 mm) lies below 1e-7 of
// R(1 um), where the solver is not converged (checked below: against itself with half the node
// spacing and twice the top frequency, within 0.5 % above 1e-6 of R(1 um), 5 % at 1e-7, up to 6x
// below 1e-8). Measured 2026-12-06: at the paper's geometry 0.5-1.9 % up to a_e 9.5 (within 2.5 %
// here) and 3.0 % at 13.2 (within 4 %), under another geometry 0.7-3.4 % (within 4 %); inside the
// offsets' a_e (african, 0.1 mm, g 0.75, index 1.5, ratio 1.2 at 380 nm with 1.2 times its
// melanin, a_e 6.90) 0.9 %.
TEST(SkinStackTable, DarkerEpidermisThanThePresetsMatchesTheSolver) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.001, 10.0, 111);
  std::size_t i0 = 0;
  while (radii.r[i0] < 0.02 * (1 - 1e-9)) ++i0;
  // The worst |a / b - 1| at r >= 0.02 mm where b is above 1e-4 of b(0.02 mm) and 1e-6 of b(1 um).
  auto worst = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double w = 0;
    for (std::size_t i = i0; i < b.size(); ++i)
      if (b[i] > 1e-4 * b[i0] && b[i] > 1e-6 * b[0]) w = std::max(w, std::abs(a[i] / b[i] - 1));
    return w;
  };
  struct Case {
    double melanin_factor, g, eta, ratio, thickness, lambda, tolerance;
  };
  for (const Case& c : skin::test::sanitized<Case>({{1.5, 0.9, 1.4, 0.5, 0.25, 460.0, 0.025},
                                                    {1.5, 0.9, 1.4, 0.5, 0.05, 440.0, 0.025},
                                                    {2.2, 0.9, 1.4, 0.5, 0.25, 490.0, 0.025},
                                                    {2.0, 0.9, 1.4, 0.5, 0.1, 470.0, 0.025},
                                                    {2.8, 0.9, 1.4, 0.5, 0.25, 460.0, 0.04},
                                                    {2.6, 0.8, 1.4, 0.5, 0.1, 480.0, 0.04},
                                                    {1.8, 0.8, 1.33, 0.5, 0.25, 480.0, 0.04},
                                                    {2.2, 0.8, 1.4, 1.0, 0.1, 500.0, 0.04},
                                                    {1.6, 0.85, 1.45, 0.3, 0.15, 470.0, 0.04},
                                                    {1.5, 0.75, 1.5, 1.2, 0.1, 380.0, 0.04}})) {
    skin::physics::SkinParameters p = skin::physics::find_preset("african").parameters;
    p.melanin *= c.melanin_factor;
    p.g = c.g;
    p.eta = c.eta;
    p.dermis_scattering_scale = c.ratio;
    p.epidermis_thickness = c.thickness;
    const skin::physics::LayerStack s = skin::physics::skin_layer_stack(p, c.lambda);
    const double ae = s.layers[0].sigma_a / s.layers[0].sigma_s_prime;
    EXPECT_GT(ae, 6.93) << c.melanin_factor << ' ' << c.lambda;  // beyond the nodes before 2026-12-06
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.lambda << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    skin::transport::ProfileSolver ps(radii);
    const std::vector<double> b = ps.profile(solved);
    const double w = worst(ps.profile(table), b);
    std::cout << "african, melanin x " << c.melanin_factor << ", g " << c.g << " eta " << c.eta << " ratio " << c.ratio
              << ' ' << c.thickness << " mm at " << c.lambda << " nm (a_e " << ae << "): worst " << 100 * w << " %\n";
    EXPECT_LT(w, c.tolerance) << c.melanin_factor << ' ' << c.lambda;
    if (c.lambda == 380.0 && !skin::test::kUnderSanitizers) {
      // The window: the solver against itself, converged further.
      skin::transport::accurate::FrequencyProfileOptions finer;
      finer.du = 0.0625;
      finer.k_hi = 12;
      const double self = worst(b, ps.profile(skin::transport::accurate::FrequencyStack(s, finer)));
      std::cout << "  the solver against itself converged further: " << 100 * self << " %\n";
      EXPECT_LT(self, 0.01);
    }
  }
  // Darker than a_e 12 under another g: solved.
  skin::physics::SkinParameters p = skin::physics::find_preset("african").parameters;
  p.melanin *= 2.8;
  p.g = 0.8;
  const std::string why = SkinStackTable::builtin().gap(skin::physics::skin_layer_stack(p, 460.0));
  EXPECT_NE(why.find("above 12 with another g, index or dermis scattering ratio"), std::string::npos) << why;
}

// 2 pi int r R(r) dr over 1e-7-100 mm (log grid, 20000 points) is the adding-doubling R_d.
TEST(SkinStackTable, ProfileIntegratesToTheTotal) {
  skin::physics::LayerStack half_space;
  half_space.layers = {Layer{0.3, 4.0, skin::physics::kInfinity, 1.4, 0.9}};
  for (const auto& [name, s] : {std::pair{"pale", preset_stack("pale", 700)}, {"tanned", preset_stack("tanned", 400)},
                                {"half-space", half_space}}) {
    const skin::transport::accurate::AccurateStack a(s);
    ASSERT_TRUE(a.skin_table()) << name;
    const int n = 20000;
    const double l0 = std::log(1e-7), l1 = std::log(100.0), h = (l1 - l0) / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double r = std::exp(l0 + h * i);
      sum += (i == 0 || i == n ? 0.5 : 1.0) * 2 * std::numbers::pi * r * r * a.singular(r);
    }
    EXPECT_NEAR(sum * h / a.total(), 1.0, 2e-3) << name;
  }
}

TEST(SkinStackTable, CoversLightSkinAndNamesWhatItDoesNot) {
  const SkinStackTable& t = SkinStackTable::builtin();
  // Every preset, the paper's and the tone presets (whose red light in the lightest skin, a_e and
  // a_d down to 0.0015, was solved until the nodes below 0.004 of 2026-12-06).
  for (const auto& preset : skin::physics::presets())
    for (double lambda = 380; lambda <= 780; lambda += 10)
      EXPECT_EQ(t.gap(preset_stack(preset.name.c_str(), lambda)), "") << preset.name << ' ' << lambda;
  // An epidermis darker than the last node (16.06 sigma_s'): african skin with three times its
  // melanin.
  skin::physics::SkinParameters dark = skin::physics::find_preset("african").parameters;
  dark.melanin = 1.5;
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(dark, 400)).find("is outside the skin table's [0.001264911, 16.0"),
            std::string::npos)
      << t.gap(skin::physics::skin_layer_stack(dark, 400));
  // Another g, index or dermis ratio is read with the offsets inside their nodes' range.
  skin::physics::SkinParameters p;
  p.g = 0.5;
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(p, 550)).find("g 0.5 is outside the skin table's ["), std::string::npos)
      << t.gap(skin::physics::skin_layer_stack(p, 550));
  p = {};
  p.eta = 1.2;
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(p, 550)).find("index 1.2 is outside the skin table's ["), std::string::npos);
  for (const auto& [g, eta, ratio] : {std::tuple{0.8, 1.4, 0.5}, {0.9, 1.33, 0.5}, {0.9, 1.4, 1.0}, {0.75, 1.5, 0.5}}) {
    p = {};
    p.g = g;
    p.eta = eta;
    p.dermis_scattering_scale = ratio;
    EXPECT_EQ(t.gap(skin::physics::skin_layer_stack(p, 550)), "") << g << ' ' << eta << ' ' << ratio;
  }
  // A thin epidermis (0.03-0.1 mm: most of the body and face) is read, every preset, 380-780 nm,
  // and a thick one (0.6 mm, tau up to 8.7 since the nodes at 6.75 and 10.1; 1.5 mm, tau up to 22,
  // since the nodes at 15.2 and 22.8).
  for (const auto& preset : skin::physics::paper_presets())
    for (const double d : {0.03, 0.06, 0.1, 0.6, 1.5})
      for (double lambda = 380; lambda <= 780; lambda += 20) {
        skin::physics::SkinParameters thin = preset.parameters;
        thin.epidermis_thickness = d;
        EXPECT_EQ(t.gap(skin::physics::skin_layer_stack(thin, lambda)), "") << preset.name << ' ' << d << ' ' << lambda;
      }
  p = {};
  p.epidermis_thickness = 5.0;  // (tau ~33, beyond the last node, 22.8)
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(p, 550)).find("sigma_s' d ="), std::string::npos);
  // Another dermis ratio with another g or index: the built-in offsets combine them with their
  // cross terms (data/skin_stack_cross.csv), over a dermis no darker than a_d 0.5.
  ASSERT_NE(t.offsets->cross, nullptr);
  p = {};
  p.g = 0.8;
  p.dermis_scattering_scale = 1.0;
  EXPECT_EQ(t.gap(skin::physics::skin_layer_stack(p, 550)), "");
  p = {};
  p.dermis_scattering_scale = 3;
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(p, 550)).find("the lower layer's sigma_s' / the top layer's 3 is outside"),
            std::string::npos) << t.gap(skin::physics::skin_layer_stack(p, 550));
  skin::physics::LayerStack three = preset_stack("caucasian", 550);
  three.layers.push_back(three.layers.back());
  three.layers[1].thickness = 1.0;
  EXPECT_EQ(t.gap(three), "neither a half-space nor two layers");
  // Half-spaces: skin's index and g under air, alpha' 0.038-0.9999.
  skin::physics::LayerStack h;
  h.layers = {Layer{0.01, 1.0, skin::physics::kInfinity, 1.4, 0.9}};
  EXPECT_EQ(t.gap(h), "");
  h.layers[0].g = 0.8;
  EXPECT_EQ(t.gap(h), "g is not the skin table's 0.9");
  h.layers[0].g = 0.9;
  h.layers[0].thickness = 2.0;
  EXPECT_EQ(t.gap(h), "a slab, not a half-space");
  h.layers[0].thickness = skin::physics::kInfinity;
  h.layers[0].sigma_a = 30.0;
  EXPECT_NE(t.gap(h).find("is outside the skin table's half-space [1e-04, 25]"), std::string::npos) << t.gap(h);
  // Outside the table the accurate model solves the stack in the frequency domain.
  EXPECT_FALSE(skin::transport::accurate::AccurateStack(three).skin_table());
}

// Beyond the g axis' last node the offsets continue linearly in 1 - g through the last two nodes,
// 0.4 of their interval farther (0.95 and the base 0.9: to 0.97): the rule by arithmetic, on
// offsets of constant rows (the other nodes' values are not used), and no farther.
TEST(SkinStackOffsets, GBeyondItsLastNodeContinuesLinearlyInOneMinusG) {
  SkinStackOffsets o;
  o.base = {0.9, 1.4, 0.5};
  o.nodes = {std::vector<double>{0.8, 0.9, 0.95}, std::vector<double>{1.4}, std::vector<double>{0.5}};
  o.tau = {1, 2, 3, 4};
  o.a_e = o.a_d = {0.01, 0.1, 1, 10};
  o.x = {0.1, 1, 10, 100, 1000};
  const std::size_t n_top = 4 * 4 * 5, n_low = 4 * 4 * 4 * 5;
  o.d_top = {std::vector<std::vector<double>>{std::vector<double>(n_top, 0.25), {}, std::vector<double>(n_top, 0.1)}, {{}}, {{}}};
  o.d_low = {std::vector<std::vector<double>>{std::vector<double>(n_low, -0.5), {}, std::vector<double>(n_low, 0.2)}, {{}}, {{}}};
  SkinStackTable on_x;  // (only its x: the same as the offsets')
  on_x.x = o.x;
  auto read = [&](double g) {
    std::vector<double> top(5, 0.0), low(5, 0.0);
    o.add(2.5, 0.3, 0.3, g, 1.4, 0.5, on_x, top, low, false);
    return std::pair{top, low};
  };
  for (const auto& [g, f] : {std::pair{0.95, 1.0}, std::pair{0.96, 1.2}, std::pair{0.97, 1.4}}) {
    EXPECT_EQ(o.gap(g, 1.4, 0.5), "") << g;
    const auto [top, low] = read(g);
    for (std::size_t i = 0; i < 5; ++i) {
      EXPECT_NEAR(top[i], 0.1 * f, 1e-12) << "g " << g << ", x " << o.x[i];
      EXPECT_NEAR(low[i], 0.2 * f, 1e-12) << "g " << g << ", x " << o.x[i];
    }
  }
  EXPECT_EQ(o.gap(0.971, 1.4, 0.5), "g 0.971 is outside the skin table's [0.8, 0.97]");
}

// An axis' offsets may reach farther than its cross terms' corners (g 0.97 offsets, corners only
// at g 0.7). On the side without corners the terms are the other side's continued through the
// base (SkinStackCross::add), as far as that corner is from the base: g 0.9667 (ln(1 - g) mirrored
// through ln 0.1). A combined read beyond it is refused with that reason, while the same g alone,
// or another dermis ratio inside the reach, is read.
TEST(SkinStackOffsets, CombinedReadsStopWhereTheCrossTermsReach) {
  using skin::transport::accurate::SkinStackCross;
  SkinStackOffsets o;
  o.base = {0.9, 1.4, 0.5};
  o.nodes = {std::vector<double>{0.7, 0.8, 0.9, 0.95, 0.97}, {1.33, 1.4, 1.55}, {0.2, 0.5, 2.0}};
  EXPECT_NE(o.gap(0.8, 1.4, 2.0).find("without cross terms"), std::string::npos) << o.gap(0.8, 1.4, 2.0);
  SkinStackCross c;
  c.base = o.base;
  c.ends = {std::array<double, 2>{0.7, 0.9}, {1.33, 1.55}, {0.2, 2.0}};
  o.cross = &c;
  EXPECT_NEAR(c.reach(0, 1), 1 - 0.01 / 0.3, 1e-12);
  EXPECT_EQ(c.reach(0, 0), 0.7);
  EXPECT_EQ(c.reach(1, 1), 1.55);
  EXPECT_NEAR(c.position(0, 0, 0.95), std::log(0.5) / std::log(3.0), 1e-12);  // -0.63: through the base
  EXPECT_EQ(o.gap(0.97, 1.4, 0.5), "");  // g alone: the offsets
  EXPECT_EQ(o.gap(0.8, 1.4, 2.0), "");
  EXPECT_EQ(o.gap(0.95, 1.4, 2.0), "");  // continued through the base
  EXPECT_EQ(o.gap(0.45, 1.4, 0.5), "g 0.45 is outside the skin table's [0.7, 0.978]");
  // The index has no continuation beyond its nodes: its reach is the corners' mirrored.
  c.ends[1] = {1.4, 1.47};
  EXPECT_EQ(o.gap(0.9, 1.5, 2.0), "index 1.5 together with another dermis scattering ratio is outside the skin "
                                  "table's cross terms' reach [1.33, 1.47]");
  c.ends[1] = {1.33, 1.55};
  // g beyond its last node (0.97, continued to 0.978: g_reach) with another ratio: the cross
  // terms' position continues as far.
  EXPECT_EQ(o.gap(0.975, 1.4, 2.0), "");
  EXPECT_NE(o.gap(0.98, 1.4, 0.5).find("g 0.98 is outside the skin table's [0.7, 0.978]"), std::string::npos)
      << o.gap(0.98, 1.4, 0.5);
  c.ends[1] = {1.4, 1.55};  // the index: corners above only, mirrored to 1.25 below
  EXPECT_EQ(o.gap(0.9, 1.33, 2.0), "");
  c.ends[0] = {0.9, 0.9};  // no corners on either side: nothing to continue
  EXPECT_NE(o.gap(0.8, 1.4, 2.0).find("reach [0.9, 0.9]"), std::string::npos) << o.gap(0.8, 1.4, 2.0);
}

// Parsing `text` throws one line containing `what` (and naming `file`, if `names_file`).
template <typename Parsed>
void expect_refused(const std::string& text, const std::string& file, const std::string& what, bool names_file) {
  try {
    Parsed::parse(text, file);
    ADD_FAILURE() << "accepted; expected: " << what;
  } catch (const skin::util::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    if (names_file) {
      EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
    }
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(SkinStackTable, MalformedTablesAreRefused) {
  SkinStackTable t = SkinStackTable::default_nodes();
  t.tau = {1, 2, 3, 4};
  t.a_e = t.a_d = {0.01, 0.1, 1, 10};
  t.x = {0.1, 1, 10, 100, 1000};
  t.ln_rho.assign(4 * 4 * 4 * 5, -1.0);
  t.ln_rho_top.assign(4 * 4 * 5, -2.0);
  t.a_h = {0.01, 0.1, 1, 10};
  t.ln_rho_half.assign(4 * 5, -3.0);
  const std::string good = t.to_csv();
  EXPECT_NO_THROW(SkinStackTable::parse(good, "t.csv"));
  auto refused = [](const std::string& text, const std::string& what) { expect_refused<SkinStackTable>(text, "t.csv", what, false); };
  refused(good.substr(0, good.size() - 200), "t.csv");  // truncated
  std::string bad = good;
  bad.replace(bad.find("\n1,0.01,0.01,"), 13, "\n1,0.02,0.01,");
  refused(bad, "is not node");
  bad = good;
  bad.replace(bad.find("\n1,0.01,inf,"), 12, "\n1,0.01,0.5,");  // the top layer's row
  refused(bad, "is not node (tau, a_e, a_d) = (1, 0.01, inf)");
  bad = good;
  bad.replace(bad.rfind("\n"), 1, "\n4,10,inf,-1,-1,-1,-1,-1\n");  // a row too many
  refused(bad, "rows (tau x a_e x (the top layer alone and each a_d), then a_h)");
  bad = good;
  bad.replace(bad.find("\ninf,0.1,inf,"), 13, "\ninf,0.2,inf,");  // a half-space row
  refused(bad, "is not node (tau, a_e, a_d) = (inf, 0.1, inf)");
  // Without half-space nodes the table is read, and half-spaces are not covered.
  bad = good;
  bad.erase(bad.find("# a_h:"), bad.find('\n', bad.find("# a_h:")) + 1 - bad.find("# a_h:"));
  bad.erase(bad.find("\ninf,0.01,inf,"));
  bad += '\n';
  const SkinStackTable no_half = SkinStackTable::parse(bad, "t.csv");
  skin::physics::LayerStack h;
  h.layers = {Layer{0.1, 1.0, skin::physics::kInfinity, 1.4, 0.9}};
  EXPECT_EQ(no_half.gap(h), "the skin table has no half-space nodes");
  bad = good;
  bad.replace(bad.rfind("-1.0000"), 7, "nan");
  refused(bad, "is 'nan', not a number");  // (parse_csv)
  bad = good;
  bad.replace(bad.rfind("-1.0000"), 7, "inf");
  refused(bad, "= inf is not a finite number");
  bad = good;
  bad.replace(bad.find("# x: 0.1,1,10,100,1000"), 22, "# x: 0.1,1,10,100,2000");
  refused(bad, "evenly spaced");
  // ln rho far from any profile's (the fuzzer's -20000.1, fuzz/regressions/fuzz_skin_stack_table:
  // 4-point weights turned it into exp(+1200)), and a row spanning more than the table's floor.
  bad = good;
  bad.replace(bad.rfind("-1.0000"), 7, "-20000.1");
  refused(bad, "-20000.1 is not a finite number within 100 of 0");
  bad = good;
  bad.replace(bad.rfind("-1.0000"), 7, "-40.0000");
  refused(bad, "spans 39 in ln rho; allowed: at most 29.94");
  bad = good;
  bad.replace(bad.find("# a_e: 0.01,0.1,1,10"), 20, "# a_e: 0.01,0.1,1,1e10");
  refused(bad, "'a_e' must lie within [1e-9, 1e9] and increase");
}

// What parses gives a finite, non-negative profile by construction: nodes nearly together make
// the 4-point weights between the far nodes ~1e5, and rows alternating between ln rho -60 and
// +30 (each row flat, so within the floor) then interpolate to exp(+1e6): without the clamp of
// skin_stack_table.cpp this test fails at 72 radii.
TEST(SkinStackTable, ProfilesOfAnyParsedTableAreFiniteAndNonNegative) {
  SkinStackTable t = SkinStackTable::default_nodes();
  t.tau = {1, 1.000001, 1.000002, 4};
  t.a_e = t.a_d = {0.01, 0.01000001, 1, 10};
  t.x = {0.1, 1, 10, 100, 1000};
  t.ln_rho.resize(4 * 4 * 4 * 5);
  for (std::size_t i = 0; i < t.ln_rho.size(); ++i) t.ln_rho[i] = (i / 5) % 2 ? 30.0 : -60.0;
  t.ln_rho_top.resize(4 * 4 * 5);
  for (std::size_t i = 0; i < t.ln_rho_top.size(); ++i) t.ln_rho_top[i] = (i / 5) % 2 ? -60.0 : 30.0;
  t.a_h = {0.01, 0.01000001, 1, 10};
  t.ln_rho_half = t.ln_rho_top;
  const SkinStackTable table = SkinStackTable::parse(t.to_csv(), "t.csv");
  const double s = 5.0;
  skin::physics::LayerStack two, half;
  two.layers = {Layer{0.3 * s, s, 2.5 / s, table.eta, table.g},
                Layer{0.3 * s, table.dermis_ratio * s, skin::physics::kInfinity, table.eta, table.g}};
  half.layers = {Layer{0.3 * s, s, skin::physics::kInfinity, table.eta, table.g}};
  for (const auto* st : {&two, &half}) {
    ASSERT_EQ(table.gap(*st), "");
    const skin::transport::accurate::SkinStackProfile profile(table, *st, 0.5);
    for (double r = 0; r < 100; r = r == 0 ? 1e-6 : r * 1.3) {
      const double v = profile(r);
      EXPECT_TRUE(std::isfinite(v) && v >= 0) << "r " << r << ": " << v;
    }
  }
}

}  // namespace

// The offsets for another g, index or dermis ratio (SkinStackOffsets) refuse malformed files in
// one line naming the file, and a file written by to_csv() reads back.
TEST(SkinStackOffsets, MalformedFilesAreRefused) {
  using skin::transport::accurate::SkinStackOffsets;
  SkinStackOffsets o;
  o.nodes = {std::vector<double>{0.8, 0.9}, std::vector<double>{1.4}, std::vector<double>{0.5}};
  o.tau = {1, 2, 3, 4};
  o.a_e = o.a_d = {0.01, 0.1, 1, 10};
  o.x = {0.1, 1, 10, 100, 1000};
  o.d_top = {std::vector<std::vector<double>>{std::vector<double>(4 * 4 * 5, 0.25), {}}, {{}}, {{}}};
  o.d_low = {std::vector<std::vector<double>>{std::vector<double>(4 * 4 * 4 * 5, -0.5), {}}, {{}}, {{}}};
  const std::string good = o.to_csv();
  const SkinStackOffsets back = SkinStackOffsets::parse(good, "o.csv");
  EXPECT_EQ(back.d_top[0][0], o.d_top[0][0]);
  EXPECT_EQ(back.d_low[0][0], o.d_low[0][0]);
  EXPECT_EQ(back.gap(0.85, 1.4, 0.5), "");
  EXPECT_EQ(back.gap(0.95, 1.4, 0.5), "g 0.95 is outside the skin table's [0.8, 0.94]");  // (continued 0.4 of 0.1)
  EXPECT_EQ(back.gap(0.85, 1.45, 0.5), "index 1.45 is outside the skin table's [1.4, 1.4]");
  auto refused = [](const std::string& text, const std::string& what) {
    expect_refused<SkinStackOffsets>(text, "o.csv", what, true);
  };
  refused(good.substr(0, good.size() - 200), "o.csv");  // truncated
  std::string bad = good;
  bad.replace(bad.find("# g_nodes: 0.8,0.9"), 18, "# g_nodes: 0.8,0.85");
  refused(bad, "'g_nodes' needs the table's 0.9 among them");
  bad = good;
  bad.replace(bad.find("\n0,0.8,1,0.01,0.01,"), 19, "\n0,0.8,1,0.01,0.02,");
  refused(bad, "is not node (axis, value, tau, a_e, a_d) = (0, 0.8, 1, 0.01, 0.01)");
  bad = good;
  bad.replace(bad.rfind("-0.500"), 6, "-25.000");
  refused(bad, "= -25 is not a finite number within 20 of 0");
  bad = good;
  bad.replace(bad.rfind("-0.500"), 6, "nan");
  refused(bad, "is 'nan', not a number");
  bad = good + "0,0.8,4,10,10,0,0,0,0,0\n";
  refused(bad, "1 row(s) after its last node");
  bad = good;
  bad.replace(bad.find("# eta_nodes: 1.4"), 16, "# eta_nodes: 1.4,9");
  refused(bad, "'eta_nodes' must lie within [1, 3] and increase");
  // Which nodes' light from below was solved on its own: written and read back; a value that is
  // not one of the axis' other nodes is refused.
  EXPECT_EQ(good.find("# g_low_solved"), std::string::npos);
  EXPECT_EQ(back.low_solved[0], (std::vector<char>{0, 0}));
  SkinStackOffsets solved = o;
  solved.low_solved = {std::vector<char>{1, 0}, std::vector<char>{0}, std::vector<char>{0}};
  const std::string with_solved = solved.to_csv();
  EXPECT_NE(with_solved.find("\n# g_low_solved: 0.8\n"), std::string::npos);
  EXPECT_EQ(SkinStackOffsets::parse(with_solved, "o.csv").low_solved[0], (std::vector<char>{1, 0}));
  bad = with_solved;
  bad.replace(bad.find("# g_low_solved: 0.8"), 19, "# g_low_solved: 0.9");
  refused(bad, "'g_low_solved' names 0.9, which is not one of the 'g_nodes' other than the table's 0.9");
  bad = with_solved;
  bad.replace(bad.find("# g_low_solved: 0.8"), 19, "# g_low_solved: 0.7");
  refused(bad, "'g_low_solved' names 0.7");
  // An axis' own, finer a_e nodes: its rows are on them, written and read back (the other axes'
  // on the coarse ones); they must hold the coarse ones and increase.
  SkinStackOffsets own = o;
  own.axis_a_e[0] = {0.01, 0.1, 0.4, 1, 10};
  own.d_top[0][0].assign(4 * 5 * 5, 0.125);
  own.d_low[0][0].assign(4 * 5 * 4 * 5, -0.25);
  own.d_low[0][0][own.low_row(0, 3, 3, 3) * 5 + 4] = 1.5;  // (tau 4, a_e 10, a_d 10, the last x)
  const std::string with_own = own.to_csv();
  EXPECT_NE(with_own.find("\n# g_a_e: 0.01,0.1,0.4,1,10\n"), std::string::npos);
  EXPECT_NE(with_own.find("\n0,0.8,1,0.4,0.01,"), std::string::npos);
  const SkinStackOffsets own_back = SkinStackOffsets::parse(with_own, "o.csv");
  EXPECT_EQ(own_back.a_e_of(0), own.axis_a_e[0]);
  EXPECT_EQ(own_back.a_e_of(1), o.a_e);
  EXPECT_EQ(own_back.d_low[0][0], own.d_low[0][0]);
  EXPECT_EQ(own_back.low_row(0, 3, 3, 3), ((3u * 5 + 4) * 4 + 3));
  EXPECT_EQ(own_back.top_row(0, 1, 2), 1u * 5 + 3);
  bad = with_own;
  bad.replace(bad.find("# g_a_e: 0.01,0.1,0.4,1,10"), 26, "# g_a_e: 0.01,0.1,0.4,2,10");
  refused(bad, "'g_a_e' must hold every node of 'a_e' (1 is missing)");
  bad = with_own;
  bad.replace(bad.find("# g_a_e: 0.01,0.1,0.4,1,10"), 26, "# g_a_e: 0.01,0.4,0.1,1,10");
  refused(bad, "'g_a_e' must lie within [1e-9, 1e9] and increase");
  bad = with_own;
  bad.replace(bad.find("\n0,0.8,1,0.4,0.01,"), 19, "\n0,0.8,1,0.5,0.01,");
  refused(bad, "is not node (axis, value, tau, a_e, a_d) = (0, 0.8, 1, 0.4, 0.01)");
}

// The cross terms of two axes (SkinStackCross) refuse malformed files in one line naming the
// file, a file written by to_csv() reads back, and a term is added only where both of its axes
// are off the table's, scaled by their positions towards the corner's ends.
// SkinStackCross::settle: a node's terms keep their value beyond the x where the light from
// below (the table's or the corner's) falls under 1e-8 of the node's peak, which comes at smaller
// x in a dark stack than in a bright one, and are 0 where it never is above; where it is they are
// untouched. Terms that are not on the offsets' nodes are refused.
TEST(SkinStackCross, SettleHoldsTermsNearTheFloorAndNeedsTheOffsetsNodes) {
  using skin::transport::accurate::SkinStackCross;
  const SkinStackTable& t = SkinStackTable::builtin();
  const SkinStackOffsets& o = *t.offsets;
  SkinStackCross c = SkinStackCross::default_nodes(o);
  const std::size_t n_t = c.tau.size(), n_e = c.a_e.size(), n_d = c.a_d.size(), n_x = c.x.size();
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      c.c_top[p][k].assign(p == 0 ? n_t * n_e * n_x : 0, 0.0);
      c.c_low[p][k].assign(n_t * n_e * n_d * n_x, 0.0);
    }
  // (index, ratio) at (1.55, 2): a ramp in x at every node.
  std::vector<double>& low = c.c_low[2][3];
  for (std::size_t i = 0; i < low.size(); ++i) low[i] = 0.001 * static_cast<double>(i % n_x);
  c.settle(t, o);
  // A node's row: the ramp on one run of x, held at its ends outside it (near the beam too, where
  // the solved light from below is not resolved); the run's last x is returned.
  auto last_kept = [&](std::size_t i_t, std::size_t i_e, std::size_t i_d) {
    const double* row = low.data() + ((i_t * n_e + i_e) * n_d + i_d) * n_x;
    std::size_t f = 0;
    while (f < n_x && row[f] != 0.001 * static_cast<double>(f)) ++f;
    if (f == n_x) return f;
    std::size_t l = f;
    while (l + 1 < n_x && row[l + 1] == 0.001 * static_cast<double>(l + 1)) ++l;
    for (std::size_t i = 0; i < n_x; ++i)
      if (i < f || i > l) {
        EXPECT_EQ(row[i], row[i < f ? f : l]) << "node " << i_t << ',' << i_e << ',' << i_d << " x index " << i;
      }
    return l;
  };
  const std::size_t bright = last_kept(0, 0, 0), darker = last_kept(n_t / 2, n_e / 2, n_d / 2);
  EXPECT_LT(darker, bright);
  EXPECT_LT(bright, n_x - 1);  // even a bright stack's far tail falls under 1e-8 of its peak
  // The darkest node's light from below is under 1e-8 of its peak everywhere: no term.
  const double* darkest = low.data() + (((n_t - 1) * n_e + n_e - 1) * n_d + n_d - 1) * n_x;
  for (std::size_t i = 0; i < n_x; ++i) EXPECT_EQ(darkest[i], 0.0);
  SkinStackCross other = SkinStackCross::default_nodes(o);
  other.a_d.pop_back();
  EXPECT_THROW(other.settle(t, o), std::logic_error);
}

TEST(SkinStackCross, MalformedFilesAreRefusedAndTermsScaleFromTheBase) {
  using skin::transport::accurate::SkinStackCross;
  SkinStackCross c;
  c.ends = {{{0.7, 0.95}, {1.33, 1.55}, {0.2, 2.0}}};
  c.tau = {1, 2, 3, 4};
  c.a_e = c.a_d = {0.01, 0.1, 1, 10};
  c.x = {0.1, 1, 10, 100, 1000};
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      c.c_top[p][k].assign(p == 0 ? 4 * 4 * 5 : 0, 0.0);
      c.c_low[p][k].assign(4 * 4 * 4 * 5, 0.0);
    }
  c.c_top[0][3].assign(4 * 4 * 5, 0.25);   // g high, eta high
  c.c_low[1][0].assign(4 * 4 * 4 * 5, -0.5);  // g low, ratio low
  const std::string good = c.to_csv();
  const SkinStackCross back = SkinStackCross::parse(good, "c.csv");
  EXPECT_EQ(back.to_csv(), good);
  EXPECT_EQ(back.c_top[0][3], c.c_top[0][3]);
  EXPECT_EQ(back.c_low[1][0], c.c_low[1][0]);
  auto added = [&](double g, double eta, double ratio) {
    std::vector<double> dt(5, 0.0), dl(5, 0.0);
    back.add(2.5, 0.5, 0.5, {g, eta, ratio}, dt, dl);
    return std::pair{dt[2], dl[2]};
  };
  EXPECT_EQ(added(0.95, 1.4, 0.5), std::pair(0.0, 0.0));  // one axis off: no pair term
  EXPECT_EQ(added(0.95, 1.55, 0.5).second, 0.0);
  EXPECT_NEAR(added(0.95, 1.55, 0.5).first, 0.25, 1e-12);  // the corner itself
  // Halfway in ln(1 - g) and in eta: a quarter of it.
  EXPECT_NEAR(added(1 - std::sqrt(0.1 * 0.05), 1.475, 0.5).first, 0.25 / 4, 1e-12);
  EXPECT_NEAR(added(0.9, 1.55, 2.0).second, 0.0, 1e-12);  // eta x ratio: zero terms
  EXPECT_NEAR(added(1 - std::sqrt(0.1 * 0.3), 1.4, std::sqrt(0.2 * 0.5)).second, -0.5 / 4, 1e-12);
  // Offsets with cross terms combine another dermis ratio with another g or index; without, not.
  SkinStackOffsets o = *SkinStackTable::builtin().offsets;
  o.cross = nullptr;
  EXPECT_NE(o.gap(0.8, 1.45, 1.0).find("do not combine them"), std::string::npos);
  o.cross = &back;
  EXPECT_EQ(o.gap(0.8, 1.45, 1.0), "");
  auto refused = [](const std::string& text, const std::string& what) {
    expect_refused<SkinStackCross>(text, "c.csv", what, true);
  };
  refused(good.substr(0, good.size() - 200), "c.csv");  // truncated
  std::string bad = good;
  bad.replace(bad.find("# g_ends: 0.7,0.95"), 18, "# g_ends: 0.91,0.95");
  refused(bad, "'g_ends' must be two different values within [0, 0.99], one at or below and one at or above the table's 0.9");
  bad = good;
  bad.replace(bad.find("\n0,0.7,1.33,1,0.01,inf,"), 23, "\n0,0.7,1.33,1,0.01,0.01,");
  refused(bad, "is not node (pair, value_a, value_b, tau, a_e, a_d) = (0, 0.7, 1.33, 1, 0.01, inf)");
  bad = good;
  bad.replace(bad.rfind("0.000"), 5, "-25.000");
  refused(bad, "= -25 is not a finite number within 20 of 0");
  bad = good;
  bad.replace(bad.rfind("0.000"), 5, "nan");
  refused(bad, "is 'nan', not a number");
  bad = good + "2,1.55,2,4,10,10,0,0,0,0,0\n";
  refused(bad, "1 row(s) after its last node");
  bad = good;
  bad.replace(bad.find("# tau: 1,2,3,4"), 14, "# tau: 1,2,3");
  refused(bad, "'tau' needs at least 4 nodes");
}

// `skin tabulate-skin-profiles --cross --cross-pairs`: only the pairs asked for are solved, the
// others' corners 0, and a table to reuse gives every corner it holds, asked for or not. At a
// corner's node the table with both axes' offsets plus the term is the corner's light from below
// solved there (one node: g 0.7 with dermis ratio 0.2 and 2; about 2 s in Release).
TEST(SkinStackCross, OnlyThePairsAskedForAreSolvedAtTheOffsetsNodes) {
  using skin::transport::accurate::SkinStackCross;
  const SkinStackTable& t = SkinStackTable::builtin();
  const SkinStackOffsets& o = *t.offsets;
  const SkinStackCross d = SkinStackCross::default_nodes(o);
  EXPECT_EQ(d.tau, o.tau);  // the offsets' own nodes
  EXPECT_EQ(d.a_e, o.a_e);
  EXPECT_EQ(d.a_d, o.a_d);
  SkinStackCross c = d;
  c.tau = {o.tau[7]};  // 1.33
  c.a_e = {o.a_e[4]};  // 0.4
  c.a_d = {o.a_d[4]};  // 0.4
  c.ends[0] = {o.nodes[0].front(), o.base[0]};  // g's lower end only (0.7)
  const std::array<bool, SkinStackCross::kPairs> g_and_ratio{false, true, false};
  c.compute(t, {}, nullptr, &g_and_ratio);
  const std::size_t n_x = c.x.size();
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      const bool solved = p == 1 && k < 2;  // g at its lower end (0.7; its upper end here is the table's 0.9)
      ASSERT_EQ(c.c_low[p][k].size(), n_x);
      const double largest = std::abs(*std::max_element(c.c_low[p][k].begin(), c.c_low[p][k].end(),
                                                        [](double a, double b) { return std::abs(a) < std::abs(b); }));
      if (solved) {
        EXPECT_GT(largest, 1e-4) << "pair " << p << " corner " << k;
      } else {
        EXPECT_EQ(largest, 0.0) << "pair " << p << " corner " << k;
      }
    }
  // The corner (g 0.7, dermis ratio 2): offsets plus term = the light from below solved there.
  SkinStackTable corner;
  corner.g = 0.7;
  corner.dermis_ratio = 2.0;
  corner.x = t.x;
  const std::vector<double> solved = corner.solve_low(c.tau[0], c.a_e[0], c.a_d[0]);
  std::vector<double> top, low;
  t.ln_parts_at(c.tau[0], c.a_e[0], c.a_d[0], top, low);
  o.add(c.tau[0], c.a_e[0], c.a_d[0], 0.7, o.base[1], 2.0, t, top, low, false);
  const std::size_t stride = (t.x.size() - 1) / (n_x - 1);
  for (std::size_t m = 0; m < n_x; ++m) {
    if (c.x[m] >= 0.1 && c.x[m] <= 3) {
      EXPECT_NEAR(low[stride * m] + c.c_low[1][1][m], solved[stride * m], 1e-9) << "x = " << c.x[m];
    }
  }
  // Nothing asked for: every corner copied from the table to reuse.
  SkinStackCross again = c;
  for (auto& pair : again.c_low)
    for (auto& corner_terms : pair) corner_terms.clear();
  const std::array<bool, SkinStackCross::kPairs> none{false, false, false};
  again.compute(t, {}, &c, &none);
  EXPECT_EQ(again.c_low, c.c_low);
  // The pair asked for again with the same table to reuse: copied, not solved (nor set to 0).
  SkinStackCross copied = again;
  for (auto& pair : copied.c_low)
    for (auto& corner_terms : pair) corner_terms.clear();
  copied.compute(t, {}, &c, &g_and_ratio);
  EXPECT_EQ(copied.c_low, c.c_low);
  // The offsets extended by a tau node: the pair asked for gets that node's rows solved, every
  // corner's other rows are copied bit for bit, and a pair not asked for keeps 0 at the new node.
  SkinStackCross longer = c;
  longer.tau = {c.tau[0], o.tau[8]};  // 1.33, 2
  longer.compute(t, {}, &c, &g_and_ratio);
  const std::size_t rows = c.a_e.size() * c.a_d.size() * n_x;
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(longer.c_low[p][k].size(), 2 * rows);
      EXPECT_TRUE(std::equal(c.c_low[p][k].begin(), c.c_low[p][k].end(), longer.c_low[p][k].begin())) << "pair " << p << " corner " << k;
      const bool asked = p == 1 && k < 2;
      const double largest = std::abs(*std::max_element(longer.c_low[p][k].begin() + static_cast<std::ptrdiff_t>(rows), longer.c_low[p][k].end(),
                                                        [](double a, double b) { return std::abs(a) < std::abs(b); }));
      if (asked) {
        EXPECT_GT(largest, 1e-4) << "pair " << p << " corner " << k;
      } else {
        EXPECT_EQ(largest, 0.0) << "pair " << p << " corner " << k;
      }
    }
  // The offsets extended by an a_d node likewise: the old rows copied, the new a_d's solved (with
  // its top layer's R(k)) for the pair asked for, 0 for the others.
  SkinStackCross wider = c;
  wider.a_d = {c.a_d[0], o.a_d[5]};  // 0.4, 1.28
  wider.compute(t, {}, &c, &g_and_ratio);
  const std::size_t n_x_c = c.x.size();
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(wider.c_low[p][k].size(), 2 * n_x_c);
      EXPECT_TRUE(std::equal(c.c_low[p][k].begin(), c.c_low[p][k].end(), wider.c_low[p][k].begin())) << "pair " << p << " corner " << k;
      const double largest = std::abs(*std::max_element(wider.c_low[p][k].begin() + static_cast<std::ptrdiff_t>(n_x_c), wider.c_low[p][k].end(),
                                                        [](double a, double b) { return std::abs(a) < std::abs(b); }));
      if (p == 1 && k < 2) {
        EXPECT_GT(largest, 1e-4) << "a_d 1.28, pair " << p << " corner " << k;
      } else {
        EXPECT_EQ(largest, 0.0) << "a_d 1.28, pair " << p << " corner " << k;
      }
    }
  const std::vector<double> solved_2 = corner.solve_low(o.tau[8], c.a_e[0], c.a_d[0]);
  t.ln_parts_at(o.tau[8], c.a_e[0], c.a_d[0], top, low);
  o.add(o.tau[8], c.a_e[0], c.a_d[0], 0.7, o.base[1], 2.0, t, top, low, false);
  for (std::size_t m = 0; m < n_x; ++m) {
    if (c.x[m] >= 0.1 && c.x[m] <= 3) {
      EXPECT_NEAR(low[stride * m] + longer.c_low[1][1][rows + m], solved_2[stride * m], 1e-9) << "tau 2, x = " << c.x[m];
    }
  }
}

// Skin of another g, index or dermis ratio is read from the table with the offsets of each axis
// added (docs/accurate-solver.md, sec. 4): against FrequencyStack solved for the same stack over
// 0.02-10 mm, worst deviation where R is above 1e-4 of R(0.02 mm) (and above 1e-5), at nodes of
// an axis and between them, in light, dark and thin skin.
TEST(SkinStackOffsets, ProfilesOfAnotherGeometryMatchTheSolver) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  for (const GeometryCase& c : skin::test::sanitized<GeometryCase>({{"caucasian", 0.8, 1.4, 0.5, 0.25, 550.0},
                                                     {"african", 0.8, 1.4, 0.5, 0.25, 500.0},
                                                     {"caucasian", 0.9, 1.33, 0.5, 0.25, 650.0},
                                                     {"caucasian", 0.9, 1.4, 1.0, 0.25, 450.0},
                                                     {"asian", 0.8, 1.33, 0.5, 0.1, 600.0},
                                                     {"tanned", 0.9, 1.4, 1.8, 0.1, 500.0},
                                                     {"caucasian", 0.75, 1.5, 0.5, 0.15, 650.0},
                                                     {"caucasian", 0.8, 1.4, 0.5, 0.06, 450.0}})) {
    const skin::physics::LayerStack s = geometry_stack(c);
    const skin::transport::accurate::AccurateStack table(s);
    ASSERT_TRUE(table.skin_table()) << c.preset << ": " << SkinStackTable::builtin().gap(s);
    const skin::transport::accurate::FrequencyStack solved(s);
    EXPECT_NEAR(table.total(), solved.total(), 1e-12);
    skin::transport::ProfileSolver ps(radii);
    const auto [worst4, worst5] = worst_relative(ps.profile(table), ps.profile(solved));
    expect_near_the_solver(c, worst4, worst5);
  }
}

// A stack the built-in table reads (its gap empty), against the solver over 0.02-10 mm: within 3 %
// above 1e-4 of R(0.02 mm) and 10 % above 1e-5.
namespace {
void expect_read_within_3_and_10_percent(const skin::physics::LayerStack& st) {
  const SkinStackTable& t = SkinStackTable::builtin();
  ASSERT_EQ(t.gap(st), "");
  const auto [worst4, worst5] = read_against_the_solver(t, st, skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80));
  std::cout << "worst " << 100 * worst4 << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
  EXPECT_LT(worst4, 0.03);
  EXPECT_LT(worst5, 0.10);
}
}  // namespace

// The dermis ratio's offsets in the far field of an epidermis between the coarse a_e nodes 0.4 and
// 1.28, where the offset's fall with x changes several-fold (docs/accurate-solver.md, sec. 4): a
// 0.031 mm epidermis (tau 1.36, a_e 0.66, a_d 0.37, ratio 2, g 0.9, index 1.4), read across those
// nodes +20 % off the solver at 0.15 mm (3e-5 of R(0.02 mm)) and +10 to +51 % off a 4e6-photon
// Monte Carlo at 0.135-0.165 mm; with the ratio's own a_e and a_d nodes (twice as fine above 0.4) within
// the tolerances above.
TEST(SkinStackOffsets, DermisRatioFarFieldBetweenTheCoarseEpidermisNodes) {
  const double s = 43.83;
  skin::physics::LayerStack st;
  st.layers = {Layer{0.659 * s, s, 1.357 / s, 1.4, 0.9}, Layer{0.374 * s, 2 * s, skin::physics::kInfinity, 1.4, 0.9}};
  expect_read_within_3_and_10_percent(st);
}

// A thin dark epidermis' far field, where the solved light from below ends in its inversion's
// noise (~1e-9 of the whole profile's peak; docs/accurate-solver.md, sec. 4): a 0.023 mm epidermis
// (tau 0.29, a_e 0.97, a_d 0.53, ratio 0.24, g 0.9, index 1.4; s 12.6 / mm), read with each light
// from below as stored, was 53-98 % low at 0.61-0.71 mm (~7e-6 of R(0.02 mm); 7.3 times what a
// 4e6-photon Monte Carlo allows there); continued beyond the noise, within 3 % of the solver above
// 1e-4 and 10 % above 1e-5 (the Monte Carlo allows at least 11 % there: SE 2-3 %).
TEST(SkinStackTable, ThinDarkEpidermisFarFieldBeyondTheInversionsNoise) {
  skin::physics::LayerStack st;
  st.layers = {Layer{12.280, 12.60, 0.022905, 1.4, 0.9}, Layer{6.655, 2.9988, skin::physics::kInfinity, 1.4, 0.9}};
  expect_read_within_3_and_10_percent(st);
}

// Another dermis ratio together with another g or index, read with the three axes' offsets and
// their cross terms (docs/accurate-solver.md, sec. 4), against FrequencyStack as above. The
// cases: a thin epidermis with index 1.52 and dermis ratio 2, a bright far field at index 1.55
// with ratio 0.2 (4.3 % off without the terms held from x = 20 on), the same index with ratio
// 1.8, a dark thin epidermis with ratio 2 (61 % off without the light from below held near the
// beam), one inside every range, and domain draw 23 (g 0.835, index 1.35, ratio 1.34
// at 451 nm; 6.3 % off without the terms held where the corners' solves near their floor).
TEST(SkinStackCross, CombinedAxesMatchTheSolver) {
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  const SkinStackTable& t = SkinStackTable::builtin();
  for (const GeometryCase& c : skin::test::sanitized<GeometryCase>({{"pale", 0.9, 1.52, 2.0, 0.02, 560.0},
                                                     {"caucasian", 0.78, 1.55, 0.2, 0.16, 740.0},
                                                     {"caucasian", 0.9, 1.55, 1.8, 0.09, 560.0},
                                                     {"african", 0.74, 1.54, 2.0, 0.03, 590.0},
                                                     {"asian", 0.8, 1.45, 1.0, 0.1, 500.0}})) {
    const skin::physics::LayerStack s = geometry_stack(c);
    ASSERT_EQ(t.gap(s), "") << c.preset;
    const auto [worst4, worst5] = read_against_the_solver(t, s, radii);
    expect_near_the_solver(c, worst4, worst5);
  }
  // Stacks given in reduced units (the epidermis' sigma_s' s per mm, tau, a_e, a_d, g, index,
  // dermis ratio), held within 5 % above 1e-4 of R(0.02 mm) and 10 % above 1e-5 (Release only, as
  // the other cases after the first):
  // - domain draw 23 (skin validate --domain 60 --domain-seed 2026): where its light from below is
  //   ~5e-8 of the peak (x 5.4) the corners' solves are near their floor; the terms held there
  //   (SkinStackCross::settle) read it 1.2 % off (4.4 % when written, on 2026-12-05), 6.3 % not
  //   held then (+10.7 % off a 2e6-photon Monte Carlo where 9.7 % is allowed);
  // - two epidermises thin in tau (0.17-0.19) but 0.11-0.16 mm thick, g 0.71-0.78, ratio 2, whose
  //   split of the light into the two parts rings out to ~0.3 tau of the beam: with the light
  //   from below held within 0.3 tau 3.8 and 3.2 % off, within 0.1 tau 7.8 and 9.9 % (+8.6 % off
  //   a 4e6-photon Monte Carlo at 0.02-0.03 mm where 7.7 % is allowed);
  // - g 0.93 with ratio 0.2 (index 1.41 at 489 nm; a 0.029 mm epidermis, tau 0.45): with the g
  //   0.7 corners continued through the base (the built-in terms until 2026-12-07) 1.6 % off;
  //   with the g 0.95 corners 1.3 % above 1e-4 and 3.6 % above 1e-5. Under a 0.022 mm epidermis
  //   (tau 0.34) it read 3.2 % off (6.7 % with the terms 0 there) and is solved since 2026-12-06
  //   (GAboveTheTableWithALowRatioUnderAThinTopIsSolved);
  // - g 0.95 (index 1.33, ratio 1.26, a 0.039 mm epidermis at 684 nm): 1.1 % off with the g 0.7
  //   corners continued, 0.5 % at the g 0.95 corners (2026-12-07).
  struct Reduced { const char* name; double s, tau, a_e, a_d, g, eta, ratio; };
  if (!skin::test::kUnderSanitizers)
    for (const Reduced& c : {Reduced{"domain draw 23", 15.79, 0.60978693833287512, 0.71012474244275126, 0.20319374564149284,
                                     0.83457687184592844, 1.3464124506824522, 1.339432969897965},
                             Reduced{"thin tau, g 0.71", 1.623260533068936, 0.18649128105881427, 0.50813489321540051,
                                     0.015655585784173236, 0.70949835769857272, 1.3346007498368042, 2.0},
                             Reduced{"thin tau, g 0.78", 1.1140679156229485, 0.17378883187117938, 2.185556971650783,
                                     0.039953638447684389, 0.77668013681113501, 1.5074715173874316, 2.0},
                             Reduced{"g 0.93, ratio 0.2", 15.661101930231045, 0.45, 2.517611414489668,
                                     0.13516107102624089, 0.93151078473295024, 1.4128582552044109, 0.2},
                             Reduced{"g 0.95", 18.035923647352607, 0.71081484488842495, 0.57744911794103171,
                                     0.010563287185106643, 0.95, 1.332037565529445, 1.2574724896392766}}) {
      skin::physics::LayerStack st;
      st.layers = {{c.a_e * c.s, c.s, c.tau / c.s, c.eta, c.g}, {c.a_d * c.s, c.ratio * c.s, skin::physics::kInfinity, c.eta, c.g}};
      ASSERT_EQ(t.gap(st), "") << c.name;
      const auto [worst4, worst5] = read_against_the_solver(t, st, radii);
      std::cout << c.name << ": worst " << 100 * worst4 << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
      EXPECT_LT(worst4, 0.05) << c.name;
      EXPECT_LT(worst5, 0.10) << c.name;
    }
  // Over a dark dermis (african at 420 nm: a_d 1.14) under a thin epidermis (0.03 mm: tau 0.33)
  // such skin is refused: the cross terms miss its far field. With one axis off it is read, and
  // so it is under a thicker epidermis (tau 0.35 or more; the preset's 0.25 mm: tau 2.7).
  skin::physics::SkinParameters p = skin::physics::find_preset("african").parameters;
  p.g = 0.8;
  p.dermis_scattering_scale = 1.0;
  p.epidermis_thickness = 0.03;
  EXPECT_NE(t.gap(skin::physics::skin_layer_stack(p, 420)).find("the skin table's cross terms miss its far field"), std::string::npos)
      << t.gap(skin::physics::skin_layer_stack(p, 420));
  p.g = 0.9;
  EXPECT_EQ(t.gap(skin::physics::skin_layer_stack(p, 420)), "");
  p.g = 0.8;
  p.epidermis_thickness = 0.25;
  EXPECT_EQ(t.gap(skin::physics::skin_layer_stack(p, 420)), "");
  // There the combined read is as close to the solver as the offsets' alone over the same skin
  // with the table's dermis ratio (measured 2026-12-06 over 60 random such skins: both median 0.9 %
  // above 1e-4 and 1.7 % above 1e-5, the same 3 beyond 5 % above 1e-4, all with g above 0.95).
  // Here a bright epidermis (a_e 0.14) over a dermis twice as scattering with a_d 0.9 (random
  // skin 39 of those, 568 nm), where the ratio matters.
  if (!skin::test::kUnderSanitizers) {
    const double s = 6.23, tau = 2.488, a_e = 0.138, a_d = 0.903, g = 0.82, eta = 1.501;
    auto stack = [&](double ratio) {
      skin::physics::LayerStack st;
      st.layers = {{a_e * s, s, tau / s, eta, g}, {a_d * s, ratio * s, skin::physics::kInfinity, eta, g}};
      return st;
    };
    ASSERT_EQ(t.gap(stack(2.0)), "");
    ASSERT_EQ(t.gap(stack(0.5)), "");
    const auto [c4, c5] = read_against_the_solver(t, stack(2.0), radii);
    const auto [a4, a5] = read_against_the_solver(t, stack(0.5), radii);
    std::cout << "dark dermis, tau 2.5, g 0.82, index 1.50: ratio 2 (combined) worst " << 100 * c4 << " % above 1e-4, "
              << 100 * c5 << " % above 1e-5; ratio 0.5 (offsets alone) " << 100 * a4 << " %, " << 100 * a5 << " %\n";
    EXPECT_LT(c4, 0.05);
    EXPECT_LT(c5, 0.10);
    EXPECT_LT(c4, a4 + 0.02);
    EXPECT_LT(c5, a5 + 0.02);
  }
}

// Another dermis ratio with g above 0.91 under a thin top layer with a low ratio is solved: the
// read missed a Monte Carlo there even with the g 0.95 corners (tau 0.12, g 0.97, ratio 0.24: -20 %
// at 1.5 mm, 1.44 times what 5 % + 3 SE allow; SkinStackTable::gap). Under thicker top layers,
// and with the ratio 0.35 or more, g up to 0.97 is read since the g 0.95 corners (2026-12-07):
// the skin at g 0.97 and ratio 0.2 under tau 0.8 within 5 % of the solver above 1e-4 of R(0.02
// mm). A table whose cross terms have no corners above g 0.9 (the built-in one before) still
// solves g above 0.955 with any other ratio: continued from below, those terms missed such skin.
TEST(SkinStackCross, GAboveTheTableWithALowRatioUnderAThinTopIsSolved) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const auto stack = reduced_stack;
  ASSERT_GT(t.offsets->cross->ends[0][1], t.offsets->cross->base[0]);  // corners above g 0.9
  const std::string why = t.gap(stack(5.96, 0.1192, 1.8132, 0.495, 0.97, 1.5315, 0.2437));
  EXPECT_NE(why.find("g = 0.97 above 0.91"), std::string::npos) << why;
  EXPECT_NE(why.find("below 0.35"), std::string::npos) << why;
  EXPECT_NE(why.find("below 0.45"), std::string::npos) << why;
  EXPECT_NE(t.gap(stack(20.1, 0.4022, 0.3288, 0.0844, 0.97, 1.3958, 0.2308)), "");  // tau 0.40: solved
  EXPECT_NE(t.gap(stack(1.2, 0.2, 3.188, 0.029, 0.93, 1.55, 0.24)).find("below 0.35"), std::string::npos);
  EXPECT_EQ(t.gap(stack(1.2, 0.2, 3.188, 0.029, 0.93, 1.55, 0.5)), "");   // the table's ratio: offsets alone
  EXPECT_EQ(t.gap(stack(1.2, 0.2, 3.188, 0.029, 0.93, 1.55, 0.8)), "");   // ratio 0.35 or more
  EXPECT_EQ(t.gap(stack(1.2, 0.2, 2.5, 0.029, 0.97, 1.55, 1.44)), "");  // at g 0.97 (a_e to 2.8: HighGUnderADarkTopIsSolved)
  EXPECT_EQ(t.gap(stack(1.2, 0.2, 3.188, 0.029, 0.91, 1.55, 0.24)), "");  // up to g 0.91
  // Another g with another ratio under the thinnest epidermis (tau below 0.117) is solved at any g
  // (ThinnestEpidermis in accurate_mc_test); at the table's g, or ratio, it is read.
  EXPECT_NE(t.gap(stack(1.2, 0.096, 3.188, 0.029, 0.91, 1.55, 0.24)).find("ring near the beam"), std::string::npos);
  EXPECT_NE(t.gap(stack(1.2, 0.096, 3.188, 0.029, 0.8, 1.55, 1.44)).find("ring near the beam"), std::string::npos);
  EXPECT_EQ(t.gap(stack(1.2, 0.096, 3.188, 0.029, 0.8, 1.55, 0.5)), "");
  EXPECT_EQ(t.gap(stack(5.0, 0.796, 1.215, 0.084, 0.97, 1.55, 0.2)), "");  // tau 0.45 or more
  // Without corners above the table's g.
  SkinStackTable bare = t;
  SkinStackOffsets bare_offsets = *t.offsets;
  skin::transport::accurate::SkinStackCross bare_cross = *t.offsets->cross;
  bare_cross.ends[0][1] = bare_cross.base[0];
  bare_offsets.cross = &bare_cross;
  bare.offsets = &bare_offsets;
  const std::string bare_why = bare.gap(stack(5.0, 0.796, 1.215, 0.084, 0.97, 1.55, 0.2));
  EXPECT_NE(bare_why.find("no cross terms for g above 0.9"), std::string::npos) << bare_why;
  EXPECT_EQ(bare.gap(stack(5.0, 0.796, 1.215, 0.084, 0.95, 1.55, 0.2)), "");
  EXPECT_EQ(bare.gap(stack(5.0, 0.796, 1.215, 0.084, 0.97, 1.55, 0.5)), "");
  if (skin::test::kUnderSanitizers) return;
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  for (const auto& [name, st] : {std::pair{"g 0.9, ratio 0.24, tau 0.096", stack(1.2, 0.096, 3.188, 0.029, 0.9, 1.55, 0.24)},
                                 std::pair{"g 0.97, ratio 0.2, tau 0.8", stack(5.0, 0.796, 1.215, 0.084, 0.97, 1.55, 0.2)}}) {
    ASSERT_EQ(t.gap(st), "") << name;
    const auto [worst4, worst5] = read_against_the_solver(t, st, radii);
    std::cout << name << ": worst " << 100 * worst4 << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
    EXPECT_LT(worst4, 0.05) << name;
  }
}

// g above 0.94 under a top layer darker than a_e 2.8 is solved: there the g offsets miss the
// solver by 5-12 % above 1e-4 of R(0.02 mm) from tau 1 (at g 0.95 and 0.97, a_e 3.1-6; the g 0.95
// node itself 7.4 % at tau 2, a_e 4.55), and two such reads at g 0.97 missed 2 x 10^6 photons by
// 1.05 and 1.14 times what 5 % + 3 SE allow (SkinStackTable::gap). With a_e 2.66, or at g 0.93,
// they are read (at most 4.1 % and 3.5 % off on the same grid).
TEST(SkinStackOffsets, HighGUnderADarkTopIsSolved) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const auto stack = reduced_stack;
  const std::string why = t.gap(stack(11.72, 1.8854, 3.473, 4.077, 0.97, 1.5385, 0.2076));  // the domain draw
  EXPECT_NE(why.find("g = 0.97 above 0.94"), std::string::npos) << why;
  EXPECT_NE(why.find("above 2.8"), std::string::npos) << why;
  EXPECT_NE(t.gap(stack(12, 2, 4.55, 1, 0.95, 1.4, 0.5)), "");  // the table's ratio and index too
  EXPECT_NE(t.gap(stack(12, 0.6, 3.1, 1, 0.95, 1.4, 0.5)), "");
  EXPECT_EQ(t.gap(stack(12, 2, 2.66, 1, 0.97, 1.4, 0.5)), "");
  EXPECT_EQ(t.gap(stack(12, 2, 4.55, 1, 0.93, 1.4, 0.5)), "");
  EXPECT_EQ(t.gap(stack(12, 2, 4.55, 1, 0.9, 1.4, 0.5)), "");  // the table's own g
  if (skin::test::kUnderSanitizers) return;
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  // (what the rule keeps from the table: the read there against the solver)
  const auto [worst4, worst5] = read_against_the_solver(t, stack(11.72, 2, 4.547367, 2.664911, 0.95, 1.4, 0.5), radii);
  std::cout << "g 0.95, a_e 4.55, tau 2 (a node): worst " << 100 * worst4 << " % above 1e-4, " << 100 * worst5 << " % above 1e-5\n";
  EXPECT_GT(worst4, 0.05);
}

// The far field of a dermis less scattering than the table's (ratio 0.23; s 20.1 /mm, tau 0.40,
// a_e 0.33, a_d 0.084 between the ratio offsets' a_d nodes 0.04 and 0.126: a skin at 476 nm) falls
// more slowly than the table's rows, which reach the solver's floor (~1e-9 of their peak) at x = r
// s ~ 20, where this skin is still 3e-5 of R(0.02 mm). There the ratio's offsets take it from
// their node solves, and another g's offsets hold (SkinStackOffsets::add). Against the solver at
// 80 radii over 0.02-10 mm: at the table's g 4.8 % above 1e-5 of R(0.02 mm) and 6.7 % above 1e-6
// (out to 1.5 mm; 43 % before, the read 0.6 of the solver's at 1.5 mm); at the corners' g 0.95
// 4.2 % and 7.6 % (77 % before).
TEST(SkinStackOffsets, ALessScatteringDermisFarFieldFollowsTheSolver) {
  if (skin::test::kUnderSanitizers) GTEST_SKIP() << "two solves of ~2-5 s in Release";
  const SkinStackTable& t = SkinStackTable::builtin();
  const skin::transport::RadialGrid radii = skin::transport::RadialGrid::logarithmic(0.02, 10.0, 80);
  skin::transport::ProfileSolver ps(radii);
  for (double g : {0.9, 0.95}) {
    const skin::physics::LayerStack st = reduced_stack(20.1, 0.4022, 0.3288, 0.0844, g, 1.3958, 0.2308);
    const skin::transport::accurate::FrequencyStack solved(st);
    const skin::transport::accurate::SkinStackProfile read(t, st, solved.total());
    const std::vector<double> b = ps.profile(solved);
    double worst5 = 0, worst6 = 0, farthest = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
      const double e = std::abs(read(radii.r[i]) / b[i] - 1);
      if (b[i] > 1e-5 * b[0]) worst5 = std::max(worst5, e);
      if (b[i] > 1e-6 * b[0]) {
        worst6 = std::max(worst6, e);
        farthest = radii.r[i];
      }
    }
    std::cout << "g " << g << ": worst " << 100 * worst5 << " % above 1e-5 of R(0.02 mm), " << 100 * worst6
              << " % above 1e-6 (out to " << farthest << " mm)\n";
    EXPECT_GT(farthest, 1.4) << g;
    EXPECT_LT(worst5, 0.06) << g;
    EXPECT_LT(worst6, 0.10) << g;
  }
}

// Corners neither solved nor held (pairs left out of --cross-pairs), on a side where the reused
// terms had none: the reused file's other side is continued to the new end, so that those pairs
// read as they did, with the term linear in the position both ways. Here terms without corners
// above g 0.9 (the built-in file before 2026-12-07) are given new g ends at the offsets' last g
// node, nothing solved: the g x index and g x dermis ratio corners there are the g 0.7 ones times
// the position of that end below the base, and a read anywhere between is unchanged.
TEST(SkinStackCross, CornersNotSolvedAreContinuedFromTheOtherSide) {
  const SkinStackTable& t = SkinStackTable::builtin();
  using skin::transport::accurate::SkinStackCross;
  SkinStackCross reuse = *t.offsets->cross;
  reuse.ends[0][1] = reuse.base[0];  // no corners above the table's g
  for (std::size_t p = 0; p < 2; ++p)
    for (std::size_t k = 2; k < 4; ++k) {
      std::fill(reuse.c_top[p][k].begin(), reuse.c_top[p][k].end(), 0.0);
      std::fill(reuse.c_low[p][k].begin(), reuse.c_low[p][k].end(), 0.0);
    }
  SkinStackCross c = SkinStackCross::default_nodes(*t.offsets);
  ASSERT_GT(c.ends[0][1], c.base[0]);
  const std::array<bool, SkinStackCross::kPairs> none{false, false, false};
  c.compute(t, {}, &reuse, &none);
  EXPECT_NE(c.provenance.find("continued from the other side of g"), std::string::npos) << c.provenance;
  const double f = c.position(0, 0, c.ends[0][1]);
  EXPECT_LT(f, -0.5);
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      const bool continued = p < 2 && k >= 2;
      const std::size_t from = continued ? k - 2 : k;
      ASSERT_EQ(c.c_low[p][k].size(), reuse.c_low[p][from].size());
      for (std::size_t i = 0; i < c.c_low[p][k].size(); ++i)
        ASSERT_DOUBLE_EQ(c.c_low[p][k][i], (continued ? f : 1.0) * reuse.c_low[p][from][i]) << p << ' ' << k;
      for (std::size_t i = 0; i < c.c_top[p][k].size(); ++i)
        ASSERT_DOUBLE_EQ(c.c_top[p][k][i], (continued ? f : 1.0) * reuse.c_top[p][from][i]) << p << ' ' << k;
    }
  for (const std::array<double, 3>& v : {std::array<double, 3>{0.93, 1.5, 1.0}, {0.95, 1.35, 0.3}, {0.96, 1.4, 2.0}}) {
    std::vector<double> dt0(c.x.size(), 0.0), dl0 = dt0, dt1 = dt0, dl1 = dt0;
    reuse.add(0.5, 0.3, 0.05, v, dt0, dl0);
    c.add(0.5, 0.3, 0.05, v, dt1, dl1);
    for (std::size_t m = 0; m < c.x.size(); ++m) {
      EXPECT_NEAR(dt1[m], dt0[m], 1e-12) << v[0];
      EXPECT_NEAR(dl1[m], dl0[m], 1e-12) << v[0];
    }
  }
}

// Rebased cross terms: terms computed against other offsets become those of the given ones by
// each corner's change of the two axes' offsets, row by row. With the g 0.7 node's light from
// below raised by 0.1 and its top layer's by 0.05 in the offsets they were computed against, the
// terms of the corners at g 0.7 rise by as much (pair g x index: both parts; g x dermis ratio: the
// light from below), and the other terms stay.
TEST(SkinStackCross, RebasedTermsFollowTheOffsetsChangeAtTheirCorners) {
  const SkinStackTable& t = SkinStackTable::builtin();
  const SkinStackOffsets& to = *t.offsets;
  SkinStackOffsets from = to;
  const std::size_t j = nearest_index(from.nodes[0], 0.7);
  ASSERT_EQ(from.nodes[0][j], 0.7);
  for (double& v : from.d_low[0][j]) v += 0.1;
  for (double& v : from.d_top[0][j]) v += 0.05;
  SkinStackCross c = *to.cross;
  c.rebase(from, to);
  std::size_t shifted = 0;
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k) {
      const bool at_g07 = SkinStackCross::kPairAxes[p][0] == 0 && c.ends[0][k / 2] == 0.7;
      for (const auto& [after, before, by] : {std::tuple{&c.c_low[p][k], &to.cross->c_low[p][k], 0.1},
                                              {&c.c_top[p][k], &to.cross->c_top[p][k], 0.05}}) {
        ASSERT_EQ(after->size(), before->size());
        for (std::size_t i = 0; i < after->size(); ++i)
          ASSERT_NEAR((*after)[i] - (*before)[i], at_g07 ? by : 0.0, 1e-12) << "pair " << p << " corner " << k;
        if (at_g07) shifted += after->size();
      }
    }
  EXPECT_GT(shifted, 0u);
  // A change that would carry a term beyond 20 in ln rho stops there, as terms are computed and
  // parsed (the file it writes is read back).
  for (double& v : from.d_low[0][j]) v += 30;
  SkinStackCross far = *to.cross;
  far.rebase(from, to);
  double most = 0;
  for (std::size_t p = 0; p < SkinStackCross::kPairs; ++p)
    for (std::size_t k = 0; k < 4; ++k)
      for (double v : far.c_low[p][k]) most = std::max(most, std::abs(v));
  EXPECT_EQ(most, 20.0);
  EXPECT_NO_THROW(SkinStackCross::parse(far.to_csv(), "rebased.csv"));
  SkinStackOffsets other = to;
  other.tau.pop_back();
  EXPECT_THROW(c.rebase(other, to), std::logic_error);
}

// The stored dermis-ratio offsets are their nodes solved again (SkinStackOffsets::compute on one
// (tau, a_e, a_d) node over the table as stored, against the file as stored: builtin() settles
// both, continuing far fields beyond their noise): to the file's 3 decimals of ln rho. A
// dark epidermis over a dermis of ratio 1.4 (tau 2, a_e 1.28, a_d 0.04: its far field is the
// light from below, whose offsets a threshold of 1e-9 of the peak used to hold from 0.6 mm of
// asian skin at 450 nm on) and a bright one at ratio 0.2 (the first only under the sanitizers).
TEST(SkinStackOffsets, StoredDermisRatioNodesAreSolvedAgain) {
  const SkinStackTable t = SkinStackTable::parse(skin::util::data::embedded("skin_stack_profiles.csv"), "profiles");
  const SkinStackOffsets b = SkinStackOffsets::parse(skin::util::data::embedded("skin_stack_offsets.csv"), "offsets");
  const auto nearest = nearest_index;
  struct Case { double ratio, tau, a_e, a_d; };
  for (const Case& c : skin::test::sanitized<Case>({{1.4, 2.0, 1.28, 0.04}, {0.2, 0.6, 0.02, 0.1}})) {
    SkinStackOffsets o;
    o.base = b.base;
    o.nodes = {std::vector<double>{b.base[0]}, std::vector<double>{b.base[1]}, std::vector<double>{b.base[2], c.ratio}};
    if (c.ratio < b.base[2]) std::swap(o.nodes[2][0], o.nodes[2][1]);
    const std::size_t i = nearest(b.tau, c.tau), j = nearest(b.a_e, c.a_e), l = nearest(b.a_d, c.a_d);
    o.tau = {b.tau[i]};
    o.a_e = {b.a_e[j]};
    o.a_d = {b.a_d[l]};
    o.x = b.x;
    o.compute(t);
    const std::size_t node = c.ratio < b.base[2] ? 0 : 1, stored_node = nearest(b.nodes[2], c.ratio);
    ASSERT_NEAR(b.nodes[2][stored_node], c.ratio, 1e-12);
    const std::vector<double>& fresh = o.d_low[2][node];
    const std::vector<double>& stored = b.d_low[2][stored_node];
    const std::size_t first = b.low_row(2, i, j, l) * b.x.size();
    ASSERT_EQ(fresh.size(), b.x.size());
    for (std::size_t m = 0; m < b.x.size(); ++m)
      EXPECT_NEAR(stored[first + m], fresh[m], 1.5e-3) << "ratio " << c.ratio << " node " << i << ',' << j << ',' << l << " x = " << b.x[m];
  }
}

// SkinStackOffsets::compute with `reuse` copies the rows the reused offsets hold and solves only
// the others: the dermis ratio's own, finer a_e nodes over offsets on the coarse ones solve one top
// layer and one light from below (the new a_e), keep the held row bit for bit, and the new row is
// the built-in offsets' stored one (to the file's 3 decimals; a_e 0.779, one of the nodes the
// ratio's far field needs, sec. 4 of docs/accurate-solver.md), all over the table and offsets as
// stored (builtin() settles them). The table or an axis extended (new tau or a_e nodes) solves only
// the new rows. (Under the sanitizers the first two computes only.)
TEST(SkinStackOffsets, ReusedRowsAreCopiedAndOnlyTheOthersSolved) {
  const SkinStackTable t = SkinStackTable::parse(skin::util::data::embedded("skin_stack_profiles.csv"), "profiles");
  const SkinStackOffsets b = SkinStackOffsets::parse(skin::util::data::embedded("skin_stack_offsets.csv"), "offsets");
  auto at = [](const std::vector<double>& v, double x) {
    const std::size_t i = nearest_index(v, x);
    EXPECT_NEAR(v[i], x, 1e-3 * x);
    return i;
  };
  SkinStackOffsets coarse;
  coarse.base = b.base;
  coarse.nodes = {std::vector<double>{b.base[0]}, std::vector<double>{b.base[1]}, std::vector<double>{b.base[2], 2.0}};
  coarse.tau = {b.tau[at(b.tau, 1.333)]};
  coarse.a_e = {b.a_e[at(b.a_e, 0.4)]};
  coarse.a_d = {b.a_d[at(b.a_d, 0.1265)]};
  coarse.x = b.x;
  coarse.compute(t);
  SkinStackOffsets fine = coarse;
  const std::vector<double>& ratio_e = b.a_e_of(2);
  fine.axis_a_e[2] = {coarse.a_e[0], t.a_e[at(t.a_e, 0.779)]};
  std::size_t total = 0;
  fine.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &coarse);
  EXPECT_EQ(total, 2u);  // one top layer's R(k), one light from below
  const std::size_t n_x = b.x.size();
  ASSERT_EQ(fine.d_low[2][1].size(), 2 * n_x);
  EXPECT_TRUE(std::equal(coarse.d_low[2][1].begin(), coarse.d_low[2][1].end(), fine.d_low[2][1].begin()));
  EXPECT_EQ(fine.low_solved[2][1], 1);
  const std::size_t j = at(b.nodes[2], 2.0);
  const std::size_t first = (((at(b.tau, 1.333) * ratio_e.size()) + at(ratio_e, 0.779)) * b.a_d_of(2).size() + at(b.a_d_of(2), 0.1265)) * n_x;
  for (std::size_t m = 0; m < n_x; ++m) EXPECT_NEAR(b.d_low[2][j][first + m], fine.d_low[2][1][n_x + m], 1.5e-3) << "x = " << b.x[m];
  // Offsets holding every row solved the present way are copied whole; a node whose light from
  // below they hold as the difference of two profiles (low_solved 0) is solved again, the same.
  SkinStackOffsets again = coarse;
  total = 0;
  again.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &coarse);
  EXPECT_EQ(total, 0u);
  if (skin::test::kUnderSanitizers) return;  // (the rest solves again what is solved above)
  SkinStackOffsets as_difference = coarse;
  as_difference.low_solved[2][1] = 0;
  again.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &as_difference);
  EXPECT_EQ(total, 2u);
  EXPECT_EQ(again.low_solved[2][1], 1);
  EXPECT_TRUE(std::equal(coarse.d_low[2][1].begin(), coarse.d_low[2][1].end(), again.d_low[2][1].begin()));
  // The table extended by a tau node: only the new node's rows are solved (one top layer, one
  // light from below), the others copied bit for bit, and a node held as the difference of two
  // profiles keeps that label (its old rows are not solved again).
  SkinStackOffsets longer = coarse;
  longer.tau = {coarse.tau[0], b.tau[at(b.tau, 2.0)]};
  total = 0;
  longer.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &as_difference);
  EXPECT_EQ(total, 2u);
  EXPECT_EQ(longer.low_solved[2][1], 0);
  ASSERT_EQ(longer.d_low[2][1].size(), 2 * n_x);
  EXPECT_TRUE(std::equal(coarse.d_low[2][1].begin(), coarse.d_low[2][1].end(), longer.d_low[2][1].begin()));
  const std::size_t at_2 = (((at(b.tau, 2.0) * ratio_e.size()) + at(ratio_e, 0.4)) * b.a_d_of(2).size() + at(b.a_d_of(2), 0.1265)) * n_x;
  for (std::size_t m = 0; m < n_x; ++m) EXPECT_NEAR(b.d_low[2][j][at_2 + m], longer.d_low[2][1][n_x + m], 1.5e-3) << "tau 2, x = " << b.x[m];
  // An axis gaining an a_e node likewise: its rows solved (as `fine` solved them), the node held as
  // a difference keeps that label and its old rows.
  SkinStackOffsets wider = as_difference;
  wider.axis_a_e[2] = fine.axis_a_e[2];
  total = 0;
  wider.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &as_difference);
  EXPECT_EQ(total, 2u);
  EXPECT_EQ(wider.low_solved[2][1], 0);
  EXPECT_EQ(wider.d_low[2][1], fine.d_low[2][1]);
  // A g node gaining an a_d node: its top layer is solved again for the new light from below, and
  // the top layer's row it holds is kept as held (here a made-up row), not written over.
  SkinStackOffsets g_coarse = coarse;
  g_coarse.nodes[0] = {0.8, b.base[0]};
  g_coarse.d_top[0] = {std::vector<double>(n_x, 0.25), {}};
  g_coarse.d_low[0] = {std::vector<double>(n_x, 0.125), {}};
  g_coarse.low_solved[0] = {1, 0};
  SkinStackOffsets g_more = g_coarse;
  g_more.a_d = {coarse.a_d[0], t.a_d[at(t.a_d, 1.282)]};
  total = 0;
  g_more.compute(t, [&](std::size_t, std::size_t n) { total = n; }, &g_coarse);
  EXPECT_EQ(total, 4u);  // per node (g 0.8, dermis ratio 2) its top layer and its new light from below
  EXPECT_EQ(g_more.d_top[0][0], g_coarse.d_top[0][0]);
  ASSERT_EQ(g_more.d_low[0][0].size(), 2 * n_x);
  EXPECT_TRUE(std::equal(g_coarse.d_low[0][0].begin(), g_coarse.d_low[0][0].end(), g_more.d_low[0][0].begin()));
  EXPECT_GT(std::abs(g_more.d_low[0][0][n_x + n_x / 2] - 0.125), 1e-6);  // solved
}
