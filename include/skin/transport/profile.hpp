#pragma once
// Radial diffusion profiles R(r) of layer stacks, per wavelength and per colour channel.
// R(r) = dipole_top(r) + (1 / 2 pi) int_0^inf G(k) J0(k r) k dk,  G = R_stack(k) - dipole_top(k):
// the top layer's nearest image pair (all of the r -> 0 singularity) is inverted exactly in space,
// and only the smooth, fast-decaying remainder G is transformed numerically: G is sampled at ~150
// frequencies up to a k_max where it has decayed, interpolated, and integrated against J0 by
// Gauss-Legendre panels (product integration; the weights depend only on the radii and are
// cached). Accuracy: ~1e-6 relative where R is not tiny, ~1e-8 of the peak absolutely (tested).
#include <array>
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/transport/profile_fwd.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/transport/stack.hpp"

namespace skin::transport {

// The largest radius a profile is evaluated at [mm]: a metre of tissue, far beyond any rendering or
// measurement of skin. The panels of the product integration grow with the largest radius (a
// profile to 1e10 mm ran for minutes without ending), so larger radii are refused.
inline constexpr double kMaxRadius = 1000.0;

// Radii at which a profile is evaluated [mm], increasing, >= 0, at most kMaxRadius.
struct RadialGrid {
  std::vector<double> r;
  // n radii spaced evenly in log r from r_min to r_max (both > 0).
  static RadialGrid logarithmic(double r_min, double r_max, std::size_t n);
  // n radii from 0 to r_max inclusive.
  static RadialGrid linear(double r_max, std::size_t n);
  // Radii as given (validated: finite, >= 0, increasing).
  static RadialGrid from(std::vector<double> r);
  std::size_t size() const { return r.size(); }
  double max() const { return r.empty() ? 0.0 : r.back(); }
  bool operator==(const RadialGrid&) const = default;
};
std::ostream& operator<<(std::ostream& os, const RadialGrid& g);

// A profile per wavelength: R[i * radii.size() + j] = R(radii[j], grid[i]) [1/mm^2].
struct SpectralProfile {
  physics::WavelengthGrid grid;
  RadialGrid radii;
  std::vector<double> R;
  physics::Spectrum R_d;  // totals, from k = 0 (exact, no integration)
  double at(std::size_t i_lambda, std::size_t j_r) const { return R[i_lambda * radii.size() + j_r]; }
};

// A profile per colour channel [1/mm^2], and the channel totals.
struct RgbProfile {
  RadialGrid radii;
  std::array<std::vector<double>, 3> R;
  std::array<double, 3> R_d{};
};
std::ostream& operator<<(std::ostream& os, const RgbProfile& p);

// Inverts many spectra onto one radial grid. Keeps the quadratures of the last few k_max between
// calls (they depend only on the radii and k_max), so repeated calls cost only the evaluation of
// G, also when parameters that move k_max between two values are swept (the web page's sliders).
// Not thread-safe: use one per thread.
class ProfileSolver {
 public:
  explicit ProfileSolver(RadialGrid radii);
  ~ProfileSolver();
  ProfileSolver(ProfileSolver&&) noexcept;
  ProfileSolver& operator=(ProfileSolver&&) noexcept;

  const RadialGrid& radii() const { return radii_; }

  // R(r) of one stack at the solver's radii.
  std::vector<double> profile(const RadialResponse& stack);
  // One response per wavelength of `grid` (size == grid.size()).
  SpectralProfile spectral(const std::vector<const RadialResponse*>& stacks,
                           const physics::WavelengthGrid& grid);
  // Three channels; the weighting is linear, so it is applied in the frequency domain before the
  // inverse transform (three transforms instead of one per wavelength).
  RgbProfile rgb(const std::vector<const RadialResponse*>& stacks, const physics::ChannelWeights& weights);
  // Conveniences for the multipole model.
  SpectralProfile spectral(const std::vector<DiffusionStack>& stacks, const physics::WavelengthGrid& grid);
  RgbProfile rgb(const std::vector<DiffusionStack>& stacks, const physics::ChannelWeights& weights);

  // Upper frequency of the numerical transform for these stacks [rad/mm] (where |G| has fallen
  // below 1e-10 of the total), and the number of frequency samples used by the last call.
  static double k_max_for(const std::vector<const RadialResponse*>& stacks);
  std::size_t nodes_used() const;

 private:
  struct Quadrature;
  const Quadrature& quadrature_for(double k_max);
  RadialGrid radii_;
  std::vector<std::unique_ptr<Quadrature>> quads_;  // most recently used last
};

// Trapezoid estimate of 2 pi int R(r) r dr over the grid (for checks of a tabulated profile).
double integrate_profile(const RadialGrid& radii, const std::vector<double>& R);

}  // namespace skin::transport
