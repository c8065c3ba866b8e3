#include "skin/render/profile_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "skin/util/error.hpp"
#include "skin/render/math.hpp"

namespace skin::render {

TabulatedProfile::TabulatedProfile(const std::vector<double>& radii, const std::vector<double>& R,
                                   double R_d, double tail)
    : R_d_(R_d) {
  SKIN_ASSERT(radii.size() == R.size() && radii.size() >= 2, "profile table size");
  const std::size_t n = radii.size();
  std::vector<double> f(n), seg_abs(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    SKIN_ASSERT(std::isfinite(R[i]), "profile value must be finite");
    f[i] = 2 * kPi * radii[i] * R[i];
  }
  // Cut where the integral of |f| reaches (1 - tail) of its total.
  double total_abs = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    total_abs += 0.5 * (std::abs(f[i]) + std::abs(f[i + 1])) * (radii[i + 1] - radii[i]);
    seg_abs[i + 1] = total_abs;
  }
  std::size_t last = n - 1;
  if (total_abs > 0)
    for (std::size_t i = 1; i < n; ++i)
      if (seg_abs[i] >= (1 - tail) * total_abs) {
        last = i;
        break;
      }
  r_.assign(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(last + 1));
  f_.assign(f.begin(), f.begin() + static_cast<std::ptrdiff_t>(last + 1));
  f_plus_.resize(f_.size());
  for (std::size_t i = 0; i < f_.size(); ++i) f_plus_[i] = std::max(0.0, f_[i]);
  cdf_.assign(r_.size(), 0.0);
  double signed_total = 0;
  for (std::size_t i = 0; i + 1 < r_.size(); ++i) {
    const double dr = r_[i + 1] - r_[i];
    cdf_[i + 1] = cdf_[i] + 0.5 * (f_plus_[i] + f_plus_[i + 1]) * dr;
    signed_total += 0.5 * (f_[i] + f_[i + 1]) * dr;
  }
  total_plus_ = cdf_.back();
  if (total_plus_ > 0)
    for (auto& c : cdf_) c /= total_plus_;
  scale_ = signed_total != 0 ? R_d / signed_total : 0.0;
}

std::size_t TabulatedProfile::segment(double r) const {
  const auto it = std::upper_bound(r_.begin(), r_.end(), r);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - r_.begin())) - 1;
  return std::min(i, r_.size() - 2);
}

double TabulatedProfile::f_plus_at(double r) const {
  if (r_.empty() || r < r_.front() || r > r_.back()) return 0.0;
  const std::size_t i = segment(r);
  const double t = (r - r_[i]) / (r_[i + 1] - r_[i]);
  return f_plus_[i] * (1 - t) + f_plus_[i + 1] * t;
}

double TabulatedProfile::sample_radius(double u) const {
  if (r_.empty() || total_plus_ <= 0) return 0.0;
  u = std::clamp(u, 0.0, 1.0);
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - cdf_.begin())) - 1;
  i = std::min(i, r_.size() - 2);
  while (cdf_[i + 1] <= cdf_[i] && i + 2 < r_.size()) ++i;
  const double dr = r_[i + 1] - r_[i];
  const double a = f_plus_[i], b = f_plus_[i + 1];
  // Mass needed inside the segment, in f units: solve a t + (b - a) t^2 / (2 dr) = m for t.
  const double m = (u - cdf_[i]) * total_plus_;
  const double slope = (b - a) / dr;
  double t;
  if (m <= 0) {
    t = 0;
  } else if (std::abs(slope) < 1e-12 * std::max(a, b) / dr || slope == 0) {
    t = a > 0 ? m / a : 0.0;
  } else {
    const double disc = std::max(0.0, a * a + 2 * slope * m);
    t = 2 * m / (a + std::sqrt(disc));  // stable form of (-a + sqrt(disc)) / slope
  }
  return std::clamp(r_[i] + t, r_[i], r_[i + 1]);
}

double TabulatedProfile::pdf_radius(double r) const {
  return total_plus_ > 0 ? f_plus_at(r) / total_plus_ : 0.0;
}

double TabulatedProfile::pdf_area(double r) const {
  if (r_.empty() || total_plus_ <= 0 || r > r_.back()) return 0.0;
  if (r <= 0 || r < r_[1] * 1e-9) {
    // Limit r -> 0 of f(r) / (2 pi r) on the first linear segment (f(0) = 0 when r_0 = 0).
    return r_.front() == 0 ? f_plus_[1] / r_[1] / (2 * kPi) / total_plus_ : 0.0;
  }
  return pdf_radius(r) / (2 * kPi * r);
}

double TabulatedProfile::invert_radius(double r) const {
  if (r_.empty()) return 0.0;
  if (r <= r_.front()) return 0.0;
  if (r >= r_.back()) return 1.0;
  const std::size_t i = segment(r);
  const double t = r - r_[i];
  const double slope = (f_plus_[i + 1] - f_plus_[i]) / (r_[i + 1] - r_[i]);
  return cdf_[i] + (f_plus_[i] * t + 0.5 * slope * t * t) / total_plus_;
}

double TabulatedProfile::eval(double r) const {
  if (r_.empty() || r > r_.back()) return 0.0;
  if (r <= 0 || r < r_[1] * 1e-9) return r_.front() == 0 ? scale_ * f_[1] / r_[1] / (2 * kPi) : 0.0;
  const std::size_t i = segment(r);
  const double t = (r - r_[i]) / (r_[i + 1] - r_[i]);
  return scale_ * (f_[i] * (1 - t) + f_[i + 1] * t) / (2 * kPi * r);
}

double TabulatedProfile::probability(double r_a, double r_b) const {
  return invert_radius(r_b) - invert_radius(r_a);
}

std::ostream& operator<<(std::ostream& os, const TabulatedProfile& p) {
  return os << "TabulatedProfile{R_d=" << p.R_d() << ", r_max=" << p.r_max()
            << " mm, nodes=" << p.radii().size() << '}';
}

}  // namespace skin::render
