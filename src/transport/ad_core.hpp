#pragma once
// Internals of the adding-doubling solver, exposed to the tests of this part only (not installed,
// not a public header: it uses Eigen).
#include <Eigen/Dense>
#include <vector>

#include "skin/transport/accurate.hpp"
#include "skin/physics/layer.hpp"

namespace skin::accurate::detail {

// Largest optical depth of the diamond-initialised thin layer (its error is second order in the
// depth: 1/8 changes the MCML benchmark slab's totals by < 5e-5, docs/accurate-solver.md), and
// the transmitted flux below which a doubled layer counts as semi-infinite.
inline constexpr double kThinnest = 0.125;
inline constexpr double kSemiInfiniteT = 1e-8;

// The streams of a stack: s2[i] = (n sin theta)^2, invariant across interfaces; stream 0 is the
// normal direction (s = 0). a_ref[i]: flux weight in the medium of highest index n_ref.
struct Streams {
  int N = 0;
  double n_ref = 1;
  std::vector<double> edges;  // panel edges in s, ascending, last = n_ref
  std::vector<double> s2, a_ref;
  double escape_density = kInfinity;  // quadrature points per unit of mu_ref in the first panel
};
Streams make_streams(const LayerStack& stack, int points);
// Number of streams that propagate in a medium of index n (they are the leading ones).
int propagating(const Streams& st, double n);

struct LayerRT {
  Eigen::MatrixXd R, T;  // m x m, m = propagating(st, layer.eta)
};
// tabulate: layers from the interpolated tables of `cache` (true) or by direct doubling.
LayerRT layer_rt(const Streams& st, const Layer& layer, int points, bool tabulate,
                 const Cache& cache);

struct Boundary {
  Eigen::VectorXd r, t;  // diagonal reflection and transmission per stream (flux)
};
Boundary boundary(const Streams& st, double n_a, double n_b);

// adding_doubling() with the choice of how layers are computed (tables or direct doubling).
Totals solve(const LayerStack& stack, const Options& options, bool tabulate, const Cache& cache);

}  // namespace skin::accurate::detail
