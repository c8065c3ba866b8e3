// Radiative transfer in the spatial-frequency domain (docs/accurate-solver.md, section 5).
//
// The 2D Fourier transform over the surface (frequency k along x) turns the transport equation of
// a pencil beam into one per k:  mu dL/dz = -(sigma_t + i k sin(theta) cos(phi)) L + sigma_s int p L.
// The beam is symmetric about the x axis, so L = sum_a L_a(z, mu) cos(a phi) (orders a = 0..M);
// Henyey-Greenstein scattering keeps each order (the redistribution p_a of the addition theorem,
// Angular in ad_core.hpp) and the k term couples order a to a +- 1:
//   (cos(phi) L)_0 = L_1 / 2,  (cos(phi) L)_1 = L_0 + L_2 / 2,  (cos(phi) L)_a = (L_(a-1) + L_(a+1)) / 2.
// With L_a = i^a Lambda_a the system is real:
//   mu dLambda_a/dz = -sigma_t Lambda_a - k sin(theta) (K Lambda)_a + sigma_s (p_a Lambda_a),
//   K(0, 1) = -1/2, K(1, 0) = 1, K(a, a + 1) = -1/2, K(a, a - 1) = 1/2 (a >= 2).
// A homogeneous layer still looks the same from above and from below (z -> -z leaves sin(theta)
// cos(phi) alone), Fresnel interfaces stay diagonal (they keep phi and Snell's invariant, which
// labels the streams), so the adding-doubling machinery of adding_doubling.cpp carries over with
// matrices of (M + 1) blocks of streams, the term k sin(theta) / mu (sin(theta) = s / n in each
// layer) added to A. Only order 0 carries flux out of the surface; at k = 0 the orders decouple
// and order 0 is the totals' problem.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "ad_core.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/util/error.hpp"

namespace skin::accurate {

namespace detail {
namespace {

// The layer equations (flux form, as in adding_doubling.cpp) of one layer at dimensionless
// frequency kappa = k / sigma_t (delta-M scaled sigma_t), block-major over the orders.
void frequency_matrices(const Angular& geo, double omega, double kappa, int orders, Mat& A,
                        Mat& B) {
  const int m = geo.m, n = m * orders;
  A = Mat::Zero(n, n);
  B = Mat::Zero(n, n);
  const Vec inv_mu = geo.mu.cwiseInverse();
  for (int a = 0; a < orders; ++a) {
    A.block(a * m, a * m, m, m) = -omega * geo.c.asDiagonal() * geo.Pplus[static_cast<std::size_t>(a)] * inv_mu.asDiagonal();
    A.block(a * m, a * m, m, m).diagonal() += inv_mu;
    B.block(a * m, a * m, m, m) = omega * geo.c.asDiagonal() * geo.Pminus[static_cast<std::size_t>(a)] * inv_mu.asDiagonal();
  }
  if (kappa == 0.0) return;
  const Vec drift = kappa * geo.s.cwiseProduct(inv_mu);  // kappa sin(theta) / mu
  auto couple = [&](int a, int b, double K) {
    if (b < 0 || b >= orders) return;  // truncation: order M + 1 is dropped
    A.block(a * m, b * m, m, m).diagonal() += K * drift;
  };
  for (int a = 0; a < orders; ++a) {
    if (a == 0) {
      couple(0, 1, -0.5);
    } else if (a == 1) {
      couple(1, 0, 1.0);
      couple(1, 2, -0.5);
    } else {
      couple(a, a - 1, 0.5);
      couple(a, a + 1, -0.5);
    }
  }
}

LayerRT frequency_layer(const Angular& geo, const Layer& layer, double k, int orders) {
  const double sigma_s = layer.sigma_s() * (1 - geo.f);  // delta-M scaled [1/mm]
  const double sigma_t = layer.sigma_a + sigma_s;
  const double omega = sigma_s / sigma_t;
  const double kappa = k / sigma_t;
  Mat A, B;
  frequency_matrices(geo, omega, kappa, orders, A, B);
  // The thin layer's error is second order in its depth times the fastest rate, which the drift
  // raises by up to kappa: the initial depth shrinks with it.
  const double thinnest = kThinnest / (1.0 + kappa);
  auto transmitted = [](const LayerRT& rt) { return rt.T.cwiseAbs().colwise().sum().maxCoeff(); };
  if (layer.semi_infinite()) {
    LayerRT rt = diamond(A, B, thinnest);
    for (int i = 0; i < 64 && transmitted(rt) >= kSemiInfiniteT; ++i) double_once(rt);
    rt.T.setZero();
    return rt;
  }
  const double tau = sigma_t * layer.thickness;
  int doublings = 0;
  double dtau = tau;
  while (dtau > thinnest) {
    dtau *= 0.5;
    ++doublings;
  }
  LayerRT rt = diamond(A, B, dtau);
  for (int i = 0; i < doublings && transmitted(rt) >= 1e-30; ++i) double_once(rt);
  return rt;
}

}  // namespace
}  // namespace detail

std::vector<double> frequency_response(const LayerStack& stack, const std::vector<double>& k,
                                       const FrequencyOptions& options) {
  const int points = detail::quadrature_points(stack, options.totals);
  if (options.azimuthal_orders < 1 || options.azimuthal_orders > 64)
    throw InputError("azimuthal-orders = " + std::to_string(options.azimuthal_orders) +
                     " is out of range: allowed range is [1, 64]");
  for (double ki : k)
    if (!(ki >= 0 && std::isfinite(ki)))
      throw InputError("k = " + std::to_string(ki) + " rad/mm is out of range: must be >= 0");
  const detail::Streams st = detail::make_streams(stack, points);
  std::vector<detail::Angular> geo;
  for (const auto& l : stack.layers) geo.push_back(detail::angular(st, l.eta, l.g, options.azimuthal_orders));
  const detail::Vec t = detail::escape_weights(st, stack);
  std::vector<double> out;
  out.reserve(k.size());
  for (double ki : k) {
    // At k = 0 the orders decouple and order 0 alone is the answer.
    const int orders = ki == 0.0 ? 1 : options.azimuthal_orders;
    const detail::Below below = detail::add_stack(stack, st, orders, [&](std::size_t i) {
      return detail::frequency_layer(geo[i], stack.layers[i], ki, orders);
    });
    const detail::Vec D = detail::under_surface(stack, st, orders, below);
    out.push_back(t.dot((below.R * D).head(st.N)));
  }
  return out;
}

}  // namespace skin::accurate
