#pragma once
// The image side of a render (internal; docs/renderer.md): the pinhole camera that makes the
// camera rays, the film that sums each pixel's samples and estimates their error, and the sample
// passes with adaptive sampling, which stops a pixel once its share of the target error is met.
#include <cstdint>
#include <vector>

#include "skin/render/image.hpp"
#include "skin/render/math.hpp"
#include "skin/render/scene.hpp"

namespace skin::render {

struct Camera;

// Pinhole camera: vertical field of view, looking from eye to target, over a W x H image.
class PinholeCamera {
 public:
  PinholeCamera(const Camera& camera, int width, int height);
  const Vec3& eye() const { return eye_; }
  // The direction through the image point (px, py), each in [0, 1], py down.
  Vec3 direction(double px, double py) const {
    return normalize(fwd_ + right_ * ((2 * px - 1) * tan_half_ * aspect_) + up_ * ((1 - 2 * py) * tan_half_));
  }

 private:
  Vec3 eye_, fwd_, right_, up_;
  double tan_half_ = 0, aspect_ = 1;
};

// Per pixel: the sum of the samples, of their squares and of the odd samples (two replicates:
// even and odd samples are independently scrambled sequences), the samples taken and how many of
// them saw a translucent material first.
class Film {
 public:
  struct Pixel {
    Rgb3 sum, sum_sq, sum_odd;
    std::uint32_t skin_hits = 0;
  };
  explicit Film(std::size_t pixels);
  std::size_t pixels() const { return sum_.size(); }
  Pixel pixel(std::size_t p) const { return {sum_[p], sum_sq_[p], sum_odd_[p], skin_hits_[p]}; }
  // Stores a pixel's sums after its samples up to `taken`.
  void set(std::size_t p, const Pixel& px, std::uint32_t taken);
  std::uint32_t taken(std::size_t p) const { return taken_[p]; }
  std::uint64_t samples() const;  // over all pixels

  // The mean of a pixel's samples.
  Rgb3 mean(std::size_t p) const;
  // Two estimates of the variance of that mean, averaged over the channels. From the samples'
  // spread (as if independent): what the quasi-random samples' stratification removes it does
  // not see, so it overstates the error; used for the pixels' shares of the samples.
  double spread_variance(std::size_t p) const;
  // From the two replicates: their means differ by d with E[d^2] = var(m_e) + var(m_o), and for
  // samples of one variance var(m) = E[d^2] n_e n_o / n^2 (1/4 for equal halves); unbiased, one
  // degree of freedom per pixel, so its sum over the skin pixels is what the error estimate uses.
  double replicate_variance(std::size_t p) const;
  // A skin pixel: most of its samples see a translucent material first.
  bool is_skin(std::size_t p) const { return taken_[p] > 0 && 2 * skin_hits_[p] > taken_[p]; }
  // Mean over the skin pixels and channels (over all pixels if none is skin).
  double skin_mean() const;

  Image image(int width, int height) const;
  // The skin mask, skin pixels, samples and estimated error of RenderStats.
  void fill(RenderStats* stats) const;

 private:
  std::vector<Rgb3> sum_, sum_sq_, sum_odd_;
  std::vector<std::uint32_t> taken_, skin_hits_;
};

// Adaptive sampling: the first pass's samples per pixel (also the fewest a pixel takes) and the
// most a pixel takes unless --spp says otherwise.
inline constexpr int kAdaptiveFirstPass = 16;
inline constexpr int kAdaptiveMaxSpp = 65536;

// The sample passes of a render: one sample per pixel under a time budget; 16 per pixel, then
// doubling, when adaptive (a target error); otherwise all at once. Adaptive: after each pass,
// which pixels go on.
class SamplePasses {
 public:
  SamplePasses(const RenderSettings& settings, int spp, std::size_t pixels);
  int spp() const { return spp_; }
  // The samples per pixel at the end of the pass that starts at `done`.
  int end(int done) const;
  int count() const;  // passes up to spp
  bool active(std::size_t p) const { return active_[p] != 0; }
  // After a pass up to `done`: with a target error, stops the pixels that have their share of
  // samples; true when the render is done (the target met, or no pixel left).
  bool converged(const Film& film, int done);

 private:
  double target_error_ = 0, time_budget_ = 0;
  int spp_ = 0;
  std::vector<std::uint8_t> active_;
};

}  // namespace skin::render
