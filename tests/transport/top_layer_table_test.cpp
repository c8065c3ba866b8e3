// The built-in TopLayerTables (data/top_layer_transport_g*.csv, Monte Carlo) against the independent
// adding-doubling solver at every node, its text form, its interpolation, and the transport-top
// radial response built on it (docs/accurate-solver.md, sec. 3).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "integrated_profile.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/skin_stack_table.hpp"
#include "skin/transport/top_layer_table.hpp"
#include "skin/util/error.hpp"
#include "skin/transport/profile.hpp"
#include "skin/physics/skin_parameters.hpp"

namespace {

using skin::Layer;
using skin::LayerStack;
using skin::accurate::TopLayerTable;

const TopLayerTable& table() { return TopLayerTable::builtin(); }

// The table's geometry in reduced units: the layer under air, over an index-matched medium.
LayerStack reduced_slab(double alpha, double tau) {
  LayerStack s;
  s.layers = {Layer{1 - alpha, alpha, tau, table().eta, table().g}};
  s.eta_above = table().eta_above;
  s.eta_below = table().eta;
  return s;
}

TEST(TopLayerTable, BuiltinDescribesSkinAndPrintsItself) {
  const auto& t = table();
  EXPECT_EQ(t.g, 0.9);
  EXPECT_EQ(t.eta, 1.4);
  EXPECT_EQ(t.eta_above, 1.0);
  EXPECT_EQ(t.nodes.size(), t.x.size() * t.tau.size());
  // The set: g = 0.8, 0.9, 0.95 for the same geometry, on one grid (so that they blend).
  const auto& set = TopLayerTable::builtin_set();
  ASSERT_EQ(set.size(), 3u);
  EXPECT_EQ(set[0].g, 0.8);
  EXPECT_EQ(set[2].g, 0.95);
  for (const auto& u : set) {
    EXPECT_TRUE(u.same_grid(t));
    EXPECT_EQ(u.eta, t.eta);
    EXPECT_EQ(u.eta_above, t.eta_above);
  }
  std::ostringstream os;
  os << t;
  EXPECT_NE(os.str().find("TopLayerTable{g=0.9"), std::string::npos) << os.str();
}

// Every node's totals are a Monte Carlo estimate; the adding-doubling solver computes the same
// two (reflectance and transmittance of the beam) by a different method. They agree within 2 %
// (relative) plus 3e-4 (the Monte Carlo noise of the smallest values).
TEST(TopLayerTable, EveryNodeAgreesWithAddingDoubling) {
  double worst_R = 0, worst_T = 0;
  for (const auto& t : TopLayerTable::builtin_set())
  for (std::size_t j = 0; j < t.tau.size(); ++j)
    for (std::size_t i = 0; i < t.x.size(); ++i) {
      const double alpha = 1 - t.x[i] * t.x[i];
      auto slab = reduced_slab(alpha, t.tau[j]);
      slab.layers.front().g = t.g;
      const auto ad = skin::accurate::adding_doubling(slab);
      const auto& n = t.nodes[j * t.x.size() + i];
      EXPECT_NEAR(n.R_e, ad.R_d, 0.02 * ad.R_d + 3e-4)
          << "g=" << t.g << " alpha'=" << alpha << " tau'=" << t.tau[j];
      EXPECT_NEAR(n.T_down, ad.T_d, 0.02 * ad.T_d + 3e-4)
          << "g=" << t.g << " alpha'=" << alpha << " tau'=" << t.tau[j];
      worst_R = std::max(worst_R, std::abs(n.R_e - ad.R_d) / ad.R_d);
      worst_T = std::max(worst_T, std::abs(n.T_down - ad.T_d) / (ad.T_d + 1e-3));
    }
  std::cout << "worst relative difference: R_e " << worst_R << ", T_down " << worst_T << '\n';
}

TEST(TopLayerTable, NodesAreInternallyConsistent) {
  const auto& t = table();
  for (const auto& n : t.nodes) {
    // Energy: nothing exceeds one; the transforms start at the totals and never exceed them.
    EXPECT_LE(n.R_e + n.T_down, 1 + 1e-9);
    EXPECT_LE(n.T_up + n.R_up, 1 + 1e-9);
    EXPECT_NEAR(n.T_down_k[0], n.T_down, 1e-4 * n.T_down + 1e-12);
    EXPECT_NEAR(n.T_up_k[0], n.T_up, 1e-4 * n.T_up + 1e-12);
    EXPECT_NEAR(n.R_up_k[0], n.R_up, 1e-4 * n.R_up + 1e-12);
    for (std::size_t k = 1; k < t.kappa.size(); ++k) {
      EXPECT_LE(std::abs(n.T_down_k[k]), n.T_down * (1 + 1e-4) + 1e-12);
      EXPECT_LE(std::abs(n.R_up_k[k]), n.R_up * (1 + 1e-4) + 1e-12);
    }
  }
  // At a node the interpolation returns the node, and the profile integrates to its total (the
  // light beyond rho = 300 and the core disc aside: within 2 %).
  const std::size_t i = 5, j = 7;
  const auto s = t.sample(1 - t.x[i] * t.x[i], t.tau[j]);
  const auto& n = t.nodes[j * t.x.size() + i];
  EXPECT_NEAR(s.R_e, n.R_e, 1e-12);
  EXPECT_NEAR(s.T_up_k[10], n.T_up_k[10], 1e-12);
  EXPECT_NEAR(t.R_e_integral(s) / n.R_e, 1.0, 0.02);
  // Between nodes the values lie between theirs.
  const auto mid = t.sample(1 - std::pow(0.5 * (t.x[i] + t.x[i + 1]), 2), t.tau[j]);
  const double a = n.T_down, b = t.nodes[j * t.x.size() + i + 1].T_down;
  EXPECT_GE(mid.T_down, std::min(a, b));
  EXPECT_LE(mid.T_down, std::max(a, b));
}

TEST(TopLayerTable, TextRoundTripAndMalformedInput) {
  const auto& t = table();
  const TopLayerTable u = TopLayerTable::parse(t.to_csv(), "roundtrip");
  ASSERT_EQ(u.nodes.size(), t.nodes.size());
  EXPECT_EQ(u.x, t.x);
  EXPECT_NEAR(u.nodes[17].R_e_rho[20], t.nodes[17].R_e_rho[20], 1e-4 * t.nodes[17].R_e_rho[20]);
  const std::string text = t.to_csv();
  auto expect_error = [](const std::string& bad, const std::string& what) {
    try {
      TopLayerTable::parse(bad, "bad.csv");
      ADD_FAILURE() << "no error for " << what;
    } catch (const skin::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.csv"), std::string::npos) << e.what();
    }
  };
  std::string no_g = text;
  no_g.erase(no_g.find("# g:"), no_g.find('\n', no_g.find("# g:")) - no_g.find("# g:") + 1);
  expect_error(no_g, "a missing line");
  std::string short_row = text.substr(0, text.rfind(','));  // last row loses a field
  expect_error(short_row, "a short row");
  std::string nan = text;
  nan[nan.rfind(',') + 1] = 'x';  // (not replace(): GCC 12 warns falsely, -Wrestrict)
  expect_error(nan, "a field that is not a number");
  expect_error("", "empty text");
}

// Skin with the default g and index uses the tabulated frequency-domain profile where its
// epidermis is light enough for that table (skin_stack_table.hpp) and the transport top layer at
// every other wavelength, for every preset; a g between the top-layer tables' uses them; beyond
// them the frequency-domain solver.
TEST(TransportTop, CoversThePresetsAndFallsBackOutsideTheTable) {
  const auto& skin_table = skin::accurate::SkinStackTable::builtin();
  for (const auto& p : skin::presets())
    for (double lambda = 400; lambda <= 700; lambda += 10) {
      const LayerStack s = skin::skin_layer_stack(p.parameters, lambda);
      const skin::accurate::AccurateStack acc(s);
      EXPECT_EQ(acc.skin_table(), skin_table.gap(s).empty()) << p.name << " " << lambda;
      EXPECT_EQ(acc.transport_top(), !acc.skin_table()) << p.name << " " << lambda;
    }
  // g between two tables' blends them; outside their range falls back.
  auto params = skin::find_preset("caucasian").parameters;
  for (double g : {0.8, 0.85, 0.93, 0.95}) {
    params.g = g;
    EXPECT_TRUE(skin::accurate::AccurateStack(skin::skin_layer_stack(params, 550)).transport_top())
        << g;
  }
  for (double g : {0.0, 0.7, 0.97}) {
    params.g = g;
    EXPECT_FALSE(skin::accurate::AccurateStack(skin::skin_layer_stack(params, 550)).transport_top())
        << g;
  }
  params.g = 0.9;
  params.eta = 1.33;
  EXPECT_FALSE(skin::accurate::AccurateStack(skin::skin_layer_stack(params, 550)).transport_top());
}

TEST(TopLayerTable, BlendIsLinearInTheTransformsAndGeometricInTheProfile) {
  const auto& set = TopLayerTable::builtin_set();
  const auto a = set[0].sample(0.9, 2.0), b = set[1].sample(0.9, 2.0);
  const auto m = TopLayerTable::blend(a, b, 0.25);
  EXPECT_NEAR(m.T_down_k[5], 0.75 * a.T_down_k[5] + 0.25 * b.T_down_k[5], 1e-15);
  EXPECT_NEAR(m.R_e, 0.75 * a.R_e + 0.25 * b.R_e, 1e-15);
  EXPECT_NEAR(m.R_e_centre[40], std::pow(a.R_e_centre[40], 0.75) * std::pow(b.R_e_centre[40], 0.25),
              1e-12 * m.R_e_centre[40]);
  const auto end = TopLayerTable::blend(a, b, 1.0);
  EXPECT_NEAR(end.R_up_k[3], b.R_up_k[3], 1e-15);
}

// Brute force: 2 pi int singular(r) r dr (Simpson in log r from 1 nm to r_max) + residual(0),
// the profile's integral (the residual's transform at k = 0 is its integral).
double profile_integral(const skin::accurate::AccurateStack& acc, double r_max) {
  const int m = 4000;
  const double a = std::log(1e-6), b = std::log(r_max), h = (b - a) / m;
  double sum = 0;
  for (int i = 0; i <= m; ++i) {
    const double r = std::exp(a + i * h);
    sum += (i == 0 || i == m ? 1 : (i % 2 ? 4 : 2)) * acc.singular(r) * r * r;
  }
  return 2 * std::numbers::pi * sum * h / 3 + acc.residual_k(0);
}

// A half-space of the table's geometry is split at the table's thickest layer: transport above,
// the same medium by diffusion below; its profile integrates to the adding-doubling total.
TEST(TransportTop, HalfSpaceIsSplitAtTheThickestLayer) {
  for (double alpha : {0.5, 0.95, 0.999}) {
    LayerStack s;
    s.layers = {Layer{1 - alpha, alpha, skin::kInfinity, 1.4, 0.9}};
    const skin::accurate::AccurateStack acc(s);
    ASSERT_TRUE(acc.transport_top()) << alpha;
    EXPECT_NEAR(profile_integral(acc, 400.0) / acc.total(), 1.0, 2e-3) << alpha << " " << acc;
  }
}

// The profile integrates to the adding-doubling total.
// (Skin with g = 0.8, which the skin table does not cover.)
TEST(TransportTop, TotalIsTheAddingDoublingTotal) {
  for (const char* name : {"caucasian", "african", "pale"})
    for (double lambda : {450.0, 650.0}) {
      auto params = skin::find_preset(name).parameters;
      params.g = 0.8;
      const auto st = skin::skin_layer_stack(params, lambda);
      const skin::accurate::AccurateStack acc(st);
      ASSERT_TRUE(acc.transport_top());
      // The adding-doubling R_d computed here on its own, against the space part's integral
      // plus the transform of the rest at k = 0, and against the profile a user gets
      // integrated by brute force (0.5 %: the integration grid).
      const double R_d = skin::accurate::adding_doubling(st).R_d;
      EXPECT_NEAR(profile_integral(acc, 100.0) / R_d, 1.0, 2e-3) << name << " " << lambda << " " << acc;
      EXPECT_NEAR(skin::test::integrated_profile(acc) / R_d, 1.0, 5e-3)
          << name << " " << lambda << " " << acc;
      EXPECT_GT(acc.c_top(), 0);
      EXPECT_GE(acc.c_deep(), 0);
    }
}

// transforms_at (the accurate profile's) gives exactly the three transform_at values, at the
// nodes, between them, at 0 and beyond the last node.
TEST(TopLayerTable, TransformsAtOneKappaAreTheSingleTransforms) {
  const TopLayerTable& t = table();
  const TopLayerTable::Sample s = t.sample(0.8, 2.0);
  std::vector<double> ks = {0.0, t.kappa[1], 0.5 * (t.kappa[3] + t.kappa[4]), t.kappa.back(), 2 * t.kappa.back()};
  for (double k = 1e-3; k < 1.5 * t.kappa.back(); k *= 1.37) ks.push_back(k);
  for (double k : ks) {
    const auto [T_down, T_up, R_up] = t.transforms_at(s, k);
    EXPECT_EQ(T_down, t.transform_at(s.T_down_k, k)) << k;
    EXPECT_EQ(T_up, t.transform_at(s.T_up_k, k)) << k;
    EXPECT_EQ(R_up, t.transform_at(s.R_up_k, k)) << k;
  }
  EXPECT_EQ(t.transforms_at(s, 2 * t.kappa.back()).T_down, 0.0);
  EXPECT_GT(t.transforms_at(s, 0.0).T_down, 0.0);
}

}  // namespace
