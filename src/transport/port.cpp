// Light collected through a port (port.hpp).
#include "skin/transport/port.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "skin/util/error.hpp"

namespace skin::transport {

double port_overlap(double a, double b, double r) {
  if (b <= 0) return r < a ? 1.0 : 0.0;
  if (r >= a + b) return 0.0;
  if (r <= std::abs(a - b)) return a >= b ? 1.0 : (a * a) / (b * b);
  // The lens of two circles (radii a, b, centres r apart), over the beam's area pi b^2.
  const double ca = std::clamp((r * r + a * a - b * b) / (2 * r * a), -1.0, 1.0);
  const double cb = std::clamp((r * r + b * b - a * a) / (2 * r * b), -1.0, 1.0);
  const double k = std::max(0.0, (-r + a + b) * (r + a - b) * (r - a + b) * (r + a + b));
  const double lens = a * a * std::acos(ca) + b * b * std::acos(cb) - 0.5 * std::sqrt(k);
  return std::clamp(lens / (std::numbers::pi * b * b), 0.0, 1.0);
}

namespace {
constexpr std::size_t kPortRadii = 256;
RadialGrid port_radii(double a, double b) {
  if (!(a > 0) || !std::isfinite(a) || a > kMaxRadius / 20)
    throw util::InputError("port-radius = " + util::format_number(a) + " mm is out of range: allowed (0, " +
                           util::format_number(kMaxRadius / 20) + "] mm");
  if (!(b >= 0) || !(b <= a))
    throw util::InputError("beam-radius = " + util::format_number(b) + " mm is out of range: allowed [0, " +
                           util::format_number(a) + "] mm (at most the port radius)");
  const double r0 = std::max(a - b, 1e-4 * a), r1 = std::min(kMaxRadius, std::max(60.0, 20 * (a + b)));
  return RadialGrid::logarithmic(r0, r1, kPortRadii);
}
}  // namespace

PortCollection::PortCollection(double port_radius, double beam_radius)
    : port_(port_radius), beam_(beam_radius), solver_(port_radii(port_radius, beam_radius)) {
  // Trapezoid in ln r: 2 pi (1 - O(r)) r dr = 2 pi (1 - O(r)) r^2 d(ln r).
  const auto& r = solver_.radii().r;
  const double h = std::log(r[1] / r[0]);
  loss_weight_.resize(r.size());
  for (std::size_t j = 0; j < r.size(); ++j) {
    const double end = (j == 0 || j + 1 == r.size()) ? 0.5 : 1.0;
    loss_weight_[j] = end * h * 2 * std::numbers::pi * r[j] * r[j] * (1.0 - port_overlap(port_, beam_, r[j]));
  }
}

double PortCollection::collected(const RadialResponse& response) {
  const std::vector<double> R = solver_.profile(response);
  double lost = 0;
  for (std::size_t j = 0; j < R.size(); ++j) lost += loss_weight_[j] * R[j];
  return std::min(response.total(), response.total() - lost);
}

}  // namespace skin::transport
