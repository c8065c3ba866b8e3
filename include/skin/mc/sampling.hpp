#pragma once
// The sampling routines of the Monte Carlo solver, as matched sets
// (sample / pdf / invert), so that tests can check each against the others.
#include <cmath>
#include <cstdint>
#include <iosfwd>

#include "skin/util/random.hpp"

namespace skin::mc {

// The Monte Carlo solver's generator (its stream is part of the golden numbers).
using Rng = Xoshiro256Plus;

// Henyey-Greenstein phase function in the cosine of the scattering angle, normalised over
// cos_theta in [-1, 1]:  p(mu) = (1 - g^2) / (2 (1 + g^2 - 2 g mu)^{3/2})  (Henyey & Greenstein
// 1941; the 1/(4 pi) solid-angle form times 2 pi). Mean cosine g.
double hg_pdf_cos(double g, double mu);
// Inverse-CDF sample for u in [0, 1): mu = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g),
// and mu = 2u - 1 for |g| < 1e-6 (the limit). Result clamped to [-1, 1] against rounding.
inline double hg_sample_cos(double g, double u) {
  if (std::abs(g) < 1e-6) return 2.0 * u - 1.0;
  const double t = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  const double mu = (1.0 + g * g - t * t) / (2.0 * g);
  return mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu);
}
// The CDF, u = P(cos_theta <= mu): inverts hg_sample_cos.
double hg_invert_cos(double g, double mu);

// Exponential free path in optical depth: tau = -ln(u), u in (0, 1]; pdf exp(-tau);
// invert: u = exp(-tau).
inline double sample_optical_depth(double u) { return -std::log(u); }
inline double pdf_optical_depth(double tau) { return tau < 0 ? 0.0 : std::exp(-tau); }
inline double invert_optical_depth(double tau) { return std::exp(-tau); }

}  // namespace skin::mc
