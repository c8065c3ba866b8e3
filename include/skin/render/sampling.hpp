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
using Rng = util::Pcg32;

struct Vec2 {
  double x = 0, y = 0;
};

// The numbers of one camera sample (docs/renderer.md, "Sampler"): each call takes one dimension,
// 1D (uniform) or 2D (uniform2). Quasi-random mode: sample `index` of a stream (a pixel's
// replicate) of a padded, Owen-scrambled Sobol sequence (Burley 2020, "Practical Hash-based Owen
// Scrambling"): each dimension is the first Sobol dimension (1D) or the first two (2D) at the
// sample's index shuffled by a nested uniform scramble seeded per (stream, dimension), its
// coordinates Owen-scrambled with seeds of their own. So the first 2^k samples of a stream are a
// (0, k, 2)-net in every dimension (stratified in each, and in each 2D pair, on its own),
// different dimensions are decorrelated, and every number is uniform on [0, 1): estimates stay
// unbiased. Dimensions past kQuasiDimensions of a block, and the random mode, draw from PCG32.
class Sampler {
 public:
  static constexpr std::uint32_t kQuasiDimensions = 64;
  // Random mode: independent numbers from a generator.
  explicit Sampler(const util::Pcg32& rng) : rng_(rng) {}
  // Quasi-random mode: sample `index` of stream `stream` of an image seeded with `seed`.
  Sampler(std::uint64_t seed, std::uint64_t stream, std::uint32_t index);
  double uniform();
  Vec2 uniform2();
  // Start block `block` of dimensions: the following calls take its dimensions from 0, the same
  // ones in every sample of the stream whatever the calls before took (so that a path's later
  // decisions stay stratified when earlier ones took a varying number of dimensions).
  void start_block(std::uint32_t block) {
    key_ = util::mix64(base_ + block);
    dim_ = 0;
  }

 private:
  std::uint32_t next_seed() { return static_cast<std::uint32_t>(util::mix64(key_ + dim_++)); }
  util::Pcg32 rng_;
  std::uint64_t base_ = 0, key_ = 0;
  std::uint32_t reversed_index_ = 0, dim_ = 0;
  bool quasi_ = false;
};
// Parts of the sampler, exposed for tests: the Sobol sequence's first two dimensions at index i
// (32-bit fractions) and the nested uniform (Owen) scramble of a 32-bit fraction.
std::uint32_t sobol_dimension0(std::uint32_t i);
std::uint32_t sobol_dimension1(std::uint32_t i);
std::uint32_t owen_scramble(std::uint32_t v, std::uint32_t seed);

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
