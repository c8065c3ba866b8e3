#include "skin/transport/profile.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <boost/math/quadrature/gauss.hpp>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <ostream>

#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"

namespace skin::transport {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::lagrange4_weights;
using skin::util::require_non_negative;
using skin::util::require_positive;

using skin::physics::ChannelWeights;
using skin::physics::Spectrum;
using skin::physics::WavelengthGrid;

namespace {
void require_radius_in_range(const char* name, double r) {
  if (!(r <= kMaxRadius))
    throw InputError(std::string(name) + " = " + format_number(r) + " mm is out of range: allowed at most " +
                     format_number(kMaxRadius) + " mm");
}
}  // namespace

RadialGrid RadialGrid::logarithmic(double r_min, double r_max, std::size_t n) {
  require_positive("radius-min", r_min, "mm");
  require_positive("radius-max", r_max, "mm");
  require_radius_in_range("radius-max", r_max);
  if (r_max < r_min)
    throw InputError("radius-max = " + format_number(r_max) + " mm is out of range: must be >= radius-min = " + format_number(r_min) + " mm");
  if (n < 2 || n > 1000000)
    throw InputError("samples = " + std::to_string(n) + " is out of range: allowed range is [2, 1000000]");
  RadialGrid g;
  g.r.resize(n);
  const double a = std::log(r_min), b = std::log(r_max);
  for (std::size_t i = 0; i < n; ++i)
    g.r[i] = std::exp(a + (b - a) * static_cast<double>(i) / static_cast<double>(n - 1));
  g.r.front() = r_min;
  g.r.back() = r_max;
  return g;
}

RadialGrid RadialGrid::linear(double r_max, std::size_t n) {
  require_positive("radius-max", r_max, "mm");
  require_radius_in_range("radius-max", r_max);
  if (n < 2 || n > 1000000)
    throw InputError("samples = " + std::to_string(n) + " is out of range: allowed range is [2, 1000000]");
  RadialGrid g;
  g.r.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    g.r[i] = r_max * static_cast<double>(i) / static_cast<double>(n - 1);
  return g;
}

RadialGrid RadialGrid::from(std::vector<double> r) {
  for (std::size_t i = 0; i < r.size(); ++i) {
    require_non_negative("radius", r[i], "mm");
    require_radius_in_range("radius", r[i]);
    if (i > 0 && !(r[i] > r[i - 1]))
      throw InputError("radius = " + format_number(r[i]) + " mm is out of range: radii must increase (previous " + format_number(r[i - 1]) + " mm)");
  }
  RadialGrid g;
  g.r = std::move(r);
  return g;
}

std::ostream& operator<<(std::ostream& os, const RadialGrid& g) {
  os << "RadialGrid[" << g.size() << " radii";
  if (!g.r.empty()) os << ", " << g.r.front() << ".." << g.r.back() << " mm";
  return os << ']';
}

std::ostream& operator<<(std::ostream& os, const RgbProfile& p) {
  os << "RgbProfile{" << p.radii << ", R_d=(" << p.R_d[0] << ", " << p.R_d[1] << ", " << p.R_d[2]
     << ")";
  for (std::size_t j = 0; j < p.radii.size() && j < 4; ++j)
    os << ", R(" << p.radii.r[j] << ")=(" << p.R[0][j] << ", " << p.R[1][j] << ", " << p.R[2][j]
       << ")";
  return os << '}';
}

// Product integration. G(k) is smooth, so it is sampled only at a coarse set of frequencies
// k_m = k0 sinh(m du) (dense near k = 0, where G varies on the scale of sigma_tr, sparse where it
// has decayed) and interpolated between them by 4-point Lagrange interpolation in u = asinh(k/k0)
// (G is even in k, hence in u, which gives the stencil at u = 0 its mirror points). The
// interpolant is integrated against J0(k r) k / (2 pi) by Gauss-Legendre panels no wider than two
// periods of J0 at the largest radius. Both steps are linear in the samples, so they collapse
// into one matrix W (radii x samples): R_numerical(r_j) = sum_m W[j][m] G(k_m). W depends only on
// the radii and k_max, and is cached.
struct ProfileSolver::Quadrature {
  double k_max = 0;
  std::vector<double> k;  // sample frequencies k_m [rad/mm]
  Eigen::MatrixXd M;      // W: radii x samples
};

ProfileSolver::ProfileSolver(RadialGrid radii) : radii_(std::move(radii)) {
  if (radii_.size() == 0) throw InputError("radius: at least one radius is needed");
}
ProfileSolver::~ProfileSolver() = default;
ProfileSolver::ProfileSolver(ProfileSolver&&) noexcept = default;
ProfileSolver& ProfileSolver::operator=(ProfileSolver&&) noexcept = default;

std::size_t ProfileSolver::nodes_used() const { return quads_.empty() ? 0 : quads_.back()->k.size(); }

namespace {
constexpr double kK0 = 0.3;    // [rad/mm]: sample spacing near k = 0 is kK0 * kDu
constexpr double kDu = 0.04;   // spacing in u: interpolation error below 1e-6 of R (tested)
}  // namespace

const ProfileSolver::Quadrature& ProfileSolver::quadrature_for(double k_max) {
  constexpr std::size_t kKept = 4;
  for (std::size_t i = 0; i < quads_.size(); ++i)
    if (quads_[i]->k_max == k_max) {
      std::rotate(quads_.begin() + static_cast<std::ptrdiff_t>(i), quads_.begin() + static_cast<std::ptrdiff_t>(i) + 1, quads_.end());
      return *quads_.back();
    }
  auto q = std::make_unique<Quadrature>();
  q->k_max = k_max;
  const auto n_samples = static_cast<std::size_t>(std::ceil(std::asinh(k_max / kK0) / kDu)) + 1;
  q->k.resize(n_samples);
  for (std::size_t m = 0; m < n_samples; ++m) q->k[m] = kK0 * std::sinh(kDu * static_cast<double>(m));
  const double k_end = q->k.back();

  constexpr int kOrder = 10;
  using GL = boost::math::quadrature::gauss<double, kOrder>;
  const double r_max = radii_.max();
  double h = k_end / 16.0;
  if (r_max > 0) h = std::min(h, 4.0 * std::numbers::pi / r_max);
  const auto panels = static_cast<std::size_t>(std::ceil(k_end / h));
  h = k_end / static_cast<double>(panels);
  const auto& xa = GL::abscissa();
  const auto& wa = GL::weights();
  const auto nr = static_cast<Eigen::Index>(radii_.size());
  q->M = Eigen::MatrixXd::Zero(nr, static_cast<Eigen::Index>(n_samples));
  Eigen::VectorXd column(nr);
  const auto last = static_cast<long>(n_samples) - 1;
  for (std::size_t p = 0; p < panels; ++p) {
    const double mid = (static_cast<double>(p) + 0.5) * h, half = 0.5 * h;
    for (std::size_t i = 0; i < xa.size(); ++i) {
      for (int sgn : {-1, 1}) {
        const double kn = mid + sgn * half * xa[i];
        const double wn = half * wa[i] * kn / (2.0 * std::numbers::pi);
        // J0 from the C library (glibc's j0: accurate to a few ulp and far faster than
        // std::cyl_bessel_j).
        for (Eigen::Index j = 0; j < nr; ++j)
          column(j) = wn * ::j0(kn * radii_.r[static_cast<std::size_t>(j)]);
        // Lagrange stencil in u around this node.
        const double u = std::asinh(kn / kK0) / kDu;
        long m0 = static_cast<long>(std::floor(u)) - 1;
        m0 = std::min(m0, last - 3);
        const double t = u - static_cast<double>(m0);  // position within points m0..m0+3
        const std::array<double, 4> l = lagrange4_weights(t);
        for (int a = 0; a < 4; ++a) {
          const long m = std::labs(m0 + a);  // mirror: G(-u) = G(u)
          q->M.col(m) += l[a] * column;
        }
      }
    }
  }
  if (quads_.size() == kKept) quads_.erase(quads_.begin());
  quads_.push_back(std::move(q));
  return *quads_.back();
}

double ProfileSolver::k_max_for(const std::vector<const RadialResponse*>& stacks) {
  double k_max = 8.0;
  for (const RadialResponse* s : stacks) {
    const double scale = std::max(std::abs(s->total()), 1e-300);
    // |G(k)| k max(k, 1): a bound on the integrand's tail for the decay rates that occur (the
    // residual falls at least like exp(-2 d k) for a top layer of thickness d).
    auto small = [&](double k) {
      return std::abs(s->residual_k(k)) * k * std::max(k, 1.0) < 1e-10 * scale;
    };
    while (k_max < 65536.0 && !(small(k_max) && small(1.5 * k_max) && small(2 * k_max))) k_max *= 2.0;
  }
  return k_max;
}

std::vector<double> ProfileSolver::profile(const RadialResponse& stack) {
  const auto& q = quadrature_for(k_max_for({&stack}));
  Eigen::VectorXd G(static_cast<Eigen::Index>(q.k.size()));
  for (std::size_t n = 0; n < q.k.size(); ++n) G(static_cast<Eigen::Index>(n)) = stack.residual_k(q.k[n]);
  Eigen::VectorXd out = q.M * G;
  std::vector<double> R(radii_.size());
  for (std::size_t j = 0; j < R.size(); ++j) R[j] = stack.singular(radii_.r[j]) + out(static_cast<Eigen::Index>(j));
  return R;
}

namespace {
std::vector<const RadialResponse*> pointers(const std::vector<DiffusionStack>& stacks) {
  std::vector<const RadialResponse*> p;
  p.reserve(stacks.size());
  for (const auto& s : stacks) p.push_back(&s);
  return p;
}
// Residuals of all stacks at all nodes: one row per stack.
Eigen::MatrixXd residuals(const std::vector<const RadialResponse*>& stacks, const std::vector<double>& k) {
  Eigen::MatrixXd G(static_cast<Eigen::Index>(stacks.size()), static_cast<Eigen::Index>(k.size()));
  for (std::size_t i = 0; i < stacks.size(); ++i)
    for (std::size_t n = 0; n < k.size(); ++n)
      G(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(n)) = stacks[i]->residual_k(k[n]);
  return G;
}
}  // namespace

SpectralProfile ProfileSolver::spectral(const std::vector<DiffusionStack>& stacks,
                                        const WavelengthGrid& grid) {
  return spectral(pointers(stacks), grid);
}

RgbProfile ProfileSolver::rgb(const std::vector<DiffusionStack>& stacks,
                              const ChannelWeights& weights) {
  return rgb(pointers(stacks), weights);
}

SpectralProfile ProfileSolver::spectral(const std::vector<const RadialResponse*>& stacks,
                                        const WavelengthGrid& grid) {
  SKIN_ASSERT(stacks.size() == grid.size(), "one stack per wavelength");
  const auto& q = quadrature_for(k_max_for(stacks));
  const Eigen::MatrixXd G = residuals(stacks, q.k);
  // (lambda x nodes) (nodes x radii): row-major result matches SpectralProfile::R's layout.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out = G * q.M.transpose();
  SpectralProfile p{grid, radii_, {}, Spectrum(grid)};
  p.R.resize(stacks.size() * radii_.size());
  for (std::size_t i = 0; i < stacks.size(); ++i) {
    p.R_d[i] = stacks[i]->total();
    for (std::size_t j = 0; j < radii_.size(); ++j)
      p.R[i * radii_.size() + j] = stacks[i]->singular(radii_.r[j]) +
                                   out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  }
  return p;
}

RgbProfile ProfileSolver::rgb(const std::vector<const RadialResponse*>& stacks,
                              const ChannelWeights& weights) {
  SKIN_ASSERT(stacks.size() == weights.size(), "one weight triple per stack");
  const auto& q = quadrature_for(k_max_for(stacks));
  const auto nl = static_cast<Eigen::Index>(stacks.size());
  Eigen::MatrixXd W(3, nl);
  for (Eigen::Index i = 0; i < nl; ++i)
    for (int c = 0; c < 3; ++c) W(c, i) = weights[static_cast<std::size_t>(i)][static_cast<std::size_t>(c)];
  const Eigen::MatrixXd Gc = W * residuals(stacks, q.k);   // 3 x nodes
  const Eigen::MatrixXd out = Gc * q.M.transpose();        // 3 x radii
  RgbProfile p;
  p.radii = radii_;
  for (int c = 0; c < 3; ++c) {
    p.R[static_cast<std::size_t>(c)].assign(radii_.size(), 0.0);
    for (std::size_t j = 0; j < radii_.size(); ++j)
      p.R[static_cast<std::size_t>(c)][j] = out(c, static_cast<Eigen::Index>(j));
  }
  for (std::size_t i = 0; i < stacks.size(); ++i) {
    const double Rd = stacks[i]->total();
    for (std::size_t j = 0; j < radii_.size(); ++j) {
      const double dip = stacks[i]->singular(radii_.r[j]);
      for (std::size_t c = 0; c < 3; ++c) p.R[c][j] += weights[i][c] * dip;
    }
    for (std::size_t c = 0; c < 3; ++c) p.R_d[c] += weights[i][c] * Rd;
  }
  return p;
}

double integrate_profile(const RadialGrid& radii, const std::vector<double>& R) {
  SKIN_ASSERT(radii.size() == R.size(), "profile and radii sizes differ");
  double sum = 0.0;
  for (std::size_t j = 1; j < R.size(); ++j) {
    const double r0 = radii.r[j - 1], r1 = radii.r[j];
    sum += 0.5 * (R[j - 1] * r0 + R[j] * r1) * (r1 - r0);
  }
  return 2.0 * std::numbers::pi * sum;
}

}  // namespace skin::transport
