#pragma once
// Internals of the adding-doubling solver, exposed to the tests of this part only (not installed,
// not a public header: it uses Eigen).
#include <Eigen/Dense>
#include <functional>
#include <vector>

#include "skin/transport/accurate.hpp"
#include "skin/physics/layer.hpp"

namespace skin::transport::accurate::detail {

// Largest optical depth of the diamond-initialised thin layer (its error is second order in the
// depth: 1/8 changes the MCML benchmark slab's totals by < 5e-5, docs/accurate-solver.md, sec.
// 2), and the transmitted flux below which a doubled layer counts as semi-infinite.
inline constexpr double kThinnest = 0.125;
inline constexpr double kSemiInfiniteT = 1e-8;

// The streams of a stack: s2[i] = (n sin theta)^2, invariant across interfaces; stream 0 is the
// normal direction (s = 0). a_ref[i]: flux weight in the medium of highest index n_ref.
struct Streams {
  int N = 0;
  double n_ref = 1;
  std::vector<double> edges;  // panel edges in s, ascending, last = n_ref
  std::vector<double> s2, a_ref;
  double escape_density = physics::kInfinity;  // quadrature points per unit of mu_ref in the first panel
};
Streams make_streams(const physics::LayerStack& stack, int points);
// Number of streams that propagate in a medium of index n (they are the leading ones).
int propagating(const Streams& st, double n);

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

// Quadrature points per panel for a stack (Options, or automatic: for the totals, or for the
// frequency-domain solver); validates both.
int quadrature_points(const physics::LayerStack& stack, const Options& options,
                      bool frequency_domain = false);

// Angular data of one medium (index n, anisotropy g) on a stream set: cosines mu, sines s (of
// the angle from the normal, in that medium), c = a / (4 mu), the delta-M forward fraction f and
// the redistribution matrices of azimuthal orders 0..modes-1: Pplus[a](i, j) = p_a(mu_i, mu_j),
// Pminus[a](i, j) = p_a(-mu_i, mu_j) (order 0 renormalised to conserve energy).
struct Angular {
  int m = 0;
  Vec mu, s, c;
  std::vector<Mat> Pplus, Pminus;
  double f = 0;
};
Angular angular(const Streams& st, double n, double g, int modes);

struct LayerRT {
  Eigen::MatrixXd R, T;  // m x m, m = propagating(st, layer.eta)
};
// tabulate: layers from the interpolated tables of `cache` (true) or by direct doubling.
LayerRT layer_rt(const Streams& st, const physics::Layer& layer, int points, bool tabulate,
                 const Cache& cache);

struct Boundary {
  Eigen::VectorXd r, t;  // diagonal reflection and transmission per stream (flux)
};
Boundary boundary(const Streams& st, double n_a, double n_b);

// The diamond-initialised thin layer for the layer equations (A, B), and one doubling.
LayerRT diamond(const Mat& A, const Mat& B, double dtau);
void double_once(LayerRT& rt);

// Everything below a plane, seen from above: R (and T unless semi-infinite).
struct Below {
  Mat R, T;
};
// Puts a symmetric element (R_e, T_e) on top of `b` (adding); T only if need_T.
void add_on_top(Below& b, const Mat& Re, const Mat& Te, bool need_T);
// The whole stack below its top surface, from the bottom up: layers (layer(i): the i-th layer's
// R and T on its propagating streams, `blocks` blocks of them) and the Fresnel interfaces.
Below add_stack(const physics::LayerStack& stack, const Streams& st, int blocks,
                const std::function<LayerRT(std::size_t)>& layer);
// The downward flux just under the top surface for the unit beam in stream 0 of block 0.
Vec under_surface(const physics::LayerStack& stack, const Streams& st, int blocks, const Below& below);
// Transmission of the top surface per stream (flux that escapes upwards).
Vec escape_weights(const Streams& st, const physics::LayerStack& stack);

// Azimuthal orders of the frequency-domain solver at frequency k (options, or automatic:
// kAutomaticOrders at every k > 0; docs/accurate-solver.md, sec. 3). The same number at every
// k > 0: a step in their number between two frequency nodes is a jump in R(k) that rings in the
// far field (until 2026-12-05 the orders grew with k, 3 + ceil(4 sqrt(k / sigma_t)) up to 8, and
// under a dark epidermis over a more scattering dermis, asian skin at 450 nm with the dermis 1.4
// times as scattering, the profile swung between -160 % and +230 % of the Monte Carlo's over
// 0.3-0.9 mm, 1e-4 to 1e-6 of its peak, where 8 orders at every k are within 1 %; twice the
// time per solve). A stack less than
// kThinStackDepth scaled mean free paths deep in all (a thin slab: little multiple scattering
// smooths the radiance's dependence on azimuth, and light trapped by total internal reflection
// runs far along it) gets the same number of orders at every k > 0 (no step in their number
// between nodes, whose jump in R(k) would ring in the far field): kThinStackOrders, or
// kThinStackOrderDepth / depth rounded up to an even number where that is more (the azimuthal
// structure of the trapped light narrows as its damping per bounce, ~ the depth, falls; sec. 5),
// at most kThinStackMostOrders.
// scaled_extinction: sigma_a + sigma_s (1 - g^16), close to the delta-M scaled extinction of the
// default quadrature (it sets only how deep a thin stack is and where the nodes end).
double scaled_extinction(const physics::Layer& l);
inline constexpr int kAutomaticOrders = 8;
inline constexpr int kThinStackOrders = 24;
inline constexpr double kThinStackDepth = 0.5;
inline constexpr double kThinStackOrderDepth = 1.5;
inline constexpr int kThinStackMostOrders = 64;
int azimuthal_orders(const physics::LayerStack& stack, double k, const FrequencyOptions& options);

// The layer equations (A, B) of the frequency-domain solver for one medium at kappa = k /
// sigma_t (delta-M scaled) with `orders` azimuthal orders (block-major); from their modes (sfd.cpp),
// the reflection of a half-space of it, and a finite layer equal to the diamond layer of depth h
// doubled `doublings` times (false when the modes are not well determined: the caller then
// doubles).
void frequency_matrices(const Angular& geo, double omega, double kappa, int orders, Mat& A, Mat& B);
bool semi_infinite_modes(const Mat& A, const Mat& B, Mat& R);
bool finite_modes(const Mat& A, const Mat& B, double h, int doublings, LayerRT& rt);

// The frequency nodes of a radial response: k_j = k0 sinh(j du) up to k_hi (at least 8 nodes,
// the 6 of the interpolation below and two more), and G at k by 6-point Lagrange in
// u = asinh(k / k0) / du over those nodes (mirrored at u = 0: G(-u) = G(u)), 0 at and beyond the
// last node. The interpolation error is periodic in u, i.e. at high k it has the period k du in
// k, and its transform is an echo at r ~ 2 pi / (k du) (0.1-0.5 mm for k of 100-700 rad/mm). With
// 4 points it stood at ~5e-7 of R(0.01 mm) at 0.2-0.7 mm in african skin at 450 nm, where the
// profile is below 1e-6 of that; with 6 it is ~1e-8, as with 4 points and half the spacing.
std::vector<double> frequency_nodes(double k_hi, double k0, double du);
double interpolate_in_u(const std::vector<double>& k_nodes, const std::vector<double>& G, double k, double k0,
                        double du);

// Single scattering in the top layer that leaves directly, as the frequency-domain solver
// discretises it (sfd.cpp), at each k [rad/mm].
std::vector<double> single_scattering_k(const physics::LayerStack& stack, const std::vector<double>& k,
                                        const FrequencyOptions& options);

// adding_doubling() with the choice of how layers are computed (tables or direct doubling).
Totals solve(const physics::LayerStack& stack, const Options& options, bool tabulate, const Cache& cache);

}  // namespace skin::transport::accurate::detail
