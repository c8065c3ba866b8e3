#include "skin/model/skin_model.hpp"

namespace skin {

std::vector<LayerStack> skin_layer_stacks(const SkinParameters& p, const WavelengthGrid& grid) {
  p.validate();
  std::vector<LayerStack> stacks;
  stacks.reserve(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) stacks.push_back(skin_layer_stack(p, grid[i]));
  return stacks;
}

std::vector<DiffusionStack> skin_diffusion_stacks(const SkinParameters& p,
                                                  const WavelengthGrid& grid) {
  std::vector<DiffusionStack> out;
  out.reserve(grid.size());
  for (const auto& s : skin_layer_stacks(p, grid)) out.emplace_back(s);
  return out;
}

SkinSpectrum skin_spectrum(const SkinParameters& p, const WavelengthGrid& grid) {
  p.validate();
  SkinSpectrum s{p,           grid,         Spectrum(grid), Spectrum(grid), Spectrum(grid),
                 Spectrum(grid), Spectrum(grid), {}};
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double lambda = grid[i];
    const auto e = epidermis_coefficients(p, lambda);
    const auto d = dermis_coefficients(p, lambda);
    s.epidermis_sigma_a[i] = e.sigma_a;
    s.epidermis_sigma_s_prime[i] = e.sigma_s_prime;
    s.dermis_sigma_a[i] = d.sigma_a;
    s.dermis_sigma_s_prime[i] = d.sigma_s_prime;
    s.R_d[i] = DiffusionStack(skin_layer_stack(p, lambda)).R_d();
  }
  s.color = color::summarize(color::Colorimetry(grid), s.R_d);
  return s;
}

SpectralProfile skin_spectral_profile(const SkinParameters& p, const WavelengthGrid& grid,
                                      ProfileSolver& solver) {
  return solver.spectral(skin_diffusion_stacks(p, grid), grid);
}

RgbProfile skin_rgb_profile(const SkinParameters& p, const WavelengthGrid& grid,
                            ProfileSolver& solver) {
  return solver.rgb(skin_diffusion_stacks(p, grid), color::Colorimetry(grid).srgb_weights());
}

}  // namespace skin
