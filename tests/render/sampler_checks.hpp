#pragma once
// Checks shared by the renderer's sampler tests: Pearson's chi-square against expected bin
// probabilities, quadrature rules, the chi-square of directions on the sphere, and a skin profile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "skin/model/skin_model.hpp"
#include "test_support.hpp"
#include "skin/render/math.hpp"
#include "skin/render/profile_sampler.hpp"
#include "skin/render/sampling.hpp"

namespace skin::render::test {

using skin::test::chi_square_p;  // tests/common/test_support.hpp

// Integral of f over [a, b] by composite Simpson (n even).
inline double simpson(const std::function<double(double)>& f, double a, double b, int n = 200) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += f(a + i * h) * (i % 2 ? 4 : 2);
  return s * h / 3;
}

// Midpoint rule (avoids the end points, where some pdfs have integrable singularities).
inline double midpoint(const std::function<double(double)>& f, double a, double b, int n) {
  double s = 0;
  for (int i = 0; i < n; ++i) s += f(a + (i + 0.5) * (b - a) / n);
  return s * (b - a) / n;
}

// Chi-square of directions on the sphere: bins in (cos theta, phi), expected from the pdf
// integrated numerically over each bin (midpoint rule in both coordinates).
// `sub` is the midpoint rule's number of points per bin in phi (three times as many in cos theta):
// raise it where the pdf has edges inside bins (the outline of a quad light).
inline void direction_chi_square(const std::function<bool(Vec2, Vec3*)>& sample,
                                 const std::function<double(const Vec3&)>& pdf, std::uint64_t seed,
                                 double* p_value, double* pdf_integral, int sub = 8) {
  constexpr int kTheta = 20, kPhi = 40, kN = 200000;
  std::vector<double> prob(kTheta * kPhi), counts(kTheta * kPhi, 0.0);
  double total = 0;
  for (int i = 0; i < kTheta; ++i)
    for (int j = 0; j < kPhi; ++j) {
      const double c0 = -1 + 2.0 * i / kTheta, c1 = -1 + 2.0 * (i + 1) / kTheta;
      const double p0 = 2 * kPi * j / kPhi, p1 = 2 * kPi * (j + 1) / kPhi;
      const double v = midpoint([&](double c) {
        return midpoint([&](double ph) {
          const double s = std::sqrt(std::max(0.0, 1 - c * c));
          return pdf({s * std::cos(ph), s * std::sin(ph), c});
        }, p0, p1, sub);
      }, c0, c1, 3 * sub);
      prob[static_cast<std::size_t>(i * kPhi + j)] = v;
      total += v;
    }
  Rng rng(seed, 3);
  for (int k = 0; k < kN; ++k) {
    Vec3 w;
    if (!sample({rng.uniform(), rng.uniform()}, &w)) continue;
    const int i = std::clamp(static_cast<int>((w.z + 1) / 2 * kTheta), 0, kTheta - 1);
    double ph = std::atan2(w.y, w.x);
    if (ph < 0) ph += 2 * kPi;
    const int j = std::clamp(static_cast<int>(ph / (2 * kPi) * kPhi), 0, kPhi - 1);
    counts[static_cast<std::size_t>(i * kPhi + j)] += 1;
  }
  // Samples that failed (below the horizon) carry the missing probability mass.
  double n_ok = 0;
  for (double c : counts) n_ok += c;
  for (auto& p : prob) p /= total;
  *p_value = chi_square_p(counts, prob, n_ok);
  *pdf_integral = total;
}

// One channel (0, 1, 2 = r, g, b) of the caucasian preset's RGB profile on the renderer's grid.
inline TabulatedProfile skin_channel(int c) {
  std::vector<double> r{0.0};
  const transport::RadialGrid g = transport::RadialGrid::logarithmic(1e-3, 20.0, 128);
  r.insert(r.end(), g.r.begin(), g.r.end());
  transport::ProfileSolver solver(transport::RadialGrid::from(r));
  const transport::RgbProfile p = model::skin_rgb_profile(physics::find_preset("caucasian").parameters, physics::WavelengthGrid(400, 700, 10), solver);
  return TabulatedProfile(p.radii.r, p.R[static_cast<std::size_t>(c)], p.R_d[static_cast<std::size_t>(c)]);
}

}  // namespace skin::render::test
