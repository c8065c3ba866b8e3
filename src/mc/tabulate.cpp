// Monte Carlo tabulation of a renderer's random-walk response (tabulate.hpp, random_walk_table.hpp).
#include "skin/mc/tabulate.hpp"

#include <cmath>
#include <cstdio>

#include "skin/mc/mc.hpp"
#include "skin/util/error.hpp"

namespace skin::mc {

using skin::util::InputError;
using skin::util::format_number;

using skin::physics::Layer;
using skin::physics::LayerStack;

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
