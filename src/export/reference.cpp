#include "reference.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "skin/color/color.hpp"

namespace skin::exporting::detail {

using skin::util::Rgb;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::RgbProfile;

using skin::model::skin_rgb_profile;

using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

RadialGrid reference_radii() { return RadialGrid::logarithmic(1e-5, 60.0, 400); }

WavelengthGrid spectral_grid() { return WavelengthGrid(400.0, 700.0, 10.0); }

double area_integral(const RadialGrid& radii, const std::vector<double>& f) {
  double sum = 0;
  for (std::size_t j = 1; j < radii.size(); ++j) {
    const double r0 = radii.r[j - 1], r1 = radii.r[j];
    // f 2 pi r dr = f 2 pi r^2 d(ln r)
    const double a = f[j - 1] * r0 * r0, b = f[j] * r1 * r1;
    sum += 0.5 * (a + b) * std::log(r1 / r0);
  }
  return 2.0 * std::numbers::pi * sum;
}

double mean_radius(const RadialGrid& radii, const std::vector<double>& R) {
  std::vector<double> rR(R.size());
  for (std::size_t j = 0; j < R.size(); ++j) rR[j] = radii.r[j] * R[j];
  const double total = area_integral(radii, R);
  return total > 0 ? area_integral(radii, rR) / total : 0.0;
}

double relative_l1(const RadialGrid& radii, const std::vector<double>& a,
                   const std::vector<double>& b) {
  std::vector<double> d(a.size());
  for (std::size_t j = 0; j < a.size(); ++j) d[j] = std::abs(a[j] - b[j]);
  const double norm = area_integral(radii, b);
  return norm > 0 ? area_integral(radii, d) / norm : 0.0;
}

double delta_e(const Rgb& a, const Rgb& b) {
  const color::Xyz white = color::srgb_linear_to_xyz({1.0, 1.0, 1.0});
  return color::delta_e_2000(color::xyz_to_lab(color::srgb_linear_to_xyz(a), white),
                             color::xyz_to_lab(color::srgb_linear_to_xyz(b), white));
}

double invert_increasing(const std::function<double(double)>& f, double y, double lo, double hi) {
  if (y <= f(lo)) return lo;
  if (y >= f(hi)) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < y ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

WavelengthGrid reference_grid() { return WavelengthGrid{}; }

Reference make_reference(const SkinParameters& p, const transport::Model& model,
                         ProfileSolver& solver, const util::ProgressCallback& progress,
                         bool spectral) {
  Reference ref;
  ref.parameters = p;
  ref.model = &model;
  ref.radii = solver.radii();
  RgbProfile prof;
  if (spectral) {
    model::SkinProfiles both = model::skin_profiles(p, reference_grid(), solver, model, spectral_grid(), progress);
    prof = std::move(both.rgb);
    ref.spectral = std::move(both.spectral);
  } else {
    prof = skin_rgb_profile(p, reference_grid(), solver, model, progress);
  }
  for (int c = 0; c < 3; ++c) {
    ref.R[c] = prof.R[c];
    for (double& v : ref.R[c]) v = std::max(v, 0.0);
    ref.mean_radius[c] = mean_radius(ref.radii, ref.R[c]);
  }
  ref.R_d = {prof.R_d[0], prof.R_d[1], prof.R_d[2]};
  return ref;
}

}  // namespace skin::exporting::detail
