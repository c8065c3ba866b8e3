#pragma once
// The sampling routines of the Monte Carlo solver, as matched sets
// (sample / pdf / invert), so that tests can check each against the others.
#include <cmath>
#include <cstdint>
#include <iosfwd>

#include "skin/util/random.hpp"

namespace skin::mc {

// The Monte Carlo solver's generator (its stream is part of the golden numbers).
using Rng = util::Xoshiro256Plus;

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

// hg_sample_cos for one g, with its constants computed once (the Monte Carlo inner loop):
// mu = (1 + g^2 - (1 - g^2)^2 / (1 - g + 2 g u)^2) / (2 g), the same formula (equal to
// hg_sample_cos up to rounding, tested), one division per sample.
class HenyeyGreenstein {
 public:
  explicit HenyeyGreenstein(double g = 0)
      : isotropic_(std::abs(g) < 1e-6), a_(1.0 - g), b_(2.0 * g), c_(1.0 + g * g),
        d_((1.0 - g * g) * (1.0 - g * g)), e_(isotropic_ ? 0.0 : 0.5 / g) {}
  double sample_cos(double u) const {
    if (isotropic_) return 2.0 * u - 1.0;
    const double t = a_ + b_ * u;
    const double mu = (c_ - d_ / (t * t)) * e_;
    return mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu);
  }

 private:
  bool isotropic_;
  double a_, b_, c_, d_, e_;
};

// A uniform azimuth phi in [0, 2 pi) from 64 random bits: cos(phi) and sin(phi), without a
// rejection loop or a trigonometric call (a table of 256 sectors and short Taylor series inside
// each; within 2e-15 of std::cos / std::sin of phi = 2 pi bits / 2^64, up to the 2^-61 grid).
struct Azimuth {
  double cos_phi, sin_phi;
};
Azimuth azimuth(std::uint64_t bits);

// The direction (ux, uy, uz) (unit) after scattering by the polar angle theta and the azimuth
// phi, given cos(theta) and the products sin(theta) cos(phi), sin(theta) sin(phi):
// u' = cos(theta) u + sin(theta) (cos(phi) e1 + sin(phi) e2), with (e1, e2, u) the orthonormal
// frame of Duff et al. 2017 ("Building an orthonormal basis, revisited", JCGT 6(1)),
// s = sign(uz), a = -1 / (s + uz): e1 = (1 + s ux^2 a, s ux uy a, -s ux), e2 = (ux uy a,
// s + uy^2 a, -uy). Collected, with m = s ux sin(theta) cos(phi) + uy sin(theta) sin(phi):
//   u'x = ux cos(theta) + sin(theta) cos(phi) - m ux / (s + uz),
//   u'y = uy cos(theta) + s sin(theta) sin(phi) - m uy / (s + uz),   u'z = uz cos(theta) - m:
// one division (|s + uz| >= 1), no square root, no special case near the poles, and a short
// chain of dependent operations from one direction to the next (the photon loop's bottleneck).
// The frame differs from MCML's (eq. 3.25), but phi is uniform, so u' has the same distribution.
inline void scatter_direction(double& ux, double& uy, double& uz, double cos_t, double st_cp,
                              double st_sp) {
  const double sign = std::copysign(1.0, uz);
  const double m = sign * st_cp * ux + st_sp * uy;
  const double h = m / (sign + uz);
  const double nx = (ux * cos_t + st_cp) - h * ux;
  const double ny = (uy * cos_t + sign * st_sp) - h * uy;
  uz = uz * cos_t - m;
  ux = nx;
  uy = ny;
}

// Exponential free path in optical depth: tau = -ln(u), u in (0, 1]; pdf exp(-tau);
// invert: u = exp(-tau).
inline double sample_optical_depth(double u) { return -std::log(u); }
inline double pdf_optical_depth(double tau) { return tau < 0 ? 0.0 : std::exp(-tau); }
inline double invert_optical_depth(double tau) { return std::exp(-tau); }
// The same distribution drawn without a logarithm, for the inner loop: Boost.Random's ziggurat
// for the unit exponential (Marsaglia & Tsang 2000, "The ziggurat method for generating random
// variables", J. Stat. Softw. 5(8); 256 layers), which in about 99 % of draws takes one 64-bit
// draw, a table lookup, a multiplication and a comparison. Exact in distribution (tested by
// chi-square against exp(-tau), tail included). Draws a different number of values from `rng`
// than sample_optical_depth(rng.uniform_open0()), so the two give different streams.
double sample_optical_depth(Rng& rng);

}  // namespace skin::mc
