#pragma once
// What every export starts from: our skin's RGB profile, colour and mean exit radii, and the
// helpers the fits and the reports share. Internal to skin::export.
#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "skin/export/export.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/profile.hpp"

namespace skin::exporting::detail {

// Our skin on a logarithmic radial grid [mm] (negative tails of out-of-gamut channels clamped to
// zero for the fits and the error integrals).
struct Reference {
  physics::SkinParameters parameters;
  const transport::Model* model = nullptr;
  transport::RadialGrid radii;
  std::array<std::vector<double>, 3> R;  // [1/mm^2]
  util::Rgb R_d;                               // channel totals (exact, from k = 0)
  std::array<double, 3> mean_radius{};   // [mm]
  // With `spectral`: the per-wavelength profiles on spectral_grid() (pbrt-v4's spectra), from the
  // responses of the RGB profile's wavelengths (the 10 nm grid lies on the 2 nm one): no wavelength
  // is solved twice, and the estimate and the bar of the one solve cover them.
  std::optional<transport::SpectralProfile> spectral;
};
Reference make_reference(const physics::SkinParameters& p, const transport::Model& model,
                         transport::ProfileSolver& solver, const util::ProgressCallback& progress = {},
                         bool spectral = false);
// The wavelengths of a reference's profile (the paper's 2 nm grid).
physics::WavelengthGrid reference_grid();
// The radial grid every reference uses.
transport::RadialGrid reference_radii();
// The grid of the spectra the files hold (400-700 nm, 10 nm).
physics::WavelengthGrid spectral_grid();

// int f(r) 2 pi r dr on the log grid (trapezoid in ln r).
double area_integral(const transport::RadialGrid& radii, const std::vector<double>& f);
double mean_radius(const transport::RadialGrid& radii, const std::vector<double>& R);
// int |2 pi r (a - b)| dr / int 2 pi r b dr.
double relative_l1(const transport::RadialGrid& radii, const std::vector<double>& a,
                   const std::vector<double>& b);
// CIEDE2000 between two linear sRGB colours (D65 white).
double delta_e(const util::Rgb& a, const util::Rgb& b);

// Solves f(x) = y for increasing f on [lo, hi] by bisection; returns the clamped end when y is
// outside [f(lo), f(hi)].
double invert_increasing(const std::function<double(double)>& f, double y, double lo, double hi);

}  // namespace skin::exporting::detail
