// The targets' own models (export.hpp: the albedo inversions and profile shapes as the targets
// implement them) and the fits through them that the families share (fits.hpp).
#include "fits.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "skin/transport/random_walk_table.hpp"

namespace skin::exporting {



using skin::transport::RadialGrid;


using skin::physics::SkinParameters;



double burley_profile(double d, double r) {
  if (!(r > 0) || !(d > 0)) return 0.0;
  return (std::exp(-r / d) + std::exp(-r / (3.0 * d))) / (8.0 * std::numbers::pi * d * r);
}

double chiang_alpha(double A) {
  // Chiang, Kutz & Burley 2016, eq. 3 (a fit of the random walk's multiple-scattering albedo).
  A = std::clamp(A, 0.0, 1.0);
  const double s = 4.09712 + 4.20863 * A - std::sqrt(9.59217 + 41.6808 * A + 17.7126 * A * A);
  return 1.0 - s * s;
}

namespace {
// p(g) = sum c[i] g^i (Horner).
template <std::size_t N>
double poly(const double (&c)[N], double g) {
  double v = 0;
  for (std::size_t i = N; i-- > 0;) v = v * g + c[i];
  return v;
}
}  // namespace

double cycles_alpha(double A, double g) {
  // Cycles' subsurface_random_walk_remap (Blender 3.0+): a blend of two fits in atan(k A), each
  // coefficient a degree-7 polynomial in g (the values are Cycles'; Wrenninge, Villemin & Hery
  // 2017 give the method).
  static constexpr double cA[] = {1.8260523782, -1.28451056436, -1.79904629312, 9.19393289202,
                                  -22.8215585862, 32.0234874259, -23.6264803333, 7.21067002658};
  static constexpr double cB[] = {0.0, 31.1491581433, -201.847017512, 841.576016723,
                                  -2018.09288505, 2731.71560286, -1935.41424244, 559.009054474};
  static constexpr double cC[] = {1.09686102424, -0.394704063468, 1.05258115941, -8.83963712726,
                                  28.8643230661, -46.8802913581, 38.5402837518, -12.7181042538};
  static constexpr double cD[] = {0.496310210422, 0.360146581622, -2.15139309747, 17.8896899217,
                                  -55.2984010333, 82.065982243, -58.5106008578, 15.8478295021};
  static constexpr double cE[] = {0.0, 76.7316253952, -594.356773233, 2448.8834203,
                                  -5576.68528998, 7116.60171912, -4763.54467887, 1303.5318055};
  static constexpr double cF[] = {2.40602999408, -2.51814844609, 9.18494908356, -79.2191708682,
                                  259.082868209, -403.613804597, 302.85712436, -87.4370473567};
  A = std::clamp(A, 0.0, 1.0);
  const double a = poly(cA, g), b = 4.98511194385 + 0.127355959438 * std::exp(poly(cB, g));
  const double c = poly(cC, g), d = poly(cD, g);
  const double e = 4.23190299701 + 0.00310603949088 * std::exp(poly(cE, g)), f = poly(cF, g);
  const double blend = std::pow(A, 0.25);
  const double alpha = (1.0 - blend) * a * std::pow(std::atan(b * A), c) +
                       blend * d * std::pow(std::atan(e * A), f);
  return std::clamp(alpha, 0.0, 0.999999);
}

namespace detail {

double perceptual_roughness(const SkinParameters& p) { return std::sqrt(p.roughness); }
double fresnel_f0(double eta) {
  const double q = (eta - 1.0) / (eta + 1.0);
  return q * q;
}

WalkFit fit_walk(const Reference& ref, double (*alpha_of_A)(double), double gain) {
  const transport::RandomWalkTable& table = transport::RandomWalkTable::builtin();
  WalkFit f;
  for (int c = 0; c < 3; ++c) {
    auto D = [&](double A) { return gain * table.reflectance(alpha_of_A(A)); };
    const double y = ref.R_d[c];
    if (y > D(1.0) || y < D(0.0)) f.clamped = true;
    const double A = invert_increasing(D, y, 0.0, 1.0);
    const double alpha = alpha_of_A(A);
    const double m_rho = table.mean_rho(alpha);
    double d = ref.mean_radius[c] > 0 && m_rho > 0 ? ref.mean_radius[c] / m_rho : 1e-6;
    f.A[c] = A;
    f.alpha[c] = alpha;
    f.R_d[c] = D(A);
    auto profile = [&](double dd) {
      std::vector<double> rho(ref.radii.size());
      for (std::size_t j = 0; j < rho.size(); ++j) rho[j] = ref.radii.r[j] / dd;
      std::vector<double> R = table.density(alpha, rho);
      for (double& v : R) v /= dd * dd;
      return R;
    };
    // The table's mean (annulus centres) and that of its interpolated density differ by ~1 %:
    // one correction makes the written profile's mean radius the reference's.
    const double m_t = mean_radius(ref.radii, profile(d));
    if (m_t > 0) d *= ref.mean_radius[c] / m_t;
    f.d_mm[c] = d;
    f.R[c] = profile(d);
  }
  return f;
}

TexelFit walk_texel(const Reference& ref, const WalkFit& w, double radius_per_d) {
  TexelFit t;
  t.color = w.A;
  for (int c = 0; c < 3; ++c) t.radius_mm[c] = radius_per_d * w.d_mm[c];
  t.delta_e = delta_e(ref.R_d, w.R_d);
  return t;
}

BurleyFit fit_burley(const Reference& ref) {
  BurleyFit f;
  for (int c = 0; c < 3; ++c) {
    f.A[c] = std::clamp(ref.R_d[c], 0.0, 1.0);
    if (f.A[c] != ref.R_d[c]) f.clamped = true;
    f.d_mm[c] = std::max(ref.mean_radius[c] / 2.5, 1e-6);  // mean radius 2.5 d
    f.R_d[c] = f.A[c];
    f.R[c].resize(ref.radii.size());
    for (std::size_t j = 0; j < ref.radii.size(); ++j)
      f.R[c][j] = f.A[c] * burley_profile(f.d_mm[c], ref.radii.r[j]);
  }
  return f;
}

// Christensen & Burley 2015, eq. 6 (perpendicular incidence): d = l / s(A) for the mean free

Gaussians fit_gaussians(const Reference& ref, int n) {
  const RadialGrid& radii = ref.radii;
  const std::size_t J = radii.size();
  auto fit_ladder = [&](double v0, double q) {
    Gaussians g;
    for (int k = 0; k < n; ++k) g.v.push_back(v0 * std::pow(q, k));
    Eigen::MatrixXd A(J, n);
    for (std::size_t j = 0; j < J; ++j) {
      const double r = radii.r[j];
      for (int k = 0; k < n; ++k)
        A(j, k) = r * r * std::exp(-r * r / (2 * g.v[k])) / g.v[k];  // ~ 2 pi r^2 G
    }
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd b(J);
      for (std::size_t j = 0; j < J; ++j) b(j) = 2 * std::numbers::pi * radii.r[j] * radii.r[j] * ref.R[c][j];
      // Least squares with the negative weights removed until none is left (active set).
      std::vector<bool> on(n, true);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
      for (int iter = 0; iter < n; ++iter) {
        std::vector<int> cols;
        for (int k = 0; k < n; ++k)
          if (on[k]) cols.push_back(k);
        if (cols.empty()) break;
        Eigen::MatrixXd Asub(J, cols.size());
        for (std::size_t k = 0; k < cols.size(); ++k) Asub.col(k) = A.col(cols[k]);
        const Eigen::VectorXd sol = Asub.colPivHouseholderQr().solve(b);
        x.setZero();
        bool negative = false;
        for (std::size_t k = 0; k < cols.size(); ++k) {
          x(cols[k]) = sol(k);
          if (sol(k) < 0) { on[cols[k]] = false; negative = true; }
        }
        if (!negative) break;
        for (int k = 0; k < n; ++k) x(k) = std::max(x(k), 0.0);
      }
      g.w[c].resize(n);
      // Scaled to integrate to R_d, so that the colour is ours (the fit is of the shape).
      double total = 0;
      for (int k = 0; k < n; ++k) total += std::max(x(k), 0.0);
      for (int k = 0; k < n; ++k) g.w[c][k] = total > 0 ? std::max(x(k), 0.0) * ref.R_d[c] / total : 0.0;
      g.R[c].assign(J, 0.0);
      for (std::size_t j = 0; j < J; ++j)
        for (int k = 0; k < n; ++k) {
          const double v = g.v[k], r = radii.r[j];
          g.R[c][j] += g.w[c][k] * std::exp(-r * r / (2 * v)) / (2 * std::numbers::pi * v);
        }
      g.error += relative_l1(radii, g.R[c], ref.R[c]);
    }
    return g;
  };
  Gaussians best;
  best.error = 1e300;
  for (double lv0 = -15.0; lv0 <= -1.0; lv0 += 0.5)
    for (double lq = 0.6; lq <= 3.0; lq += 0.3) {
      Gaussians g = fit_ladder(std::exp(lv0), std::exp(lq));
      if (g.error < best.error) best = std::move(g);
    }
  return best;
}

}  // namespace detail

}  // namespace skin::exporting
