#pragma once
// Tables made by Monte Carlo.
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "skin/transport/random_walk_table.hpp"
#include "skin/util/progress.hpp"

namespace skin::mc {

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
  util::ProgressCallback progress;  // nodes done of alpha.size()
  // The default nodes: 1 - alpha = 10^(-4 + 4 j / 33), j = 0..32 (alpha 0.9999 to 0.24), and
  // alpha = 0.05.
  static RandomWalkOptions defaults();
};
transport::RandomWalkTable tabulate_random_walk(const RandomWalkOptions& options);

}  // namespace skin::mc
