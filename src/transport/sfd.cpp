// Radiative transfer in the spatial-frequency domain (docs/accurate-solver.md, section 3).
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
#include <boost/math/special_functions/bessel.hpp>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "ad_core.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/quadrature.hpp"
#include "skin/physics/fresnel.hpp"

namespace skin::transport::accurate {

using skin::util::InputError;
using skin::util::QuadratureRule;
using skin::util::gauss_legendre;
using skin::util::lagrange_weights;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::fresnel_dielectric;
using skin::physics::kInfinity;

namespace detail {

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

namespace {

// The modes of a homogeneous layer (discrete ordinates): with S = F+ + F- and D = F+ - F-,
// dS/dtau = -(A + B) D and dD/dtau = -(A - B) S, so S'' = (A + B)(A - B) S. Each eigenpair
// (lambda^2, v) of (A + B)(A - B), Re lambda > 0, is a mode that decays downwards, S = v
// exp(-lambda tau), D = w exp(-lambda tau) with w = (A + B)^-1 v lambda, i.e. F+ = U+ exp(-lambda
// tau), F- = U- exp(-lambda tau) with U+- = v +- w (up to a common factor); by symmetry (z -> -z)
// F+ = U- exp(-lambda (tau_0 - tau)), F- = U+ exp(...) decays upwards. The solutions depend
// only on the space the modes span, so V may be any basis of it: the real one of Eigen's
// pseudo-eigenvectors (a complex pair u +- iv, x +- iy becomes the columns x, y and the block
// [u v; -v u]; Lambda the same block of sqrt(u + iv)) keeps everything real. Doubling the diamond
// layer keeps these modes (the diamond layer is a Cayley transform of the layer equations, which
// keeps their invariant subspaces) and differs only in how a finite layer attenuates them.
struct Modes {
  Mat Up, Um;        // U+ and U-, one mode per column
  Mat L;             // Lambda (block diagonal: 1 x 1 and 2 x 2 blocks)
  std::vector<int> block;  // size of the block that starts at each index (0 inside a block)
};

bool layer_modes(const Mat& A, const Mat& B, Modes& m) {
  const Mat ApB = A + B;
  const Eigen::EigenSolver<Mat> es(ApB * (A - B));
  if (es.info() != Eigen::Success) return false;
  const Mat V = es.pseudoEigenvectors();
  const Mat D = es.pseudoEigenvalueMatrix();
  const auto n = D.rows();
  m.L = Mat::Zero(n, n);  // the principal square root (Re >= 0)
  m.block.assign(static_cast<std::size_t>(n), 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto ii = static_cast<std::size_t>(i);
    if (i + 1 < n && D(i, i + 1) != 0.0) {
      const std::complex<double> l = std::sqrt(std::complex<double>(D(i, i), D(i, i + 1)));
      m.L(i, i) = m.L(i + 1, i + 1) = l.real();
      m.L(i, i + 1) = l.imag();
      m.L(i + 1, i) = -l.imag();
      m.block[ii] = 2;
      ++i;
    } else {
      m.L(i, i) = std::sqrt(std::max(0.0, D(i, i)));
      m.block[ii] = 1;
    }
  }
  const Mat W = ApB.partialPivLu().solve(V * m.L);
  m.Up = V + W;
  m.Um = V - W;
  return m.Up.allFinite() && m.Um.allFinite();
}

// A half-space is unchanged by a thin layer put on top of it: the Riccati equation B - A R - R A
// + R B R = 0 (adding R_thin = B dtau, T_thin = I - A dtau). Its residual on two vectors,
// relative to the size of the layer's matrices, says whether the modes were resolved (~1e-14 to
// 1e-12 in skin; nearly defective eigenvectors or a negative lambda^2 would show here). R is
// given by its action on a matrix of vectors.
template <class ApplyR>
bool riccati_holds(const Mat& A, const Mat& B, const ApplyR& R) {
  const auto n = A.rows();
  const double scale =
      A.cwiseAbs().colwise().sum().maxCoeff() + B.cwiseAbs().colwise().sum().maxCoeff();
  Mat x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    x(i, 0) = 1;
    x(i, 1) = i % 2 == 0 ? 1 : -1;
  }
  const Mat Rx = R(x);
  const Mat residual = B * x - A * Rx - R(A * x) + R(B * Rx);
  return residual.allFinite() && residual.cwiseAbs().maxCoeff() < 1e-9 * scale;
}

}  // namespace

// The half-space: only the modes that decay downwards, F- = R F+ with R = U- U+^-1. One
// eigen-decomposition instead of 10-20 doublings of a thin layer (it costs ~7 at 128 x 128);
// agrees with doubling to ~1e-11 (tested). False when the modes are not well determined (the
// caller doubles instead).
bool semi_infinite_modes(const Mat& A, const Mat& B, Mat& R) {
  Modes m;
  if (!layer_modes(A, B, m)) return false;
  // R U+ = U-, solved transposed.
  R = m.Up.transpose().partialPivLu().solve(m.Um.transpose()).transpose();
  return R.allFinite() && riccati_holds(A, B, [&](const Mat& x) { return Mat(R * x); });
}

// A finite layer from its modes: with E the attenuation of each mode across the layer, the unit
// flux incident from above, F+(0) = U+ c + U- E d = I, and nothing from below, F-(tau) = U- E c +
// U+ d = 0, give d = -X E c (X = U+^-1 U-), c = (U+ - U- E X E)^-1, R = (U- - U+ E X E) c and T =
// (U+ - U- X) E c. Every factor is bounded (|E| <= 1), so thick layers are as stable as thin
// ones. The attenuation is the one of the diamond layer of depth h doubled `doublings` times,
// E = ((1 - lambda h / 2) / (1 + lambda h / 2))^(2^doublings) (exp(-lambda tau) to second order
// in lambda h), so that the result is the doubled layer's, without the doublings (tested).
bool finite_modes(const Mat& A, const Mat& B, double h, int doublings, LayerRT& rt) {
  Modes m;
  if (!layer_modes(A, B, m)) return false;
  const auto n = A.rows();
  // E block by block: a 1 x 1 block is a real lambda, a 2 x 2 block [a b; -b a] the complex
  // lambda = a + ib, whose factor e = p + iq is the block [p q; -q p].
  auto attenuation = [&](std::complex<double> lambda) {
    std::complex<double> e = (1.0 - 0.5 * h * lambda) / (1.0 + 0.5 * h * lambda);
    for (int i = 0; i < doublings; ++i) e *= e;
    return e;
  };
  Mat E = Mat::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int size = m.block[static_cast<std::size_t>(i)];
    if (size == 1) {
      E(i, i) = attenuation(m.L(i, i)).real();
    } else if (size == 2) {
      const std::complex<double> e = attenuation({m.L(i, i), m.L(i, i + 1)});
      E(i, i) = E(i + 1, i + 1) = e.real();
      E(i, i + 1) = e.imag();
      E(i + 1, i) = -e.imag();
    }
  }
  // Products with the block-diagonal E, in O(n^2).
  auto right = [&](const Mat& X) {  // X E
    Mat Y(X.rows(), n);
    for (Eigen::Index i = 0; i < n;) {
      const int size = m.block[static_cast<std::size_t>(i)];
      Y.middleCols(i, size) = X.middleCols(i, size) * E.block(i, i, size, size);
      i += size;
    }
    return Y;
  };
  auto left = [&](const Mat& X) {  // E X
    Mat Y(n, X.cols());
    for (Eigen::Index i = 0; i < n;) {
      const int size = m.block[static_cast<std::size_t>(i)];
      Y.middleRows(i, size) = E.block(i, i, size, size) * X.middleRows(i, size);
      i += size;
    }
    return Y;
  };
  const auto up = m.Up.partialPivLu();
  const Mat X = up.solve(m.Um);
  const Mat EXE = left(right(X));
  // R Q = U- - U+ E X E and T Q = (U+ - U- X) E with Q = U+ - U- E X E: solved transposed, one
  // factorisation.
  const auto Qt = (m.Up - m.Um * EXE).transpose().partialPivLu();
  rt.R = Qt.solve((m.Um - m.Up * EXE).transpose()).transpose();
  rt.T = Qt.solve(right(m.Up - m.Um * X).transpose()).transpose();
  // The modes must be resolved: the half-space of the same medium, R_inf = U- U+^-1, satisfies
  // its Riccati equation.
  auto r_inf = [&](const Mat& x) {  // R_inf x = U- (U+^-1 x)
    return Mat(m.Um * up.solve(x));
  };
  return rt.R.allFinite() && rt.T.allFinite() && riccati_holds(A, B, r_inf);
}

namespace {

// Where the modes are cheaper than doubling (Eigen 3.4, GCC -O3, measured at 64-512 rows): an
// eigen-decomposition costs ~7 doublings up to ~192 rows (with the rest of finite_modes ~9), but
// 12-27 beyond, where its matrices leave the cache; a half-space takes 9-14 doublings.
constexpr Eigen::Index kModesLargest = 192;
constexpr int kModesFewestDoublings = 7;

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
    // At k = 0 (one order, small matrices) by doubling, exactly as the totals (R(0) is their
    // R_d); at k > 0 from the decaying modes.
    LayerRT rt;
    if (kappa > 0 && A.rows() <= kModesLargest && semi_infinite_modes(A, B, rt.R)) {
      rt.T = Mat::Zero(A.rows(), A.cols());
      return rt;
    }
    rt = diamond(A, B, thinnest);
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
  LayerRT rt;
  // At k = 0 by doubling, exactly as the totals; at k > 0 from the modes (the same numbers)
  // where that is cheaper.
  if (kappa > 0 && A.rows() <= kModesLargest && doublings >= kModesFewestDoublings &&
      finite_modes(A, B, dtau, doublings, rt))
    return rt;
  rt = diamond(A, B, dtau);
  for (int i = 0; i < doublings && transmitted(rt) >= 1e-30; ++i) double_once(rt);
  return rt;
}

}  // namespace

// Light scattered once that leaves directly (no other scattering or reflection) in the solver's
// discretisation (streams, orders, delta-M phase function), R_1(k). In the top layer the beam
// (stream 0, order 0) decays as exp(-tau'), scatters into the upward stream i (order 0 only:
// p_a(-mu_i, 1) = 0 for a > 0), which climbs with the order coupling G_i = (I + kappa s_i K) /
// mu_i and escapes with t_i:
//   R_1 = sum_i t_i omega c_i P-_0(i, 0) [(I + G_i)^-1 (I - exp(-tau (I + G_i)))]_00,
// evaluated in the eigenbasis of K (its eigenvalues are imaginary: K is similar to an
// antisymmetric matrix), so that each stream costs M + 1 complex divisions. In a deeper layer l
// the beam arrives attenuated by the layers above and transmitted by their interfaces (stream 0),
// and the scattered stream climbs through each layer m above with exp(-tau_m G_i^(m)) (its own
// kappa, mu and s; K is the same in every layer, so in its eigenbasis this is a product of
// scalars) and crosses each interface with its transmission (docs/accurate-solver.md, sec. 3).
std::vector<double> single_scattering_k(const LayerStack& stack, const std::vector<double>& k,
                                        const FrequencyOptions& options) {
  const int points = quadrature_points(stack, options.totals, true);
  const Streams st = make_streams(stack, points);
  const Vec t = escape_weights(st, stack);
  // Per layer: the delta-M scaled data of the solver, the beam's weight at the layer's top
  // (attenuated by the layers above and transmitted by their interfaces at normal incidence,
  // stream 0) and, per stream, the transmission of the interfaces above it (the light scattered
  // in layer l climbs through every layer above: in the eigenbasis of K a product of scalars).
  const auto& ls = stack.layers;
  const std::size_t L = options.deep_single_scattering ? ls.size() : 1;
  std::vector<Angular> geo;
  std::vector<double> omega, sigma_t, tau, beam;
  double w = 1;
  for (std::size_t l = 0; l < L; ++l) {
    geo.push_back(angular(st, ls[l].eta, ls[l].g, 1));
    const double sigma_s = ls[l].sigma_s() * (1 - geo.back().f);
    sigma_t.push_back(ls[l].sigma_a + sigma_s);
    omega.push_back(sigma_s / sigma_t.back());
    tau.push_back(sigma_t.back() * ls[l].thickness);
    beam.push_back(w);
    if (l + 1 < L) w *= std::exp(-tau.back()) * boundary(st, ls[l].eta, ls[l + 1].eta).t(0);
  }
  // up[l](i): the transmission of every interface between layer l and the top surface for
  // stream i (0 where it does not propagate in some layer on the way), times the escape weight.
  std::vector<Vec> up(L);
  up[0] = t;
  for (std::size_t l = 1; l < L; ++l) {
    up[l] = up[l - 1].cwiseProduct(boundary(st, ls[l - 1].eta, ls[l].eta).t);
    for (int i = geo[l - 1].m; i < st.N; ++i) up[l](i) = 0;
  }
  std::vector<double> out;
  int last = 0;
  Eigen::VectorXcd lambda;
  Eigen::MatrixXcd V, W;
  for (double ki : k) {
    const int orders = azimuthal_orders(stack, ki, options);
    if (orders != last) {
      Mat K = Mat::Zero(orders, orders);
      for (int a = 0; a + 1 < orders; ++a) {
        K(a, a + 1) = -0.5;
        K(a + 1, a) = a == 0 ? 1.0 : 0.5;
      }
      const Eigen::EigenSolver<Mat> es(K);
      lambda = es.eigenvalues();
      V = es.eigenvectors();
      W = V.inverse();
      last = orders;
    }
    double R = 0;
    for (std::size_t l = 0; l < L; ++l) {
      if (beam[l] == 0) continue;
      const double kappa = ki / sigma_t[l];
      for (int i = 0; i < geo[l].m; ++i) {
        if (up[l](i) == 0) continue;
        std::complex<double> sum = 0;
        for (int j = 0; j < orders; ++j) {
          const std::complex<double> z =
              1.0 + (1.0 + kappa * geo[l].s(i) * lambda(j)) / geo[l].mu(i);
          const std::complex<double> depth =
              std::isfinite(tau[l]) ? 1.0 - std::exp(-tau[l] * z) : 1.0;
          // Through the layers above, whole: exp(-tau_m (1 + kappa_m s_i lambda_j) / mu_i).
          std::complex<double> above = 1.0;
          for (std::size_t m = 0; m < l; ++m)
            above *= std::exp(-tau[m] * (1.0 + ki / sigma_t[m] * geo[m].s(i) * lambda(j)) /
                              geo[m].mu(i));
          sum += V(0, j) * W(j, 0) * depth / z * above;
        }
        R += beam[l] * up[l](i) * omega[l] * geo[l].c(i) * geo[l].Pminus[0](i, 0) * sum.real();
      }
    }
    out.push_back(R);
  }
  return out;
}

// Light that comes back along the beam without scattering (in the delta-M picture: the forward
// peak counts as unscattered): the normal stream 0 never couples to other orders or streams;
// it is attenuated by exp(-sigma_t d) per layer and reflected by the Fresnel reflectance at
// normal incidence of every interface. 1D adding from the bottom up.
double ballistic_return(const LayerStack& stack, const FrequencyOptions& options) {
  const int points = quadrature_points(stack, options.totals, true);
  const Streams st = make_streams(stack, points);
  const auto& ls = stack.layers;
  auto fresnel0 = [](double a, double b) { return fresnel_dielectric(1.0, a, b); };
  double R = stack.semi_infinite() ? 0.0 : fresnel0(ls.back().eta, stack.eta_below);
  for (std::size_t i = ls.size(); i-- > 0;) {
    const Layer& l = ls[i];
    if (!l.semi_infinite()) {
      const double f = angular(st, l.eta, l.g, 1).f;
      const double e = std::exp(-(l.sigma_a + l.sigma_s() * (1 - f)) * l.thickness);
      R *= e * e;
    }
    if (i > 0) {
      const double r = fresnel0(ls[i - 1].eta, l.eta);
      R = r + (1 - r) * (1 - r) * R / (1 - r * R);
    }
  }
  const double r_top = fresnel0(stack.eta_above, ls.front().eta);
  return (1 - r_top) * R / (1 - r_top * R);
}

}  // namespace detail

double detail::scaled_extinction(const Layer& l) {
  return l.sigma_a + l.sigma_s() * (1 - std::pow(l.g, 16));
}

int detail::azimuthal_orders(const LayerStack& stack, double k, const FrequencyOptions& options) {
  if (options.azimuthal_orders != 0) return k == 0.0 ? 1 : options.azimuthal_orders;
  if (k == 0.0) return 1;  // the orders decouple: order 0 alone is the answer
  double depth = 0;
  for (const auto& l : stack.layers) depth += scaled_extinction(l) * l.thickness;  // infinite for a semi-infinite layer
  // An even number: with 47 orders the slab of sec. 5 is -4.6 % near the beam, with 48 +2.8 %.
  // (Clamped before the conversion: a clear stack has depth 0.)
  if (depth < kThinStackDepth) {
    const double half = std::ceil(kThinStackOrderDepth / (2 * depth));
    return std::clamp(2 * static_cast<int>(std::min(half, 0.5 * kThinStackMostOrders)),
                      kThinStackOrders, kThinStackMostOrders);
  }
  return kAutomaticOrders;
}

std::vector<double> frequency_response(const LayerStack& stack, const std::vector<double>& k,
                                       const FrequencyOptions& options) {
  const int points = detail::quadrature_points(stack, options.totals, true);
  if (options.azimuthal_orders < 0 || options.azimuthal_orders > 64)
    throw InputError("azimuthal-orders = " + std::to_string(options.azimuthal_orders) +
                     " is out of range: must be 0 (automatic) or in [1, 64]");
  for (double ki : k)
    if (!(ki >= 0 && std::isfinite(ki)))
      throw InputError("k = " + std::to_string(ki) + " rad/mm is out of range: must be >= 0");
  const detail::Streams st = detail::make_streams(stack, points);
  int most = 1;
  for (double ki : k) most = std::max(most, detail::azimuthal_orders(stack, ki, options));
  std::vector<detail::Angular> geo;
  for (const auto& l : stack.layers) geo.push_back(detail::angular(st, l.eta, l.g, most));
  const detail::Vec t = detail::escape_weights(st, stack);
  // The frequencies are independent: in parallel (each writes its own slot, so the numbers do
  // not depend on the threads).
  std::vector<double> out(k.size());
  tbb::parallel_for(std::size_t{0}, k.size(), [&](std::size_t j) {
    const double ki = k[j];
    const int orders = detail::azimuthal_orders(stack, ki, options);
    const detail::Below below = detail::add_stack(stack, st, orders, [&](std::size_t i) {
      return detail::frequency_layer(geo[i], stack.layers[i], ki, orders);
    });
    const detail::Vec D = detail::under_surface(stack, st, orders, below);
    out[j] = t.dot((below.R * D).head(st.N));
  });
  return out;
}

}  // namespace skin::transport::accurate

namespace skin::transport::accurate {

FrequencyStack::FrequencyStack(const LayerStack& stack, const FrequencyProfileOptions& options)
    : FrequencyStack(stack, options, Cache()) {}

namespace {

// Henyey-Greenstein phase function (normalised to int p dOmega / (4 pi) = 1).
double hg(double g, double cos_theta) {
  const double d = 1 + g * g - 2 * g * cos_theta;
  return (1 - g * g) / (d * std::sqrt(d));
}

}  // namespace

double FrequencyStack::single_scattering(double r) const {
  // R_1(r) = sigma_s / (4 pi) int_0^d exp(-sigma_t (z + l)) p(-z / l) T(z / l) z / l^3 dz,
  // l = sqrt(r^2 + z^2); with z = r tan(t): sigma_s / (4 pi r) int sin(t) exp(-sigma_t r (tan t +
  // sec t)) p(-sin t) T(sin t) dt over t from the critical angle's asin(mu_c) (no light escapes
  // below mu_c) to atan(d / r), cut where the exponent has fallen by 40 (tan t + sec t =
  // tan(pi / 4 + t / 2)).
  r = std::max(r, r_floor_);
  double deep = 0;  // the layers below
  for (std::size_t l = 1; deep_ && l < layers_.size(); ++l) deep += deep_single_scattering(l, r);
  const double x = 1 + 40 / (sigma_t_ * r);
  const double t_hi = std::min(std::atan(d_ / r), 2 * std::atan(x) - std::numbers::pi / 2);
  const double t_lo = std::asin(mu_c_);
  if (!(t_hi > t_lo)) return deep;
  const QuadratureRule& rule = gauss_legendre(24);
  double sum = 0;
  constexpr int kPanels = 4;
  const double h = (t_hi - t_lo) / kPanels;
  for (int p = 0; p < kPanels; ++p) {
    for (std::size_t q = 0; q < rule.x.size(); ++q) {
      const double tt = t_lo + h * (p + 0.5 * (1 + rule.x[q]));
      const double mu = std::sin(tt);
      const double e = std::exp(-sigma_t_ * r * (std::tan(tt) + 1 / std::cos(tt)));
      sum += 0.5 * h * rule.w[q] * mu * e * hg(g_, -mu) *
             (1 - fresnel_dielectric(mu, n_, n_above_));
    }
  }
  return sigma_s_ * sum / (4 * std::numbers::pi * r) + deep;
}

double FrequencyStack::single_scattering_total() const {
  // R_1(k = 0) = (sigma_s / 2) int_mu_c^1 p(-mu) T(mu) (1 - exp(-sigma_t d (1 + 1 / mu))) /
  // (sigma_t (1 + 1 / mu)) dmu.
  const QuadratureRule& rule = gauss_legendre(64);
  double sum = 0;
  const double half = 0.5 * (1 - mu_c_);
  for (std::size_t q = 0; q < rule.x.size(); ++q) {
    const double mu = mu_c_ + half * (1 + rule.x[q]);
    const double a = sigma_t_ * (1 + 1 / mu);
    const double depth = std::isfinite(d_) ? -std::expm1(-a * d_) : 1.0;
    sum += half * rule.w[q] * hg(g_, -mu) * (1 - fresnel_dielectric(mu, n_, n_above_)) * depth / a;
  }
  double deep = 0;
  for (std::size_t l = 1; deep_ && l < layers_.size(); ++l) deep += deep_single_scattering_total(l);
  return 0.5 * sigma_s_ * sum + deep;
}

namespace {
// cos and tan of the ray in a layer of index n for Snell's invariant s = n_l sin(theta_l).
struct Ray {
  double cos, tan;
};
Ray ray(double s, double n) {
  const double sn = s / n, cs = std::sqrt(std::max(0.0, 1 - sn * sn));
  return {cs, sn / cs};
}
}  // namespace

// The largest Snell invariant s = n sin(theta) of a ray from layer l that escapes: below every
// index above it and the medium above.
double FrequencyStack::escaping_invariant(std::size_t l) const {
  double s_max = std::min(n_above_, layers_[l].n);
  for (std::size_t m = 0; m < l; ++m) s_max = std::min(s_max, layers_[m].n);
  return s_max;
}

// What reaches the surface of a ray leaving layer l upwards with invariant s and cosine mu in
// layer l: the Fresnel transmission of every interface and of the top surface, and the
// attenuation across every layer above (0 when it is totally reflected on the way).
double FrequencyStack::climb(std::size_t l, double s, double mu) const {
  double f = 1, cos_below = mu;  // the ray's cosine in the layer below each interface
  for (std::size_t m = l; m-- > 0;) {
    const Ray ry = ray(s, layers_[m].n);
    if (!(ry.cos > 0)) return 0;
    f *= (1 - fresnel_dielectric(cos_below, layers_[m + 1].n, layers_[m].n)) *
         std::exp(-layers_[m].sigma_t * layers_[m].d / ry.cos);
    cos_below = ry.cos;
  }
  return f * (1 - fresnel_dielectric(cos_below, layers_[0].n, n_above_));
}

// Light scattered once in layer l >= 1 that leaves directly, in space: the beam reaches depth z'
// into the layer with the weight `beam` exp(-sigma_t z'), scatters into the angle theta from the
// upward normal, climbs z' / cos(theta) in the layer and d_m / cos(theta_m) in each layer m above
// (Snell: n_m sin(theta_m) = n_l sin(theta), total reflection = no escape), crosses each
// interface with its Fresnel transmission and leaves at r = z' tan(theta) + sum_m d_m
// tan(theta_m). Per unit area (the ring's 2 pi r dr against the solid angle, at fixed theta
// dr = tan(theta) dz'): R_1(r) = beam sigma_s / (4 pi r) int cos(theta) exp(-sigma_t z' (1 +
// 1 / cos(theta))) p(-cos(theta)) prod_m exp(-sigma_t,m d_m / cos(theta_m)) T(theta) dtheta with
// z'(theta) = (r - L(theta)) / tan(theta), L the lateral run through the layers above, over the
// angles where 0 <= z' <= d (cut where the exponent has fallen by 40).
double FrequencyStack::deep_single_scattering(std::size_t l, double r) const {
  r = std::max(r, r_floor_);
  const ExactLayer& e = layers_[l];
  if (e.beam == 0 || e.sigma_s == 0) return 0;
  const double theta_max = std::asin(std::min(1.0, escaping_invariant(l) / e.n) * (1 - 1e-12));
  auto lateral = [&](double theta) {  // L(theta)
    const double s = e.n * std::sin(theta);
    double L = 0;
    for (std::size_t m = 0; m < l; ++m) L += layers_[m].d * ray(s, layers_[m].n).tan;
    return L;
  };
  // Root of an increasing function on [0, theta_max] by bisection (or an end).
  auto root = [&](const auto& f) {
    double a = 0, b = theta_max;
    if (f(b) <= 0) return b;
    if (f(a) >= 0) return a;
    for (int i = 0; i < 60; ++i) {  // to 1e-18 of the range
      const double c = 0.5 * (a + b);
      (f(c) < 0 ? a : b) = c;
    }
    return 0.5 * (a + b);
  };
  const double theta_hi = root([&](double t) { return lateral(t) - r; });  // z' = 0
  double theta_lo = root([&](double t) {  // the 40 e-folds
    return 40.0 - e.sigma_t * (r - lateral(t)) * (1 + 1 / std::cos(t)) / std::tan(t);
  });
  if (std::isfinite(e.d))
    theta_lo = std::max(theta_lo, root([&](double t) { return e.d * std::tan(t) + lateral(t) - r; }));
  if (!(theta_hi > theta_lo)) return 0;
  const QuadratureRule& rule = gauss_legendre(24);
  constexpr int kPanels = 4;
  const double h = (theta_hi - theta_lo) / kPanels;
  double sum = 0;
  for (int p = 0; p < kPanels; ++p) {
    for (std::size_t q = 0; q < rule.x.size(); ++q) {
      const double t = theta_lo + h * (p + 0.5 * (1 + rule.x[q]));
      const double ct = std::cos(t), s = e.n * std::sin(t);
      const double z = std::max(0.0, (r - lateral(t)) / std::tan(t));
      sum += 0.5 * h * rule.w[q] * ct * std::exp(-e.sigma_t * z * (1 + 1 / ct)) * hg(e.g, -ct) *
             climb(l, s, ct);
    }
  }
  return e.beam * e.sigma_s * sum / (4 * std::numbers::pi * r);
}

// Its total: beam (sigma_s / 2) int p(-mu) T(mu) prod_m exp(-sigma_t,m d_m / mu_m) (1 -
// exp(-sigma_t d (1 + 1 / mu))) / (sigma_t (1 + 1 / mu)) dmu over the cosines that escape.
double FrequencyStack::deep_single_scattering_total(std::size_t l) const {
  const ExactLayer& e = layers_[l];
  if (e.beam == 0 || e.sigma_s == 0) return 0;
  const double sin_max = std::min(1.0, escaping_invariant(l) / e.n);
  const double mu_lo = std::sqrt(std::max(0.0, 1 - sin_max * sin_max));
  const QuadratureRule& rule = gauss_legendre(64);
  const double half = 0.5 * (1 - mu_lo);
  double sum = 0;
  for (std::size_t q = 0; q < rule.x.size(); ++q) {
    const double mu = mu_lo + half * (1 + rule.x[q]);
    const double s = e.n * std::sqrt(std::max(0.0, 1 - mu * mu));
    const double a = e.sigma_t * (1 + 1 / mu);
    sum += half * rule.w[q] * hg(e.g, -mu) *
           (std::isfinite(e.d) ? -std::expm1(-a * e.d) : 1.0) / a * climb(l, s, mu);
  }
  return e.beam * 0.5 * e.sigma_s * sum;
}

FrequencyStack::FrequencyStack(const LayerStack& stack, const FrequencyProfileOptions& options,
                               const Cache& cache)
    : totals_(adding_doubling(stack, options.transport.totals, cache)),
      k0_(options.k0),
      du_(options.du) {
  // The largest delta-M scaled extinction of the stack (delta-M with the totals' number of
  // moments is close to sigma_s (1 - g^16) + sigma_a; this sets only the extent of the nodes).
  // The scale of the finest structure: a mean free path, or the thinnest layer.
  double sigma_t = 0, finest = 0;
  for (const auto& l : stack.layers) {
    sigma_t = std::max(sigma_t, detail::scaled_extinction(l));
    finest = std::max({finest, detail::scaled_extinction(l), 1 / l.thickness});
  }
  k_ = detail::frequency_nodes(options.k_hi * finest, k0_, du_);
  const std::size_t n = k_.size();
  R_ = frequency_response(stack, k_, options.transport);
  // Single scattering in the top layer, exactly (Henyey-Greenstein, in space) and as the solver
  // sees it (delta-M, discrete, in k): the profile is the exact one plus the solver's rest
  // (Nakajima & Tanaka 1988, TMS), scaled so that the total is the adding-doubling R_d.
  const Layer& top = stack.layers.front();
  sigma_s_ = top.sigma_s();
  sigma_t_ = top.sigma_a + sigma_s_;
  g_ = top.g;
  d_ = top.thickness;
  n_ = top.eta;
  n_above_ = stack.eta_above;
  mu_c_ = n_above_ < n_ ? std::sqrt(1 - (n_above_ / n_) * (n_above_ / n_)) : 0.0;
  r_floor_ = 1e-6 / sigma_t_;
  deep_ = options.transport.deep_single_scattering;
  double beam = 1;
  for (std::size_t l = 0; l < stack.layers.size(); ++l) {
    const Layer& ly = stack.layers[l];
    layers_.push_back({ly.sigma_s(), ly.sigma_a + ly.sigma_s(), ly.g, ly.eta, ly.thickness, beam});
    if (l + 1 < stack.layers.size())
      beam *= std::exp(-layers_.back().sigma_t * ly.thickness) *
              (1 - fresnel_dielectric(1.0, ly.eta, stack.layers[l + 1].eta));
  }
  const auto R1 = detail::single_scattering_k(stack, k_, options.transport);
  // Light back along the beam unscattered (a slab's bottom or an index step reflects the beam):
  // a delta at r = 0 in the solver, the same at every k, subtracted in full from the remainder
  // at every node. In space it is drawn as a Gaussian of the fixed width kBallisticWidth (2 um),
  // so it stays inside the first micrometres (accurate.hpp says why 2); any narrow width is
  // consistent with the nodes (the Gaussian's transform B exp(-k^2 w^2 / 4) differs from the
  // delta's B only at k ~ 1 / w, i.e. within ~w of the beam). It used to be 6 / k_hi, which is the top layer's thickness for a
  // thin top (or 1 / sigma_t*, up to 0.25 mm): that spread the delta into the annuli at
  // 0.02-0.09 mm, up to 18 times the true profile of a 14 um slab in air.
  B_ = detail::ballistic_return(stack, options.transport);
  const double rest0 = R_[0] - R1[0] - B_;
  const double scale = rest0 != 0 ? (totals_.R_d - single_scattering_total() - B_) / rest0 : 0.0;
  // The rest's tail beyond k_hi is the pair A (k^2 + b^2)^-q <-> A (r / 2b)^(q-1) K_(q-1)(b r) /
  // (2 pi Gamma(q)) (Gradshteyn & Ryzhik 6.565.4), b = k_hi / 2 (flat below k_hi, so that it does
  // not move the rest at low k), with A and q matching the rest's value and slope at k_hi (the
  // slope of the interpolant, the cubic through the last four nodes), so that the numerical
  // remainder ends at k_hi with zero value and zero slope. With the value alone (q = 1, the
  // 1 / k^2 of double scattering) the remainder ended with a kink, whose transform rang at
  // 2 pi / k_hi with ~5e-7 of R(0.01 mm) at 0.2-1 mm in african skin at 450 nm, where the profile
  // itself is below that.
  b_ = 0.5 * k_.back();
  const auto rest = [&](std::size_t j) { return scale * (R_[j] - R1[j] - B_); };
  const double k_end = k_.back(), rest_end = rest(n - 1);
  q_ = 1;
  if (n >= 4 && rest_end != 0) {
    // d rest / du at the last node (backward 4-point formula), d u / d k = 1 / sqrt(k^2 + k0^2).
    const double d_du = (11 * rest_end - 18 * rest(n - 2) + 9 * rest(n - 3) - 2 * rest(n - 4)) / (6 * du_);
    const double p = -d_du / std::hypot(k_end, k0_) * k_end / rest_end;  // -d ln rest / d ln k
    // -d ln T / d ln k = 2 q k^2 / (k^2 + b^2); the pair holds for 0 < q < 5/2.
    const double q = p * (k_end * k_end + b_ * b_) / (2 * k_end * k_end);
    if (std::isfinite(q)) q_ = std::clamp(q, kTailExponentMin, kTailExponentMax);
  }
  A_ = rest_end * std::pow(k_end * k_end + b_ * b_, q_);
  tail_norm_ = 1 / (2 * std::numbers::pi * std::tgamma(q_) * std::pow(2 * b_, q_ - 1));
  G_.resize(n);
  for (std::size_t j = 0; j < n; ++j) G_[j] = rest(j) - A_ * std::pow(k_[j] * k_[j] + b_ * b_, -q_);
}

double FrequencyStack::tail(double r) const {
  const double rr = std::max(r, r_floor_);
  return A_ * tail_norm_ * std::pow(rr, q_ - 1) * boost::math::cyl_bessel_k(q_ - 1, b_ * rr);
}

double FrequencyStack::singular(double r) const {
  return single_scattering(r) + tail(r) +
         B_ * std::exp(-(r * r) / (kBallisticWidth * kBallisticWidth)) /
             (std::numbers::pi * kBallisticWidth * kBallisticWidth);
}

double FrequencyStack::residual_k(double k) const { return detail::interpolate_in_u(k_, G_, k, k0_, du_); }

std::vector<double> detail::frequency_nodes(double k_hi, double k0, double du) {
  const auto n = std::max<std::size_t>(static_cast<std::size_t>(std::ceil(std::asinh(k_hi / k0) / du)) + 1, 8);
  std::vector<double> k(n);
  for (std::size_t j = 0; j < n; ++j) k[j] = k0 * std::sinh(du * static_cast<double>(j));
  return k;
}

double detail::interpolate_in_u(const std::vector<double>& k_nodes, const std::vector<double>& G, double k,
                                double k0, double du) {
  if (k >= k_nodes.back()) return 0.0;
  constexpr int P = 6;
  const double u = std::asinh(std::abs(k) / k0) / du;
  const long last = static_cast<long>(k_nodes.size()) - 1;
  const long m0 = std::min(static_cast<long>(std::floor(u)) - (P / 2 - 1), last - (P - 1));
  const std::array<double, P> w = lagrange_weights<P>(u - static_cast<double>(m0));
  double out = 0;
  for (int a = 0; a < P; ++a)
    out += w[static_cast<std::size_t>(a)] * G[static_cast<std::size_t>(std::labs(m0 + a))];  // mirror: G(-u) = G(u)
  return out;
}

}  // namespace skin::transport::accurate
