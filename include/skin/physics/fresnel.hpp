#pragma once
// Optics of a smooth dielectric interface: unpolarised Fresnel reflectance and the refracted
// direction's cosine (Snell). The one implementation of the project: the transport solvers, the
// Monte Carlo reference and the renderer's specular lobe all call it. Tested in
// tests/physics/test_fresnel.cpp.
#include <algorithm>
#include <cmath>

namespace skin::physics {

struct FresnelResult {
  double R;      // reflectance, 1 at and beyond total internal reflection
  double cos_t;  // cosine of the refracted ray to the normal, 0 where R = 1
};

// Light from a medium of index n1 into one of index n2, meeting the interface with cosine
// cos_i (> 0) to the normal: R = (r_s^2 + r_p^2) / 2 with the amplitude ratios
// r_s = (n1 cos_i - n2 cos_t) / (n1 cos_i + n2 cos_t), r_p = (n2 cos_i - n1 cos_t) /
// (n2 cos_i + n1 cos_t) (Born & Wolf, section 1.5), n1 sin_i = n2 sin_t. A cosine that rounding
// has pushed past 1 counts as normal incidence (sin^2 clamped at 0).
inline FresnelResult fresnel(double cos_i, double n1, double n2) {
  const double eta = n1 / n2;
  const double sin2_t = eta * eta * std::max(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return {1.0, 0.0};  // total internal reflection
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return {0.5 * (rs * rs + rp * rp), cos_t};
}

// The reflectance alone.
inline double fresnel_dielectric(double cos_i, double n1, double n2) { return fresnel(cos_i, n1, n2).R; }

}  // namespace skin::physics
