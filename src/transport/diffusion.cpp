#include "skin/transport/diffusion.hpp"

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <numbers>
#include <ostream>

#include "skin/physics/fresnel.hpp"
#include "skin/util/error.hpp"

namespace skin::transport {

using skin::util::format_number;

using skin::physics::fresnel_dielectric;

double F_dr(double eta) {
  if (std::abs(eta - 1.0) < 1e-12) return 0.0;  // matched boundary: no internal reflection
  if (eta >= 1.0) return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
  return -0.4399 + 0.7099 / eta - 0.3319 / (eta * eta) + 0.0636 / (eta * eta * eta);
}

double F_dr_exact(double eta) {
  if (eta == 1.0) return 0.0;
  // 2 int_0^1 F(mu) mu dmu for light inside (index eta) meeting the outside (index 1). Beyond the
  // critical angle (mu < mu_c) F = 1 and that part integrates to mu_c^2 in closed form; the rest
  // has a square-root kink at mu_c, which an adaptive Gauss-Kronrod rule resolves.
  const double mu_c = eta > 1.0 ? std::sqrt(1.0 - 1.0 / (eta * eta)) : 0.0;
  auto f = [eta](double mu) { return 2.0 * mu * fresnel_dielectric(mu, eta, 1.0); };
  const double rest =
      boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, mu_c, 1.0, 15, 1e-13);
  return mu_c * mu_c + rest;
}

double A_boundary(double eta) {
  const double f = F_dr(eta);
  return (1.0 + f) / (1.0 - f);
}

DiffusionSlab DiffusionSlab::make(double sigma_a, double sigma_s_prime, double d, double A_top,
                                  double A_bottom) {
  SKIN_ASSERT(sigma_a >= 0 && sigma_s_prime > 0 && d > 0 && A_top >= 1 - 1e-12,
              "sigma_a=" + format_number(sigma_a) + " sigma_s_prime=" +
                  format_number(sigma_s_prime) + " d=" + format_number(d) +
                  " A_top=" + format_number(A_top));
  DiffusionSlab s;
  s.sigma_a = sigma_a;
  s.sigma_s_prime = sigma_s_prime;
  s.d = d;
  s.A_top = A_top;
  s.A_bottom = A_bottom;
  s.sigma_t_prime = sigma_a + sigma_s_prime;
  s.alpha_prime = sigma_s_prime / s.sigma_t_prime;
  s.D = 1.0 / (3.0 * s.sigma_t_prime);
  s.sigma_tr = std::sqrt(sigma_a / s.D);
  s.z_r = 1.0 / s.sigma_t_prime;
  s.z_b_top = 2.0 * A_top * s.D;
  s.z_b_bottom = 2.0 * A_bottom * s.D;
  s.L = d + s.z_b_top + s.z_b_bottom;
  return s;
}

bool DiffusionSlab::semi_infinite() const { return std::isinf(d); }

DiffusionSlab DiffusionSlab::flipped() const {
  return make(sigma_a, sigma_s_prime, d, A_bottom, A_top);
}

namespace {

// image_series (below) with the shared factor q = exp(-P s) precomputed: one exp per family, used where
// P s is not small (otherwise image_series' expm1 form keeps the precision).
inline double image_series_q(double c, double P, double s, double q) {
  double c0 = c - P * std::floor(c / P);
  if (c0 >= P) c0 -= P;
  const bool on_boundary = c0 == 0.0;
  const double a = std::exp(-c0 * s);
  const double b = a > 1e-300 ? q / a : std::exp(-(P - c0) * s);  // exp(-(P - c0) s)
  const double value = (a - b) / (1.0 - q);
  return on_boundary ? value - 1.0 : value;
}

// S(c) = sum over all integers i of sgn(i P + c) exp(-|i P + c| s), P = 2L: the image sum of one
// family of poles in the frequency domain (each pole at depth z contributes 2 pi sgn(z)
// exp(-|z| s), model-notes section 4). With c0 = c mod P in [0, P) the positive poles are
// c0 + j P (j >= 0) and the negative ones c0 - j P (j >= 1): two geometric series,
//   S = (exp(-c0 s) - exp(-(P - c0) s)) / (1 - exp(-P s)),
// written with expm1 so that it stays accurate as s -> 0 (weak absorption, k -> 0), where
// S -> 1 - 2 c0 / P.
double image_series(double c, double P, double s) {
  double c0 = c - P * std::floor(c / P);
  if (c0 >= P) c0 -= P;
  const bool on_boundary = c0 == 0.0;  // the pole at depth 0 has sgn 0
  if (P * s >= 0.05) return image_series_q(c, P, s, std::exp(-P * s));
  double value;
  if (s == 0.0) {
    value = 1.0 - 2.0 * c0 / P;
  } else {
    value = std::exp(-c0 * s) * std::expm1(-(P - 2.0 * c0) * s) / std::expm1(-P * s);
  }
  return on_boundary ? value - 1.0 : value;
}

inline double pole_k(double z, double s) {  // one pole, frequency domain, without the 2 pi
  if (z == 0.0) return 0.0;
  return std::copysign(std::exp(-std::abs(z) * s), z);
}

// z (1 + sigma_tr dist) exp(-sigma_tr dist) / dist^3, dist = sqrt(r^2 + z^2): one pole in space.
inline double pole_r(double z, double r, double sigma_tr) {
  const double dist = std::sqrt(r * r + z * z);
  if (dist == 0.0) return 0.0;
  return z * (1.0 + sigma_tr * dist) * std::exp(-sigma_tr * dist) / (dist * dist * dist);
}

}  // namespace

double DiffusionSlab::R_dipole_k(double k) const {
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  return 0.5 * alpha_prime * (std::exp(-z_r * s) + std::exp(-(z_r + 2.0 * z_b_top) * s));
}

double DiffusionSlab::R_dipole(double r) const {
  const double z_v = -(z_r + 2.0 * z_b_top);
  return alpha_prime / (4.0 * std::numbers::pi) * (pole_r(z_r, r, sigma_tr) - pole_r(z_v, r, sigma_tr));
}

double DiffusionSlab::R_k(double k) const {
  if (semi_infinite()) return R_dipole_k(k);
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  const double P = 2.0 * L;
  // Real poles at 2iL + z_r, images at 2iL - z_r - 2 z_b_top (DJ05 eq 7).
  return 0.5 * alpha_prime *
         (image_series(z_r, P, s) - image_series(-z_r - 2.0 * z_b_top, P, s));
}

std::array<double, 4> DiffusionSlab::transfer_k(double k) const {
  if (semi_infinite()) return {R_dipole_k(k), 0.0, 0.0, 0.0};
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  const double P = 2.0 * L;
  const double h = 0.5 * alpha_prime;
  if (P * s < 0.05) {  // near the non-absorbing, k = 0 limit: keep the expm1 form
    const double Sr = image_series(z_r, P, s), St = image_series(d - z_r, P, s);
    return {h * (Sr - image_series(-z_r - 2.0 * z_b_top, P, s)),
            h * (St - image_series(d + z_r + 2.0 * z_b_top, P, s)),
            h * (Sr - image_series(-z_r - 2.0 * z_b_bottom, P, s)),
            h * (St - image_series(d + z_r + 2.0 * z_b_bottom, P, s))};
  }
  const double q = std::exp(-P * s);
  const double Sr = image_series_q(z_r, P, s, q), St = image_series_q(d - z_r, P, s, q);
  return {h * (Sr - image_series_q(-z_r - 2.0 * z_b_top, P, s, q)),
          h * (St - image_series_q(d + z_r + 2.0 * z_b_top, P, s, q)),
          h * (Sr - image_series_q(-z_r - 2.0 * z_b_bottom, P, s, q)),
          h * (St - image_series_q(d + z_r + 2.0 * z_b_bottom, P, s, q))};
}

double DiffusionSlab::T_k(double k) const {
  if (semi_infinite()) return 0.0;
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  const double P = 2.0 * L;
  // Same poles seen from the bottom surface z = d: depths d - z.
  return 0.5 * alpha_prime *
         (image_series(d - z_r, P, s) - image_series(d + z_r + 2.0 * z_b_top, P, s));
}

namespace {
template <class PairTerm>
double sum_pairs(PairTerm pair, double tol, int max_pairs) {
  double sum = pair(0);
  for (int i = 1; i <= max_pairs; ++i) {
    const double t = pair(i) + pair(-i);
    sum += t;
    if (std::abs(t) <= tol * std::abs(sum)) break;
  }
  return sum;
}
}  // namespace

double DiffusionSlab::R_k_sum(double k, double tol, int max_pairs) const {
  if (semi_infinite()) return R_dipole_k(k);
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  auto pair = [&](int i) {
    const double zr = 2.0 * i * L + z_r, zv = 2.0 * i * L - z_r - 2.0 * z_b_top;
    return pole_k(zr, s) - pole_k(zv, s);
  };
  return 0.5 * alpha_prime * sum_pairs(pair, tol, max_pairs);
}

double DiffusionSlab::T_k_sum(double k, double tol, int max_pairs) const {
  if (semi_infinite()) return 0.0;
  const double s = std::sqrt(sigma_tr * sigma_tr + k * k);
  auto pair = [&](int i) {
    const double zr = 2.0 * i * L + z_r, zv = 2.0 * i * L - z_r - 2.0 * z_b_top;
    return pole_k(d - zr, s) - pole_k(d - zv, s);
  };
  return 0.5 * alpha_prime * sum_pairs(pair, tol, max_pairs);
}

double DiffusionSlab::R(double r, double tol) const {
  if (semi_infinite()) return R_dipole(r);
  auto pair = [&](int i) {
    const double zr = 2.0 * i * L + z_r, zv = 2.0 * i * L - z_r - 2.0 * z_b_top;
    return pole_r(zr, r, sigma_tr) - pole_r(zv, r, sigma_tr);
  };
  return alpha_prime / (4.0 * std::numbers::pi) * sum_pairs(pair, tol, 1000000);
}

double DiffusionSlab::T(double r, double tol) const {
  if (semi_infinite()) return 0.0;
  auto pair = [&](int i) {
    const double zr = 2.0 * i * L + z_r, zv = 2.0 * i * L - z_r - 2.0 * z_b_top;
    return pole_r(d - zr, r, sigma_tr) - pole_r(d - zv, r, sigma_tr);
  };
  return alpha_prime / (4.0 * std::numbers::pi) * sum_pairs(pair, tol, 1000000);
}

std::ostream& operator<<(std::ostream& os, const DiffusionSlab& s) {
  return os << "DiffusionSlab{sigma_a=" << s.sigma_a << "/mm, sigma_s_prime=" << s.sigma_s_prime
            << "/mm, d=" << s.d << "mm, A_top=" << s.A_top << ", A_bottom=" << s.A_bottom
            << ", alpha'=" << s.alpha_prime << ", sigma_tr=" << s.sigma_tr << "/mm, z_r=" << s.z_r
            << "mm, z_b_top=" << s.z_b_top << "mm, z_b_bottom=" << s.z_b_bottom << "mm}";
}

double R_d_semi_infinite(double alpha_prime, double A) {
  const double root = std::sqrt(3.0 * (1.0 - alpha_prime));
  return 0.5 * alpha_prime * (1.0 + std::exp(-4.0 / 3.0 * A * root)) * std::exp(-root);
}

}  // namespace skin::transport
