// The camera, the film and the sample passes of a render (film.hpp; docs/renderer.md).
#include "film.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene_data.hpp"

namespace skin::render {

PinholeCamera::PinholeCamera(const Camera& c, int width, int height)
    : eye_(c.eye),
      fwd_(normalize(c.target - c.eye)),
      right_(normalize(cross(fwd_, c.up))),
      up_(cross(right_, fwd_)),
      tan_half_(std::tan(c.fov_deg * kPi / 360.0)),
      aspect_(static_cast<double>(width) / height) {}

Film::Film(std::size_t pixels)
    : sum_(pixels), sum_sq_(pixels), sum_odd_(pixels), taken_(pixels, 0), skin_hits_(pixels, 0) {}

void Film::set(std::size_t p, const Pixel& px, std::uint32_t taken) {
  sum_[p] = px.sum;
  sum_sq_[p] = px.sum_sq;
  sum_odd_[p] = px.sum_odd;
  skin_hits_[p] = px.skin_hits;
  taken_[p] = taken;
}

std::uint64_t Film::samples() const {
  std::uint64_t n = 0;
  for (const std::uint32_t t : taken_) n += t;
  return n;
}

Rgb3 Film::mean(std::size_t p) const { return taken_[p] > 0 ? sum_[p] / static_cast<double>(taken_[p]) : Rgb3{}; }

double Film::spread_variance(std::size_t p) const {
  const double n = taken_[p];
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const Rgb3 m = sum_[p] / n, q = sum_sq_[p] / n;
  const double v = std::max(0.0, q.r - m.r * m.r) + std::max(0.0, q.g - m.g * m.g) + std::max(0.0, q.b - m.b * m.b);
  return v / 3.0 / (n - 1);  // (n / (n - 1)) x the biased variance, / n
}

double Film::replicate_variance(std::size_t p) const {
  const std::uint32_t n = taken_[p], n_odd = n / 2, n_even = n - n_odd;
  if (n_odd < 1) return std::numeric_limits<double>::quiet_NaN();
  const Rgb3 d = (sum_[p] - sum_odd_[p]) / static_cast<double>(n_even) - sum_odd_[p] / static_cast<double>(n_odd);
  const double nn = static_cast<double>(n);
  return (d.r * d.r + d.g * d.g + d.b * d.b) / 3.0 * (static_cast<double>(n_even) * n_odd / (nn * nn));
}

double Film::skin_mean() const {
  double total = 0, all = 0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < pixels(); ++p) {
    const Rgb3 m = mean(p);
    all += (m.r + m.g + m.b) / 3;
    if (is_skin(p)) {
      total += (m.r + m.g + m.b) / 3;
      ++n;
    }
  }
  return n > 0 ? total / static_cast<double>(n) : all / static_cast<double>(pixels());
}

Image Film::image(int width, int height) const {
  Image img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) img.set(x, y, mean(static_cast<std::size_t>(y) * width + x));
  return img;
}

void Film::fill(RenderStats* stats) const {
  stats->camera_samples = samples();
  stats->skin_mask.assign(pixels(), 0);
  stats->skin_pixels = 0;
  double var = 0;
  for (std::size_t p = 0; p < pixels(); ++p)
    if (is_skin(p)) {
      stats->skin_mask[p] = 1;
      ++stats->skin_pixels;
      var += replicate_variance(p);
    }
  const double m = skin_mean();
  stats->estimated_error = stats->skin_pixels > 0 && m > 0 ? std::sqrt(var / static_cast<double>(stats->skin_pixels)) / m
                                                           : std::numeric_limits<double>::quiet_NaN();
}

SamplePasses::SamplePasses(const RenderSettings& settings, int spp, std::size_t pixels)
    : target_error_(settings.target_error), time_budget_(settings.time_budget), spp_(spp), active_(pixels, 1) {}

int SamplePasses::end(int done) const {
  if (time_budget_ > 0) return done + 1;
  if (target_error_ > 0) return std::min(spp_, done == 0 ? kAdaptiveFirstPass : 2 * done);
  return spp_;
}

int SamplePasses::count() const {
  int passes = 0;
  for (int d = 0; d < spp_; d = end(d)) ++passes;
  return passes;
}

bool SamplePasses::converged(const Film& film, int done) {
  if (!(target_error_ > 0) || done >= spp_) return false;
  // Samples in proportion to each pixel's standard deviation sigma_p (the allocation that
  // minimises the RMS error over the pixels for a number of samples): the error^2 is then
  // mean(sigma_p^2 / n_p) = kappa mean(sigma_p) with n_p = sigma_p / kappa, so the target
  // sets kappa = (E M)^2 / mean(sigma_p), M the skin's mean. A pixel stops once n_p reaches
  // sigma_p / kappa; the render once all have, or once the estimated error is within E.
  const double limit = target_error_ * film.skin_mean();
  // The spread overstates the quasi-random error: scaled by the ratio rho of the two
  // estimates over the skin, it sets each pixel's share.
  double sigma_sum = 0, spread_sum = 0, var_sum = 0;
  std::size_t skin = 0;
  for (std::size_t p = 0; p < film.pixels(); ++p)
    if (film.is_skin(p)) {
      const double v = film.spread_variance(p);
      sigma_sum += std::sqrt(v * film.taken(p));
      spread_sum += v;
      var_sum += film.replicate_variance(p);
      ++skin;
    }
  if (skin == 0 || var_sum / static_cast<double>(skin) <= limit * limit) return true;
  const double rho = spread_sum > 0 ? var_sum / spread_sum : 1.0;
  const double kappa = limit * limit / (std::sqrt(rho) * sigma_sum / static_cast<double>(skin));
  std::size_t still = 0;
  for (std::size_t p = 0; p < film.pixels(); ++p) {
    if (active_[p] && film.taken(p) >= static_cast<std::uint32_t>(kAdaptiveFirstPass) &&
        !(std::sqrt(rho * film.spread_variance(p) * film.taken(p)) > kappa * film.taken(p)))
      active_[p] = 0;
    still += active_[p];
  }
  return still == 0;
}

}  // namespace skin::render
