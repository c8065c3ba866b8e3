// Adding-doubling for layered Henyey-Greenstein media (docs/accurate-solver.md, section 2).
//
// Representation. Directions are quadrature streams labelled by the transverse invariant
// s = n sin(theta), which Snell's law conserves across every interface, so one set of streams
// serves all layers and every Fresnel boundary is diagonal. A stream with s < n propagates in a
// medium of index n with cosine mu = sqrt(1 - (s / n)^2); one with s > n does not exist there
// (it is totally reflected at the interface). The quadrature is built in the cosine mu_ref of
// the layer of highest index n_ref, split into panels at every index of the stack (so each
// medium's critical angle is a panel edge): Gauss-Radau with its fixed node at mu_ref = 1 (the
// normally incident beam) in the first panel, Gauss-Legendre in the others.
//
// Matrices act on stream fluxes (power per stream crossing a horizontal plane, as a fraction of
// the incident power): R(i, j) is the fraction of the flux in stream j that leaves in stream i.
// With the flux weight a_i of stream i (sum_i a_i = int_0^1 2 mu dmu = 1 in each medium, and
// a_i^(n) = (n_ref / n)^2 a_i^(ref) because d(mu^2) = d(s^2) / n^2), the layer equations are
//   dF+/dtau = -A F+ + B F-,   -dF-/dtau = -A F- + B F+,
//   A = diag(1 / mu) - omega C P+ M^-1,  B = omega C P- M^-1,  C = diag(a / (4 mu)),
// where P+(i, j) = p0(mu_i, mu_j) and P-(i, j) = p0(-mu_i, mu_j) are the azimuthally averaged
// phase function (normalised to (1/2) int_-1^1 p0 dmu = 1). With these flux matrices, a
// homogeneous layer looks the same from above and from below, boundaries are diagonal, and the
// adding rules are plain matrix algebra (no quadrature weights inside the products).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <ostream>
#include <vector>

#include "ad_core.hpp"
#include "skin/transport/accurate.hpp"
#include "skin/transport/diffusion.hpp"
#include "skin/physics/fresnel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/quadrature.hpp"

namespace skin::transport::accurate {

using skin::util::InputError;
using skin::util::QuadratureRule;
using skin::util::gauss_legendre;
using skin::util::gauss_radau;
using skin::util::lagrange4_weights;


using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::fresnel_dielectric;


std::ostream& operator<<(std::ostream& os, const Options& o) {
  return os << "accurate::Options{quadrature_points=" << o.quadrature_points << '}';
}


namespace detail {

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

Streams make_streams(const LayerStack& stack, int points) {
  double n_ref = 0;
  for (const auto& l : stack.layers) n_ref = std::max(n_ref, l.eta);
  // Panel edges in s: every index of the stack below n_ref (streams with s > n_ref exist in no
  // layer, so a higher index of the surroundings bounds nothing).
  std::vector<double> edges;
  auto add_edge = [&](double n) {
    if (n < n_ref * (1 - 1e-12)) edges.push_back(n);
  };
  add_edge(stack.eta_above);
  if (!stack.semi_infinite()) add_edge(stack.eta_below);
  for (const auto& l : stack.layers) add_edge(l.eta);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end(),
                          [](double a, double b) { return std::abs(a - b) <= 1e-12 * b; }),
              edges.end());
  edges.push_back(n_ref);

  Streams st;
  st.n_ref = n_ref;
  st.edges = edges;
  double s_lo = 0;
  for (std::size_t p = 0; p < edges.size(); ++p) {
    const double s_hi = edges[p];
    // The panel's streams propagate in the layers of index >= s_hi; in the lowest of them, of
    // index n_low, their cosine mu_low runs from sqrt(1 - (s_hi / n_low)^2) (0 if n_low = s_hi:
    // grazing at that layer's critical angle) to sqrt(1 - (s_lo / n_low)^2). The rule is laid
    // out in mu_low: the radiance in that layer is a smooth function of it, and so is the cosine
    // in every layer of higher index (mu = sqrt(1 - (n_low / n)^2 (1 - mu_low^2)) is smooth for
    // n > n_low), whereas a rule in the cosine of the highest-index layer would meet a
    // square-root edge in every lower one (with 8 points, R_d and T_d of stacks with internal
    // index steps were then off by up to 13 %). The media around the stack do not count: light
    // does not scatter there. Flux weights: n^2 mu dmu is the same in every medium, so
    // a_ref = (n_low / n_ref)^2 2 mu_low dmu_low.
    double n_low = n_ref;
    for (const auto& l : stack.layers)
      if (l.eta >= s_hi * (1 - 1e-12)) n_low = std::min(n_low, l.eta);
    const double top = std::sqrt(std::max(0.0, 1.0 - (s_lo / n_low) * (s_lo / n_low)));
    const double bottom = std::sqrt(std::max(0.0, 1.0 - (s_hi / n_low) * (s_hi / n_low)));
    const QuadratureRule& rule = p == 0 ? gauss_radau(points) : gauss_legendre(points);
    const double half = 0.5 * (top - bottom), mid = 0.5 * (top + bottom);
    if (p == 0) {
      // Quadrature points per unit of the reference cosine in the panel around the normal.
      const double mu_lo = std::sqrt(std::max(0.0, 1.0 - (s_hi / n_ref) * (s_hi / n_ref)));
      st.escape_density = points / (1.0 - mu_lo);
    }
    const double ratio2 = (n_low / n_ref) * (n_low / n_ref);
    // Descending x (ascending s) within the panel: the propagating streams of every medium are
    // then the leading ones.
    for (int i = points - 1; i >= 0; --i) {
      const double mu = mid + half * rule.x[static_cast<std::size_t>(i)];
      const double w = half * rule.w[static_cast<std::size_t>(i)];
      st.s2.push_back(n_low * n_low * (1.0 - mu * mu));
      st.a_ref.push_back(ratio2 * 2.0 * mu * w);
    }
    s_lo = s_hi;
  }
  st.N = static_cast<int>(st.s2.size());
  return st;
}

int propagating(const Streams& st, double n) {
  int m = 0;
  while (m < st.N && st.s2[static_cast<std::size_t>(m)] < n * n) ++m;
  return m;
}

namespace {

// Semi-infinite reflection matrices at the nodes x_j = j / kNodes, x = sqrt(1 - omega), filled on
// demand (see table_at below).
struct SemiInfiniteTable {
  static constexpr int kNodes = 256;
  std::vector<Mat> R = std::vector<Mat>(kNodes + 1);
  // Each node is filled once, by whichever thread needs it first.
  std::unique_ptr<std::once_flag[]> filled = std::make_unique<std::once_flag[]>(kNodes + 1);
};

// Finite-layer reflection and transmission on the nodes (x_i, tau_j): x_i = i / kX (x = sqrt(1 -
// omega)), tau_j = kTauMin 2^(j / kPerOctave) (delta-M scaled optical depth), filled on demand
// (see slab_table_at below).
struct SlabTable {
  static constexpr int kX = 128;
  static constexpr int kPerOctave = 8;
  static constexpr double kTauMin = 1.0 / 8;
  // Up to tau = 2^9 kTauMin = 64: beyond, the diffusive decay exp(-kappa tau), kappa ~ x, varies
  // too fast across an x cell for cubic interpolation (the caller then doubles directly).
  static constexpr int kTau = 9 * kPerOctave;
  // The deepest layer read from it (slab_table_at needs a node on either side: u <= kTau - 1).
  static constexpr double kTauTop = 58.0;
  std::vector<LayerRT> nodes = std::vector<LayerRT>((kX + 1) * (kTau + 1));
  std::unique_ptr<std::once_flag[]> filled = std::make_unique<std::once_flag[]>((kX + 1) * (kTau + 1));
};

// Angular data of one medium with the layer tables on it. Kept in a Cache (a spectrum repeats
// the same geometry).
struct Geometry : Angular {
  mutable SemiInfiniteTable table;
  mutable SlabTable slab_table;
};

struct GeometryKey {
  double n, g, n_ref;
  int points;
  std::vector<double> edges;
  bool operator==(const GeometryKey&) const = default;
};

}  // namespace

Angular angular(const Streams& st, double n, double g, int modes) {
  Angular geo;
  const int m = propagating(st, n);
  geo.m = m;
  geo.mu.resize(m);
  geo.c.resize(m);
  geo.s.resize(m);
  const double scale = (st.n_ref / n) * (st.n_ref / n);
  for (int i = 0; i < m; ++i) {
    const auto si = static_cast<std::size_t>(i);
    geo.mu(i) = std::sqrt(std::max(0.0, 1.0 - st.s2[si] / (n * n)));
    geo.s(i) = std::sqrt(st.s2[si]) / n;
    geo.c(i) = scale * st.a_ref[si] / (4.0 * geo.mu(i));
  }
  // Delta-M (Wiscombe 1977): the HG moments g^l are kept for l < 2m; the forward peak beyond
  // them, f = g^(2m), is treated as unscattered. chi_l = (g^l - f) / (1 - f).
  // Number of moments: 2 per stream, but no more than the panel around the normal (where the
  // beam enters and the light leaves) resolves: 2 per quadrature point per unit of cosine there.
  // Without this cap a wide escape panel next to a narrow one (an index step of a few per cent)
  // under-resolves the kept forward peak and R_d goes wrong by up to 10 %
  // (docs/accurate-solver.md, section 2).
  const int L = std::max(2, std::min(2 * m, static_cast<int>(std::floor(2 * st.escape_density))));
  geo.f = std::pow(g, L);
  if (std::abs(g) < 1e-300) geo.f = 0;
  Vec chi(L);
  double gl = 1;
  for (int l = 0; l < L; ++l) {
    chi(l) = (gl - geo.f) / (1 - geo.f);
    gl *= g;
  }
  // Azimuthal order a of the redistribution (a = 0: the azimuthal average that totals need):
  // p_a(mu, mu') = sum_{l >= a} (2l + 1) chi_l Pbar_l^a(mu) Pbar_l^a(mu'), with the normalised
  // associated Legendre functions Pbar_l^a = sqrt((l - a)! / (l + a)!) P_l^a (addition theorem;
  // order a of cos(a (phi - phi')) enters the radiance's order a with the same factor 1/2 as
  // order 0). Pbar_l^a(-x) = (-1)^(l + a) Pbar_l^a(x).
  for (int a = 0; a < modes; ++a) {
    Mat Pl = Mat::Zero(m, L);
    for (int i = 0; i < m; ++i) {
      const double x = geo.mu(i), sx = std::sqrt(std::max(0.0, 1.0 - x * x));
      double pmm = 1;  // Pbar_a^a
      for (int k = 1; k <= a; ++k) pmm *= std::sqrt((2.0 * k - 1) / (2.0 * k)) * sx;
      if (a >= L) break;
      Pl(i, a) = pmm;
      if (a + 1 < L) Pl(i, a + 1) = x * std::sqrt(2.0 * a + 1) * pmm;
      for (int l = a + 2; l < L; ++l) {
        const double dl = l;
        Pl(i, l) = ((2 * dl - 1) * x * Pl(i, l - 1) -
                    std::sqrt((dl - 1) * (dl - 1) - double(a) * a) * Pl(i, l - 2)) /
                   std::sqrt(dl * dl - double(a) * a);
      }
    }
    Vec wplus(L), wminus(L);
    for (int l = 0; l < L; ++l) {
      wplus(l) = l < a ? 0.0 : (2 * l + 1) * chi(l);
      wminus(l) = ((l + a) % 2 == 0 ? 1.0 : -1.0) * wplus(l);
    }
    geo.Pplus.push_back(Pl * wplus.asDiagonal() * Pl.transpose());
    geo.Pminus.push_back(Pl * wminus.asDiagonal() * Pl.transpose());
  }
  // Renormalise each incident direction so that the quadrature conserves energy exactly
  // (Wiscombe 1976): sum_i c_i (P+ + P-)(i, j) = 1. Order 0 only (the others carry no energy).
  for (int j = 0; j < m; ++j) {
    const double sum = geo.c.dot(geo.Pplus[0].col(j) + geo.Pminus[0].col(j));
    if (sum > 0) {
      geo.Pplus[0].col(j) /= sum;
      geo.Pminus[0].col(j) /= sum;
    }
  }
  return geo;
}

namespace {

Geometry build_geometry(const Streams& st, double n, double g) {
  Geometry geo;
  static_cast<Angular&>(geo) = angular(st, n, g, 1);
  return geo;
}

}  // namespace

}  // namespace detail

struct Cache::Impl {
  std::mutex mutex;
  // The last 16 geometries used (a spectrum needs one or two); entries are shared, so that an
  // evicted one stays valid for the solve that holds it.
  std::deque<std::pair<detail::GeometryKey, std::shared_ptr<const detail::Geometry>>> entries;
};

Cache::Cache() : impl_(std::make_unique<Impl>()) {}
Cache::~Cache() = default;

namespace detail {
namespace {

std::shared_ptr<const Geometry> geometry(const Cache& cache, const Streams& st, double n, double g,
                                         int points) {
  GeometryKey key{n, g, st.n_ref, points, st.edges};
  Cache::Impl& c = cache.impl();
  {
    const std::lock_guard lock(c.mutex);
    for (const auto& e : c.entries)
      if (e.first == key) return e.second;
  }
  auto geo = std::make_shared<const Geometry>(build_geometry(st, n, g));  // outside the lock
  const std::lock_guard lock(c.mutex);
  for (const auto& e : c.entries)
    if (e.first == key) return e.second;  // another thread built it meanwhile
  if (c.entries.size() >= 16) c.entries.pop_front();
  c.entries.emplace_back(std::move(key), geo);
  return geo;
}

}  // namespace

// The diamond-initialised thin layer of optical thickness dtau (Wiscombe 1976; Prahl 1995,
// section 3): derivatives at the layer's midplane, solved with the sum and difference of the
// two flux directions, X = (P - C)^-1 (Q + C), Y = (P + C)^-1 (Q - C), R = (X - Y) / 2,
// T = (X + Y) / 2 with P = I + h A, Q = I - h A, C = h B, h = dtau / 2. It conserves energy
// exactly; its error is second order in dtau (the direct beam, for instance, is attenuated by
// the Pade approximant (1 - h / mu) / (1 + h / mu) of exp(-dtau / mu)).
LayerRT diamond(const Mat& A, const Mat& B, double dtau) {
  const auto m = A.rows();
  const double h = 0.5 * dtau;
  const Mat I = Mat::Identity(m, m);
  const Mat P = I + h * A, Q = I - h * A, C = h * B;
  const Mat X = (P - C).partialPivLu().solve(Q + C);
  const Mat Y = (P + C).partialPivLu().solve(Q - C);
  return {0.5 * (X - Y), 0.5 * (X + Y)};
}

// One doubling of a homogeneous layer (it is the same seen from above and from below):
// R2 = R + T R (I - R R)^-1 T,  T2 = T (I - R R)^-1 T.
void double_once(LayerRT& rt) {
  const auto m = rt.R.rows();
  const Mat Xs = (Mat::Identity(m, m) - rt.R * rt.R).partialPivLu().solve(rt.T);
  rt.R.noalias() += rt.T * (rt.R * Xs);
  rt.T = rt.T * Xs;
}

namespace {

void scattering_matrices(const Geometry& geo, double omega, Mat& A, Mat& B) {
  const Vec inv_mu = geo.mu.cwiseInverse();
  A = -omega * geo.c.asDiagonal() * geo.Pplus[0] * inv_mu.asDiagonal();
  A.diagonal() += inv_mu;
  B = omega * geo.c.asDiagonal() * geo.Pminus[0] * inv_mu.asDiagonal();
}

// Semi-infinite reflection by doubling until the transmitted flux is negligible: what lies deeper
// then changes R by at most T^2 (kSemiInfiniteT^2). The cap covers omega = 1 (no absorption),
// where transmission falls only like 1 / tau; 2^60 times the initial depth leaves ~1e-17 there.
Mat semi_infinite_direct(const Geometry& geo, double omega) {
  Mat A, B;
  scattering_matrices(geo, omega, A, B);
  LayerRT rt = diamond(A, B, kThinnest);
  for (int i = 0; i < 60; ++i) {
    if (rt.T.colwise().sum().maxCoeff() < kSemiInfiniteT) break;
    double_once(rt);
  }
  return rt.R;
}

// The semi-infinite reflection depends on the single-scattering albedo alone (for a given
// geometry), smoothly in x = sqrt(1 - omega) (as the closed forms do: the semi-infinite albedo
// is 1 - H(1) sqrt(1 - omega) for isotropic scattering). Tabulated lazily on a uniform grid in x
// and interpolated with 4-point Lagrange polynomials: a spectrum then pays for ~20 doublings at
// a few table nodes instead of at every wavelength.
Mat table_at(const Geometry& geo, double omega) {
  constexpr int K = SemiInfiniteTable::kNodes;
  auto node = [&](int j) -> const Mat& {
    const auto jj = static_cast<std::size_t>(j);
    std::call_once(geo.table.filled[jj], [&] {
      const double x = static_cast<double>(j) / K;
      geo.table.R[jj] = semi_infinite_direct(geo, 1.0 - x * x);
    });
    return geo.table.R[jj];
  };
  const double x = std::sqrt(std::max(0.0, 1.0 - omega)) * K;
  const int j0 = std::clamp(static_cast<int>(std::floor(x)) - 1, 0, K - 3);
  const double t = x - j0;  // position from node j0 in node units, in [0, 3]
  const std::array<double, 4> w = lagrange4_weights(t);
  Mat out = Mat::Zero(geo.m, geo.m);
  for (int a = 0; a < 4; ++a) out += w[a] * node(j0 + a);
  return out;
}

// A finite homogeneous layer by diamond initialisation (tau / 2^k <= kThinnest) and k doublings.
LayerRT finite_direct(const Geometry& geo, double omega, double tau) {
  int k = 0;
  double dtau = tau;
  while (dtau > kThinnest) {
    dtau *= 0.5;
    ++k;
  }
  Mat A, B;
  scattering_matrices(geo, omega, A, B);
  LayerRT rt = diamond(A, B, dtau);
  for (int i = 0; i < k; ++i) {
    double_once(rt);
    if (rt.T.colwise().sum().maxCoeff() < 1e-30) break;  // thicker than infinite
  }
  return rt;
}

// Finite layers depend on (omega, tau) alone for a given geometry, smoothly in x = sqrt(1 -
// omega) and in log tau. Bicubic (4 x 4 point Lagrange) interpolation on the lazily filled
// SlabTable; false when tau is outside the table (the caller then doubles directly). A spectrum
// of one parameter set touches a few hundred nodes; later spectra of nearby parameters reuse
// them, so a warm table costs two 4 x 4 weighted sums of matrices instead of ~10 doublings.
bool slab_table_at(const Geometry& geo, double omega, double tau, LayerRT& out) {
  using Tab = SlabTable;
  const double u = std::log2(tau / Tab::kTauMin) * Tab::kPerOctave;
  if (!(u >= 1.0 && u <= Tab::kTau - 1.0)) return false;
  const double x = std::sqrt(std::max(0.0, 1.0 - omega)) * Tab::kX;
  const int i0 = std::clamp(static_cast<int>(std::floor(x)) - 1, 0, Tab::kX - 3);
  const int j0 = std::clamp(static_cast<int>(std::floor(u)) - 1, 0, Tab::kTau - 3);
  const std::array<double, 4> wx = lagrange4_weights(x - i0), wt = lagrange4_weights(u - j0);
  out.R = Mat::Zero(geo.m, geo.m);
  out.T = Mat::Zero(geo.m, geo.m);
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      const int i = i0 + a, j = j0 + b;
      const auto k = static_cast<std::size_t>(i * (Tab::kTau + 1) + j);
      LayerRT& node = geo.slab_table.nodes[k];
      std::call_once(geo.slab_table.filled[k], [&] {
        const double xi = static_cast<double>(i) / Tab::kX;
        node = finite_direct(geo, 1.0 - xi * xi,
                             Tab::kTauMin * std::exp2(static_cast<double>(j) / Tab::kPerOctave));
      });
      const double w = wx[a] * wt[b];
      out.R += w * node.R;
      out.T += w * node.T;
    }
  }
  return true;
}

}  // namespace

// The most doublings of a layer read from the finite-layer table (layer_rt).
constexpr int kMaxTableDoublings = 3;

// Reflection and transmission (flux form, m x m) of one homogeneous layer of optical thickness
// tau (delta-M scaled) and single-scattering albedo omega: diamond initialisation and doubling.
// A semi-infinite layer comes from the table (or by direct doubling when `tabulate` is false).
LayerRT layer_rt(const Streams& st, const Layer& layer, int points, bool tabulate,
                 const Cache& cache) {
  const auto held = geometry(cache, st, layer.eta, layer.g, points);
  const Geometry& geo = *held;
  const double sigma_s = layer.sigma_s() * (1 - geo.f);  // delta-M scaled [1/mm]
  const double sigma_t = layer.sigma_a + sigma_s;
  const double omega = sigma_s / sigma_t;
  if (layer.semi_infinite()) {
    LayerRT rt;
    if (tabulate) {
      rt.R = table_at(geo, omega);
    } else {
      rt.R = semi_infinite_direct(geo, omega);
    }
    rt.T = Mat::Zero(geo.m, geo.m);
    return rt;
  }
  const double tau = sigma_t * layer.thickness;
  if (tabulate) {
    LayerRT rt;
    if (slab_table_at(geo, omega, tau, rt)) return rt;
    // Thicker than the table, up to 2^kMaxTableDoublings times its depth: read it at tau / 2^k
    // (the first halving inside it) and double k times, instead of doubling from the diamond
    // layer (~log2(tau / kThinnest) doublings: a 0.4 mm epidermis at g 0.915 is tau ~ 400, 12
    // doublings at each wavelength of a spectrum; the domain's benchmark draw 2's R_d spectrum
    // 57 -> 16 ms). Each doubling carries the table's interpolation error on, and a nearly
    // conservative layer accumulates it, so the doublings are capped: against direct doubling
    // R_d within 3.8e-4, T_d 4e-3 (albedo 0.999; Limits.ThickSlabsFromTheTableMatchDirectDoubling),
    // the domain's thick skin within 9.5e-5 of R_d.
    int k = 0;
    double t = tau;
    while (t > SlabTable::kTauTop) {
      t *= 0.5;
      ++k;
    }
    if (k > 0 && k <= kMaxTableDoublings && slab_table_at(geo, omega, t, rt)) {
      for (int i = 0; i < k; ++i) {
        double_once(rt);
        if (rt.T.colwise().sum().maxCoeff() < 1e-30) break;  // thicker than infinite
      }
      return rt;
    }
  }
  return finite_direct(geo, omega, tau);
}

// Diagonal boundary between media of index n_a (above) and n_b (below) on the stream set.
Boundary boundary(const Streams& st, double n_a, double n_b) {
  Boundary b;
  b.r = Vec::Zero(st.N);
  b.t = Vec::Zero(st.N);
  for (int i = 0; i < st.N; ++i) {
    const double s2 = st.s2[static_cast<std::size_t>(i)];
    const bool in_a = s2 < n_a * n_a, in_b = s2 < n_b * n_b;
    if (in_a && in_b) {
      const double mu_a = std::sqrt(std::max(0.0, 1.0 - s2 / (n_a * n_a)));
      const double F = fresnel_dielectric(mu_a, n_a, n_b);
      b.r(i) = F;
      b.t(i) = 1 - F;
    } else if (in_a || in_b) {
      b.r(i) = 1;  // total internal reflection on the side where the stream exists
    }
  }
  return b;
}

}  // namespace detail

namespace {
using detail::Mat;
using detail::Vec;

void validate_options(const Options& o) {
  if (o.quadrature_points != 0 && (o.quadrature_points < 2 || o.quadrature_points > 64))
    throw InputError("quadrature-points = " + std::to_string(o.quadrature_points) +
                     " is out of range: must be 0 (automatic) or in [2, 64]");
}

}  // namespace

// Puts a symmetric element (R_e, T_e) on top of `b` (van de Hulst's adding equations):
//   X = (I - R_e R_b)^-1 T_e,  R = R_e + T_e R_b X,  T = T_b X.
void detail::add_on_top(Below& b, const Mat& Re, const Mat& Te, bool need_T) {
  const auto N = b.R.rows();
  const Mat X = (Mat::Identity(N, N) - Re * b.R).partialPivLu().solve(Te);
  Mat R = Re + Te * b.R * X;
  if (need_T) b.T = b.T * X;
  b.R = std::move(R);
}

int detail::quadrature_points(const LayerStack& stack, const Options& options,
                              bool frequency_domain) {
  stack.validate();
  validate_options(options);
  bool index_steps = false, forward = false, strong = false;
  for (const auto& l : stack.layers) {
    index_steps = index_steps || l.eta != stack.layers.front().eta;
    forward = forward || l.g > kForwardG;
    strong = strong || l.g > kStrongForwardG;
  }
  return options.quadrature_points != 0 ? options.quadrature_points
         : index_steps                  ? kIndexStepQuadraturePoints
         : forward && frequency_domain && !strong ? kForwardQuadraturePoints
         : forward                      ? kForwardTotalsQuadraturePoints
                                        : kDefaultQuadraturePoints;
}

// Matrices of `blocks` blocks of the stream set (block-major: entry b * N + i is stream i of
// block b; the azimuthal orders of the frequency-domain solver, sfd.cpp): a layer's m x m blocks
// go to the leading streams of each block, a boundary's diagonal repeats in every block.
namespace {
Mat embed(const Mat& small, int N, int blocks) {
  const auto m = small.rows() / blocks;
  Mat big = Mat::Zero(N * blocks, N * blocks);
  for (int a = 0; a < blocks; ++a)
    for (int b = 0; b < blocks; ++b)
      big.block(a * N, b * N, m, m) = small.block(a * m, b * m, m, m);
  return big;
}
Vec repeat(const Vec& v, int blocks) { return v.replicate(blocks, 1); }
}  // namespace

Vec detail::escape_weights(const Streams& st, const LayerStack& stack) {
  return boundary(st, stack.eta_above, stack.layers.front().eta).t;
}

detail::Below detail::add_stack(const LayerStack& stack, const Streams& st, int blocks,
                                const std::function<LayerRT(std::size_t)>& layer) {
  const int N = st.N, NB = N * blocks;
  const auto& ls = stack.layers;
  const bool semi = stack.semi_infinite();
  auto add_boundary = [&](Below& below, double n_a, double n_b, bool need_T) {
    const auto b = boundary(st, n_a, n_b);
    add_on_top(below, Mat(repeat(b.r, blocks).asDiagonal()),
               Mat(repeat(b.t, blocks).asDiagonal()), need_T);
  };
  Below below;
  below.R = Mat::Zero(NB, NB);
  below.T = Mat::Zero(NB, NB);
  std::size_t i = ls.size();
  if (semi) {
    --i;
    below.R = embed(layer(i).R, N, blocks);
    if (i > 0 && ls[i - 1].eta != ls[i].eta)  // the interface above the half-space
      add_boundary(below, ls[i - 1].eta, ls[i].eta, false);
  } else {
    const auto b = boundary(st, ls.back().eta, stack.eta_below);
    below.R = repeat(b.r, blocks).asDiagonal();
    below.T = repeat(b.t, blocks).asDiagonal();
  }
  while (i > 0) {
    --i;
    const auto rt = layer(i);
    add_on_top(below, embed(rt.R, N, blocks), embed(rt.T, N, blocks), !semi);
    if (i > 0 && ls[i - 1].eta != ls[i].eta) add_boundary(below, ls[i - 1].eta, ls[i].eta, !semi);
  }
  return below;
}

Vec detail::under_surface(const LayerStack& stack, const Streams& st, int blocks,
                          const Below& below) {
  // The beam enters stream 0 (mu = 1) of block 0 with unit flux; light reflected back up is
  // partly reflected down again by the surface (diagonal r): D = (I - r R_below)^-1 e_0.
  const auto top = boundary(st, stack.eta_above, stack.layers.front().eta);
  const auto NB = below.R.rows();
  Vec e0 = Vec::Zero(NB);
  e0(0) = 1;
  const Mat M = Mat::Identity(NB, NB) - repeat(top.r, blocks).asDiagonal() * below.R;
  return M.partialPivLu().solve(e0);
}

Totals detail::solve(const LayerStack& stack, const Options& options, bool options_tabulate,
                     const Cache& cache) {
  const int points = quadrature_points(stack, options);
  const Streams st = make_streams(stack, points);
  const Below below = add_stack(stack, st, 1, [&](std::size_t i) {
    return layer_rt(st, stack.layers[i], points, options_tabulate, cache);
  });
  // Light that escapes: R_d = t . (R_below D),  T_d = sum(T_below D).
  const Vec D = under_surface(stack, st, 1, below);
  Totals out;
  out.R_specular = fresnel_dielectric(1.0, stack.eta_above, stack.layers.front().eta);
  out.R_d = escape_weights(st, stack).dot(below.R * D);
  out.T_d = stack.semi_infinite() ? 0.0 : (below.T * D).sum();
  return out;
}

Totals adding_doubling(const LayerStack& stack, const Options& options, const Cache& cache) {
  return detail::solve(stack, options, true, cache);
}

Totals adding_doubling(const LayerStack& stack, const Options& options) {
  return adding_doubling(stack, options, Cache());
}

}  // namespace skin::transport::accurate
