#pragma once
// Optical description of a plane-parallel stack of turbid layers, top to bottom.
// Lengths in mm, coefficients in 1/mm.
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace skin::physics {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Layer {
  double sigma_a = 0.0;           // absorption coefficient [1/mm]
  double sigma_s_prime = 1.0;     // reduced scattering coefficient sigma_s (1 - g) [1/mm]
  double thickness = kInfinity;   // [mm]; infinity = semi-infinite (only the last layer)
  double eta = 1.4;               // refractive index
  double g = 0.9;                 // Henyey-Greenstein anisotropy (transport solvers; diffusion
                                  // sees only sigma_s_prime)
  bool semi_infinite() const { return thickness == kInfinity; }
  double sigma_s() const { return sigma_s_prime / (1.0 - g); }  // [1/mm]
  bool operator==(const Layer&) const = default;
};

struct LayerStack {
  std::vector<Layer> layers;  // top to bottom
  double eta_above = 1.0;     // medium above the top surface (air)
  double eta_below = 1.0;     // medium below the last layer (unused if it is semi-infinite)

  bool semi_infinite() const { return !layers.empty() && layers.back().semi_infinite(); }
  // Throws InputError naming the layer (1-based) and parameter: empty stack, sigma_a < 0,
  // sigma_s_prime <= 0, thickness <= 0, a semi-infinite layer that is not the last, eta outside
  // [1, 3], g outside (-1, 1), NaN anywhere.
  void validate() const;
  bool operator==(const LayerStack&) const = default;
};

std::ostream& operator<<(std::ostream& os, const Layer& l);
std::ostream& operator<<(std::ostream& os, const LayerStack& s);
std::string to_string(const LayerStack& s);

}  // namespace skin::physics
