// Monte Carlo tabulation of a thin top layer's transport (tabulate.hpp, top_layer_table.hpp).
#include "skin/mc/tabulate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <sstream>

#include "skin/mc/mc.hpp"
#include "skin/util/error.hpp"

namespace skin::mc {

namespace {

// Fine exit histogram: logarithmic bins from 1e-3 to 1e3 reduced mean free paths, 1200 of them
// (1.16 % wide); every 12th edge up to rho = 300 is an edge of the table's R_e bins.
constexpr double kFineMin = 1e-3, kFineMax = 1e3;
constexpr std::size_t kFineBins = 1201;  // bin 0 = [0, kFineMin) plus 1200 logarithmic bins
constexpr std::size_t kCoarsen = 12;
constexpr double kRhoMax = 300.0;
// Reduced frequencies of the transforms: kappa_0 sinh(u), 48 nodes up to 300.
constexpr double kKappa0 = 0.25, kKappaMax = 300.0;
constexpr std::size_t kKappaNodes = 48;

void check(const TabulateOptions& o) {
  require_in_range("g", o.g, -0.999, 0.999, "");
  require_in_range("eta", o.eta, 1.0, 3.0, "");
  require_in_range("eta_above", o.eta_above, 1.0, 3.0, "");
  auto increasing = [](const std::vector<double>& v, const char* name, double lo, double hi) {
    if (v.size() < 2) throw InputError(std::string(name) + ": at least two nodes are needed");
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!(v[i] >= lo && v[i] < hi))
        throw InputError(std::string(name) + " node " + format_number(v[i]) +
                         " is out of range: must be in [" + format_number(lo) + ", " +
                         format_number(hi) + ")");
      if (i && !(v[i] > v[i - 1])) throw InputError(std::string(name) + " nodes must increase");
    }
  };
  increasing(o.x, "x", 0.0, 1.0);
  increasing(o.tau, "tau", 1e-6, 1e6);
  if (o.min_photons < 1 || o.max_photons < o.min_photons)
    throw InputError("photons: need 1 <= min_photons <= max_photons");
}

}  // namespace

TabulateOptions TabulateOptions::defaults() {
  TabulateOptions o;
  for (int i = 0; i < 16; ++i) o.x.push_back(0.05 + 0.06 * i);
  for (int j = 0; j <= 26; ++j) o.tau.push_back(0.35 * std::exp2(j / 4.0));
  return o;
}

std::ostream& operator<<(std::ostream& os, const TabulateOptions& o) {
  return os << "TabulateOptions{g=" << o.g << ", eta=" << o.eta << ", eta_above=" << o.eta_above
            << ", x nodes=" << o.x.size() << ", tau nodes=" << o.tau.size()
            << ", photons=[" << o.min_photons << ", " << o.max_photons
            << "], target_reflected=" << o.target_reflected << ", seed=" << o.seed << '}';
}

accurate::TopLayerTable tabulate_top_layer(const TabulateOptions& o) {
  check(o);
  accurate::TopLayerTable t;
  t.g = o.g;
  t.eta = o.eta;
  t.eta_above = o.eta_above;
  t.x = o.x;
  t.tau = o.tau;
  t.kappa_0 = kKappa0;
  const double du = std::asinh(kKappaMax / kKappa0) / static_cast<double>(kKappaNodes - 1);
  for (std::size_t i = 0; i < kKappaNodes; ++i)
    t.kappa.push_back(i == 0 ? 0.0 : kKappa0 * std::sinh(du * static_cast<double>(i)));
  {
    std::ostringstream p;
    p << "skin::mc::tabulate_top_layer, Monte Carlo with " << o.min_photons << " to "
      << o.max_photons << " photons per node (target reflected weight " << o.target_reflected
      << "), seed " << o.seed;
    t.provenance = p.str();
  }

  Options mo;
  mo.seed = o.seed;
  mo.threads = o.threads;
  mo.bins = 1;
  mo.r_max = kFineMax;
  mo.exit_bins = kFineBins;
  mo.exit_r_min = kFineMin;
  mo.exit_r_max = kFineMax;
  std::vector<double> fine_edges;
  std::vector<std::size_t> coarse_at;  // index of each R_e bin edge among the fine edges
  const std::size_t total = o.x.size() * o.tau.size();
  for (std::size_t j = 0; j < o.tau.size(); ++j) {
    for (std::size_t i = 0; i < o.x.size(); ++i) {
      const double alpha = 1.0 - o.x[i] * o.x[i];
      LayerStack stack;
      Layer l;
      l.sigma_a = 1.0 - alpha;
      l.sigma_s_prime = alpha;
      l.thickness = o.tau[j];
      l.eta = o.eta;
      l.g = o.g;
      stack.layers = {l};
      stack.eta_above = o.eta_above;
      stack.eta_below = o.eta;  // index-matched: light crossing the bottom leaves the layer
      const std::uint64_t node = j * o.x.size() + i;
      // Pencil beam: a pilot run sizes the main one.
      mo.source = Source::pencil;
      mo.seed = o.seed + 4 * node;
      mo.photons = 20000;
      const Result pilot = simulate(stack, mo);
      const double want = o.target_reflected / std::max(pilot.R_d, 1e-12);
      mo.photons = static_cast<std::uint64_t>(
          std::clamp(want, static_cast<double>(o.min_photons), static_cast<double>(o.max_photons)));
      mo.seed = o.seed + 4 * node + 1;
      const Result down = simulate(stack, mo);
      mo.source = Source::diffuse_bottom;
      mo.photons = o.min_photons;
      mo.seed = o.seed + 4 * node + 2;
      const Result up = simulate(stack, mo);
      if (fine_edges.empty()) {
        fine_edges = down.exit_r_edges;
        for (std::size_t b = 0; b < fine_edges.size(); b += (b == 0 ? 1 : kCoarsen)) {
          if (fine_edges[b] > kRhoMax) break;
          t.rho_edges.push_back(fine_edges[b]);
          coarse_at.push_back(b);
        }
      }
      accurate::TopLayerTable::Node n;
      n.R_e = down.R_d;
      n.T_down = down.T_d;
      n.T_up = up.R_d;
      n.R_up = up.T_d;
      // R_e per unit reduced area, on the coarse bins (sums of whole fine bins).
      for (std::size_t c = 0; c + 1 < coarse_at.size(); ++c) {
        double w = 0;
        for (std::size_t f = coarse_at[c]; f < coarse_at[c + 1]; ++f) w += down.top_exit[f];
        const double a = t.rho_edges[c], b = t.rho_edges[c + 1];
        n.R_e_rho.push_back(w / (std::numbers::pi * (b * b - a * a)));
      }
      for (double k : t.kappa) {
        n.T_down_k.push_back(k == 0 ? down.T_d : hankel_transform(fine_edges, down.bottom_exit, k));
        n.T_up_k.push_back(k == 0 ? up.R_d : hankel_transform(fine_edges, up.top_exit, k));
        n.R_up_k.push_back(k == 0 ? up.T_d : hankel_transform(fine_edges, up.bottom_exit, k));
      }
      t.nodes.push_back(std::move(n));
      if (o.progress) o.progress(node + 1, total);
    }
  }
  t.derive();
  return t;
}

}  // namespace skin::mc

namespace skin::mc {

RandomWalkOptions RandomWalkOptions::defaults() {
  RandomWalkOptions o;
  o.alpha.push_back(0.05);
  for (int j = 32; j >= 0; --j) o.alpha.push_back(1.0 - std::pow(10.0, -4.0 + 4.0 * j / 33.0));
  return o;
}

transport::RandomWalkTable tabulate_random_walk(const RandomWalkOptions& o) {
  if (o.alpha.size() < 2) throw InputError("alpha: at least two nodes are needed");
  for (std::size_t i = 0; i < o.alpha.size(); ++i)
    if (!(o.alpha[i] > 0 && o.alpha[i] < 1) || (i && !(o.alpha[i] > o.alpha[i - 1])))
      throw InputError("alpha = " + format_number(o.alpha[i]) +
                       " is out of range: nodes must increase within (0, 1)");
  if (o.bins_per_decade < 1 || o.bins_per_decade > 1000)
    throw InputError("bins_per_decade must be in [1, 1000]");
  transport::RandomWalkTable t;
  t.g = o.g;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "skin::mc::tabulate_random_walk, Monte Carlo with %llu photons per node, seed %llu",
                static_cast<unsigned long long>(o.photons), static_cast<unsigned long long>(o.seed));
  t.provenance = buf;
  for (std::size_t i = 0; i < o.alpha.size(); ++i) {
    Layer l;
    l.sigma_a = 1.0 - o.alpha[i];
    l.g = o.g;
    l.sigma_s_prime = o.alpha[i] * (1.0 - o.g);
    l.eta = 1.0;
    LayerStack stack{{l}, 1.0, 1.0};
    Options mo;
    mo.photons = o.photons;
    mo.seed = o.seed + i;
    mo.threads = o.threads;
    mo.source = Source::diffuse_top;
    mo.bins = 1;
    mo.r_max = 1.0;
    mo.exit_r_min = 1e-3;
    mo.exit_r_max = 1e3;
    mo.exit_bins = 6 * o.bins_per_decade + 1;
    const Result r = simulate(stack, mo);
    if (t.rho_edges.empty()) t.rho_edges = r.exit_r_edges;
    t.alpha.push_back(o.alpha[i]);
    t.R_d.push_back(r.R_d);
    t.R_d_se.push_back(r.R_d_se);
    t.fraction.push_back(r.top_exit);
    if (o.progress) o.progress(i + 1, o.alpha.size());
  }
  return t;
}

}  // namespace skin::mc
