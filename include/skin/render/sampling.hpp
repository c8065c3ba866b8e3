#pragma once
// The sampling warps of the renderer, each as a matched set
// (sample / pdf / invert where it exists), tested together in tests/render/test_sampling.cpp.
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "skin/render/math.hpp"
#include "skin/util/random.hpp"

namespace skin::render {

// The renderer's generator (skin/util/random.hpp): PCG32, one per pixel sample.
using Rng = Pcg32;

struct Vec2 {
  double x = 0, y = 0;
};

// Cosine-weighted hemisphere around +z (Malley's method: concentric disk, lifted).
Vec3 sample_cosine_hemisphere(Vec2 u);
double pdf_cosine_hemisphere(double cos_theta);  // cos / pi, 0 below the horizon
Vec2 sample_concentric_disk(Vec2 u);
Vec3 sample_uniform_sphere(Vec2 u);
inline double pdf_uniform_sphere() { return 1.0 / (4.0 * kPi); }
// Uniform in the cone of directions within angle acos(cos_theta_max) of +z.
Vec3 sample_uniform_cone(Vec2 u, double cos_theta_max);
double pdf_uniform_cone(double cos_theta_max);

// Piecewise-constant density on [0, 1) from non-negative weights (one per bin).
class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<double> weights);
  // Returns x in [0, 1), its density pdf(x) and the bin index.
  double sample(double u, double* pdf, std::size_t* bin) const;
  double pdf(double x) const;
  double invert(double x) const;  // the u that sample maps to x
  double total() const { return total_; }  // sum of weights / count (integral over [0, 1))
  std::size_t size() const { return w_.size(); }
  double weight(std::size_t i) const { return w_[i]; }

 private:
  std::vector<double> w_, cdf_;
  double total_ = 0;
};

// Piecewise-constant density on [0, 1)^2 (rows = v, columns = u): the marginal in v, then
// the conditional in u (used by environment maps).
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<double>& weights, std::size_t nu, std::size_t nv);
  Vec2 sample(Vec2 u, double* pdf) const;
  double pdf(Vec2 p) const;

 private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
};

// Power heuristic with beta = 2 (Veach 1997, section 9.2.4).
inline double power_heuristic(double f_pdf, double g_pdf) {
  const double f = f_pdf * f_pdf, g = g_pdf * g_pdf;
  return f + g > 0 ? f / (f + g) : 0.0;
}

}  // namespace skin::render
