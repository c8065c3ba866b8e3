#pragma once
// Generation of skin::accurate::TopLayerTable by Monte Carlo (the data file
// data/top_layer_transport_g*.csv are made by `skin tabulate-top-layer`, which calls this).
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "skin/transport/random_walk_table.hpp"
#include "skin/transport/top_layer_table.hpp"
#include "skin/util/progress.hpp"

namespace skin::mc {

struct TabulateOptions {
  double g = 0.9, eta = 1.4, eta_above = 1.0;
  // Nodes: x = sqrt(1 - alpha'), increasing in [0, 1); tau' increasing, > 0.
  std::vector<double> x, tau;
  // Photons per node for the pencil beam: enough for `target_reflected` photons' worth of
  // reflected weight (estimated by a pilot run), within [min_photons, max_photons]; the diffuse
  // source from below uses min_photons.
  std::uint64_t min_photons = 200000, max_photons = 10000000;
  double target_reflected = 60000;
  std::uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
  // Nodes done of the x.size() * tau.size() in the table, after each node (may be empty).
  ProgressCallback progress;
  // The default grid: x = 0.05, 0.11, ..., 0.95 (16 nodes; alpha' from 0.9975 to 0.0975) and
  // tau' = 0.35 2^(j / 4), j = 0..26 (0.35 to 32).
  static TabulateOptions defaults();
};
std::ostream& operator<<(std::ostream& os, const TabulateOptions& o);

// Validates the options (InputError naming the parameter), then runs two Monte Carlo simulations
// per node (pencil beam from above, Lambertian point source from below).
accurate::TopLayerTable tabulate_top_layer(const TabulateOptions& options);

// Generation of transport::RandomWalkTable (data/random_walk_g0.csv, `skin tabulate-random-walk`):
// per node, Monte Carlo with the Lambertian top source (Source::diffuse_top) in an index-matched
// half-space of single-scattering albedo alpha and sigma_t = 1, exits histogrammed in log rho.
struct RandomWalkOptions {
  double g = 0.0;
  std::vector<double> alpha;        // increasing in (0, 1)
  std::uint64_t photons = 200000;   // per node
  std::size_t bins_per_decade = 12;  // annuli from rho = 1e-3 to 1e3, plus [0, 1e-3)
  std::uint64_t seed = 1;
  int threads = 0;
  ProgressCallback progress;  // nodes done of alpha.size()
  // The default nodes: 1 - alpha = 10^(-4 + 4 j / 33), j = 0..32 (alpha 0.9999 to 0.24), and
  // alpha = 0.05.
  static RandomWalkOptions defaults();
};
transport::RandomWalkTable tabulate_random_walk(const RandomWalkOptions& options);

}  // namespace skin::mc
