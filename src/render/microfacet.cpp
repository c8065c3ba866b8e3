#include "skin/render/microfacet.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/physics/fresnel.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::require_in_range;
using skin::util::require_positive;

using skin::physics::fresnel_dielectric;

double Beckmann::D(const Vec3& h) const {
  const double c = h.z;
  if (c <= 0) return 0.0;
  const double c2 = c * c;
  const double tan2 = std::max(0.0, 1 - c2) / c2;
  const double s2 = sigma * sigma;
  return std::exp(-tan2 / s2) / (kPi * s2 * c2 * c2);
}

Vec3 Beckmann::sample_h(Vec2 u) const {
  const double tan2 = -sigma * sigma * std::log1p(-u.x);
  const double c = 1 / std::sqrt(1 + tan2);
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  const double phi = 2 * kPi * u.y;
  return {s * std::cos(phi), s * std::sin(phi), c};
}

Vec2 Beckmann::invert_h(const Vec3& h) const {
  const double c2 = h.z * h.z;
  const double tan2 = std::max(0.0, 1 - c2) / c2;
  double phi = std::atan2(h.y, h.x);
  if (phi < 0) phi += 2 * kPi;
  return {-std::expm1(-tan2 / (sigma * sigma)), phi / (2 * kPi)};
}

std::ostream& operator<<(std::ostream& os, const Beckmann& b) {
  return os << "Beckmann{sigma=" << b.sigma << '}';
}

double cook_torrance_G(const Vec3& wo, const Vec3& wi, const Vec3& h) {
  const double oh = dot(wo, h);
  if (oh <= 0) return 0.0;
  return std::min({1.0, 2 * h.z * wo.z / oh, 2 * h.z * wi.z / oh});
}

TorranceSparrow::TorranceSparrow(double rho_s, double sigma, double eta)
    : rho_s_(rho_s), beckmann_{sigma}, eta_(eta) {
  require_in_range("rho_s", rho_s, 0.0, 1.0);
  require_positive("roughness", sigma);
  require_in_range("eta", eta, 1.0, 3.0);
}

double TorranceSparrow::f(const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0 || rho_s_ == 0) return 0.0;
  const Vec3 h = normalize(wo + wi);
  const double F = fresnel_dielectric(dot(wi, h), 1.0, eta_);
  return rho_s_ * beckmann_.D(h) * cook_torrance_G(wo, wi, h) * F / (4 * wi.z * wo.z);
}

bool TorranceSparrow::sample(const Vec3& wo, Vec2 u, Vec3* wi, double* pdf) const {
  if (wo.z <= 0) return false;
  const Vec3 h = beckmann_.sample_h(u);
  const double oh = dot(wo, h);
  if (oh <= 0) return false;
  *wi = h * (2 * oh) - wo;
  if (wi->z <= 0) return false;
  *pdf = beckmann_.pdf_h(h) / (4 * oh);
  return true;
}

double TorranceSparrow::pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0 || wi.z <= 0) return 0.0;
  const Vec3 h = normalize(wo + wi);
  const double oh = dot(wo, h);
  return oh > 0 ? beckmann_.pdf_h(h) / (4 * oh) : 0.0;
}

SpecularAlbedo::SpecularAlbedo(double sigma, double eta, int n_cos) {
  SKIN_ASSERT(n_cos >= 2, "SpecularAlbedo needs >= 2 entries");
  // Deterministic stratified estimate of eq 2 with the lobe's own importance sampling:
  // rho_dr(wo) = E[f cos / pdf]; 64 x 64 strata per angle keep the error near 1e-3 (checked
  // against a brute-force hemisphere integral in tests/render/test_sampling.cpp).
  const TorranceSparrow lobe(1.0, sigma, eta);
  constexpr int kStrata = 64;
  table_.resize(static_cast<std::size_t>(n_cos));
  for (int k = 0; k < n_cos; ++k) {
    const double mu = std::max(1e-3, static_cast<double>(k) / (n_cos - 1));
    const Vec3 wo{std::sqrt(1 - mu * mu), 0, mu};
    double sum = 0;
    for (int i = 0; i < kStrata; ++i)
      for (int j = 0; j < kStrata; ++j) {
        Vec3 wi;
        double pdf = 0;
        if (lobe.sample(wo, {(i + 0.5) / kStrata, (j + 0.5) / kStrata}, &wi, &pdf) && pdf > 0)
          sum += lobe.f(wo, wi) * wi.z / pdf;
      }
    table_[static_cast<std::size_t>(k)] = sum / (kStrata * kStrata);
  }
  // mean = 2 int rho_dr(mu) mu dmu by the trapezoid rule on the table.
  double m = 0;
  for (int k = 0; k + 1 < n_cos; ++k) {
    const double a = static_cast<double>(k) / (n_cos - 1), b = static_cast<double>(k + 1) / (n_cos - 1);
    m += (b - a) * (table_[static_cast<std::size_t>(k)] * a + table_[static_cast<std::size_t>(k + 1)] * b);
  }
  mean_ = m;
}

double SpecularAlbedo::rho_dr(double cos_theta) const {
  const double x = std::clamp(cos_theta, 0.0, 1.0) * static_cast<double>(table_.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(x), table_.size() - 2);
  const double t = x - static_cast<double>(i);
  return table_[i] * (1 - t) + table_[i + 1] * t;
}

}  // namespace skin::render
