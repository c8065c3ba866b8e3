#pragma once
// The four-parameter skin model end to end: parameters -> per-wavelength layer stacks -> total
// diffuse reflectance spectrum, radial profiles and colour (DJ06 sections 3-4).
#include <string_view>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/transport/profile.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/transport/stack.hpp"

namespace skin {

// Which model of light transport in the layers computes reflectance:
// - accurate (the default): totals by the adding-doubling method (radiative transfer with a
//   Henyey-Greenstein phase function, exact Fresnel boundaries), within Monte Carlo noise for every
//   skin type; profiles from Monte Carlo transport of the epidermis (a built-in table) coupled
//   to a diffusion dermis, integrating exactly to those totals, within 10 % of Monte Carlo over
//   0.1-5 mm (docs/accurate-solver.md). Default because the multipole overstates dark skin's
//   reflectance 2-3x in the blue, and the colour follows the totals and the BSSRDF the profiles.
// - multipole: the paper's method (DJ05 multipole, convolved in the frequency domain), kept
//   unchanged to reproduce the paper.
enum class Solver { accurate, multipole };
std::string_view to_string(Solver s);
// "accurate" or "multipole"; throws InputError otherwise.
Solver parse_solver(std::string_view name);

struct SkinSpectrum {
  SkinParameters parameters;
  Solver solver = Solver::accurate;
  WavelengthGrid grid;
  Spectrum epidermis_sigma_a, epidermis_sigma_s_prime;  // [1/mm]
  Spectrum dermis_sigma_a, dermis_sigma_s_prime;        // [1/mm]
  Spectrum R_d;                                         // total diffuse reflectance
  color::ColorSummary color;                            // colour of R_d under D65
};

// One two-layer stack per wavelength (validates the parameters).
std::vector<LayerStack> skin_layer_stacks(const SkinParameters& p, const WavelengthGrid& grid);
std::vector<DiffusionStack> skin_diffusion_stacks(const SkinParameters& p,
                                                  const WavelengthGrid& grid);

// Total diffuse reflectance (per power that entered) of one layer stack by either solver.
double stack_R_d(const LayerStack& stack, Solver solver);

// R_d(lambda) and colour. Throws InputError for invalid parameters.
SkinSpectrum skin_spectrum(const SkinParameters& p, const WavelengthGrid& grid = {},
                           Solver solver = Solver::accurate);

// Radial profiles per wavelength, or per linear sRGB channel (colour weights from `grid`).
SpectralProfile skin_spectral_profile(const SkinParameters& p, const WavelengthGrid& grid,
                                      ProfileSolver& profiles, Solver solver = Solver::accurate);
RgbProfile skin_rgb_profile(const SkinParameters& p, const WavelengthGrid& grid,
                            ProfileSolver& profiles, Solver solver = Solver::accurate);

}  // namespace skin
