#include "skin/render/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/util/error.hpp"

namespace skin::render {

std::ostream& operator<<(std::ostream& os, const Vec3& v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}

Vec2 sample_concentric_disk(Vec2 u) {
  const double a = 2 * u.x - 1, b = 2 * u.y - 1;
  if (a == 0 && b == 0) return {0, 0};
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4) * (b / a);
  } else {
    r = b;
    phi = kPi / 2 - (kPi / 4) * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_concentric_disk(u);
  return {d.x, d.y, std::sqrt(std::max(0.0, 1 - d.x * d.x - d.y * d.y))};
}
double pdf_cosine_hemisphere(double cos_theta) { return cos_theta > 0 ? cos_theta / kPi : 0.0; }

Vec3 sample_uniform_sphere(Vec2 u) {
  const double z = 1 - 2 * u.x;
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 sample_uniform_cone(Vec2 u, double cos_theta_max) {
  const double c = 1 - u.x * (1 - cos_theta_max);
  const double s = std::sqrt(std::max(0.0, 1 - c * c));
  const double phi = 2 * kPi * u.y;
  return {s * std::cos(phi), s * std::sin(phi), c};
}
double pdf_uniform_cone(double cos_theta_max) { return 1.0 / (2 * kPi * (1 - cos_theta_max)); }

Distribution1D::Distribution1D(std::vector<double> weights) : w_(std::move(weights)) {
  SKIN_ASSERT(!w_.empty(), "Distribution1D needs at least one bin");
  cdf_.assign(w_.size() + 1, 0.0);
  for (std::size_t i = 0; i < w_.size(); ++i) {
    SKIN_ASSERT(w_[i] >= 0 && std::isfinite(w_[i]), "Distribution1D weight must be finite, >= 0");
    cdf_[i + 1] = cdf_[i] + w_[i];
  }
  const double sum = cdf_.back();
  const double n = static_cast<double>(w_.size());
  total_ = sum / n;
  if (sum == 0) {  // nothing to prefer: uniform
    for (std::size_t i = 0; i <= w_.size(); ++i) cdf_[i] = static_cast<double>(i) / n;
  } else {
    for (auto& c : cdf_) c /= sum;
  }
}

double Distribution1D::sample(double u, double* pdf, std::size_t* bin) const {
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - cdf_.begin() - 1));
  i = std::min(i, w_.size() - 1);
  while (cdf_[i + 1] - cdf_[i] <= 0 && i + 1 < w_.size()) ++i;  // skip empty bins
  const double n = static_cast<double>(w_.size());
  const double width = cdf_[i + 1] - cdf_[i];
  const double du = width > 0 ? (u - cdf_[i]) / width : 0.5;
  if (pdf) *pdf = width * n;
  if (bin) *bin = i;
  return std::min((static_cast<double>(i) + std::clamp(du, 0.0, 1.0)) / n, std::nextafter(1.0, 0.0));
}

double Distribution1D::pdf(double x) const {
  if (x < 0 || x >= 1) return 0.0;
  const auto i = std::min(static_cast<std::size_t>(x * static_cast<double>(w_.size())), w_.size() - 1);
  return (cdf_[i + 1] - cdf_[i]) * static_cast<double>(w_.size());
}

double Distribution1D::invert(double x) const {
  const double n = static_cast<double>(w_.size());
  const auto i = std::min(static_cast<std::size_t>(std::clamp(x, 0.0, 1.0) * n), w_.size() - 1);
  const double frac = x * n - static_cast<double>(i);
  return cdf_[i] + frac * (cdf_[i + 1] - cdf_[i]);
}

Distribution2D::Distribution2D(const std::vector<double>& weights, std::size_t nu, std::size_t nv) {
  SKIN_ASSERT(weights.size() == nu * nv && nu > 0 && nv > 0, "Distribution2D size mismatch");
  std::vector<double> row_totals(nv);
  conditional_.reserve(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    conditional_.emplace_back(std::vector<double>(weights.begin() + static_cast<std::ptrdiff_t>(v * nu),
                                                  weights.begin() + static_cast<std::ptrdiff_t>((v + 1) * nu)));
    row_totals[v] = conditional_.back().total();
  }
  marginal_ = Distribution1D(std::move(row_totals));
}

Vec2 Distribution2D::sample(Vec2 u, double* pdf) const {
  double pv = 0, pu = 0;
  std::size_t row = 0;
  const double v = marginal_.sample(u.y, &pv, &row);
  const double x = conditional_[row].sample(u.x, &pu, nullptr);
  if (pdf) *pdf = pu * pv;
  return {x, v};
}

double Distribution2D::pdf(Vec2 p) const {
  if (p.x < 0 || p.x >= 1 || p.y < 0 || p.y >= 1) return 0.0;
  const auto row = std::min(static_cast<std::size_t>(p.y * static_cast<double>(conditional_.size())),
                            conditional_.size() - 1);
  return marginal_.pdf(p.y) * conditional_[row].pdf(p.x);
}

}  // namespace skin::render
