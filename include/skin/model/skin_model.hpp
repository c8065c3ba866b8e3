#pragma once
// The four-parameter skin model end to end: parameters -> per-wavelength layer stacks -> total
// diffuse reflectance spectrum, radial profiles and colour (DJ06 sections 3-4).
#include <vector>

#include "skin/color/color.hpp"
#include "skin/physics/profile.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/physics/stack.hpp"

namespace skin {

struct SkinSpectrum {
  SkinParameters parameters;
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

// R_d(lambda) and colour. Throws InputError for invalid parameters.
SkinSpectrum skin_spectrum(const SkinParameters& p, const WavelengthGrid& grid = {});

// Radial profiles per wavelength, or per linear sRGB channel (colour weights from `grid`).
SpectralProfile skin_spectral_profile(const SkinParameters& p, const WavelengthGrid& grid,
                                      ProfileSolver& solver);
RgbProfile skin_rgb_profile(const SkinParameters& p, const WavelengthGrid& grid,
                            ProfileSolver& solver);

}  // namespace skin
