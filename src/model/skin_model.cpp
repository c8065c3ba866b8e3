#include "skin/model/skin_model.hpp"

#include <memory>

#include "skin/transport/accurate.hpp"
#include "skin/util/error.hpp"

namespace skin {

std::string_view to_string(Solver s) { return s == Solver::accurate ? "accurate" : "multipole"; }

Solver parse_solver(std::string_view name) {
  if (name == "accurate") return Solver::accurate;
  if (name == "multipole") return Solver::multipole;
  throw InputError("solver = '" + std::string(name) +
                   "' is unknown: allowed values are accurate, multipole");
}

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

double stack_R_d(const LayerStack& stack, Solver solver) {
  return solver == Solver::accurate ? accurate::adding_doubling(stack).R_d
                                    : DiffusionStack(stack).R_d();
}

SkinSpectrum skin_spectrum(const SkinParameters& p, const WavelengthGrid& grid, Solver solver) {
  p.validate();
  SkinSpectrum s{p,           solver,         grid,           Spectrum(grid), Spectrum(grid),
                 Spectrum(grid), Spectrum(grid), Spectrum(grid), {}};
  for (std::size_t i = 0; i < grid.size(); ++i) {
    // The stack carries the layer coefficients (eqs 6-8); report them from it.
    const LayerStack stack = skin_layer_stack(p, grid[i]);
    s.epidermis_sigma_a[i] = stack.layers[0].sigma_a;
    s.epidermis_sigma_s_prime[i] = stack.layers[0].sigma_s_prime;
    s.dermis_sigma_a[i] = stack.layers[1].sigma_a;
    s.dermis_sigma_s_prime[i] = stack.layers[1].sigma_s_prime;
    s.R_d[i] = stack_R_d(stack, solver);
  }
  s.color = color::summarize(color::Colorimetry(grid), s.R_d);
  return s;
}

namespace {
// The per-wavelength radial responses of either solver, kept alive for the profile solver.
struct Responses {
  std::vector<DiffusionStack> multipole;
  std::vector<accurate::AccurateStack> accurate;
  std::vector<const RadialResponse*> pointers;
};
std::unique_ptr<Responses> responses(const SkinParameters& p, const WavelengthGrid& grid,
                                     Solver solver) {
  auto r = std::make_unique<Responses>();
  const auto stacks = skin_layer_stacks(p, grid);
  if (solver == Solver::accurate) {
    r->accurate.reserve(stacks.size());
    for (const auto& s : stacks) r->pointers.push_back(&r->accurate.emplace_back(s));
  } else {
    r->multipole.reserve(stacks.size());
    for (const auto& s : stacks) r->pointers.push_back(&r->multipole.emplace_back(s));
  }
  return r;
}
}  // namespace

SpectralProfile skin_spectral_profile(const SkinParameters& p, const WavelengthGrid& grid,
                                      ProfileSolver& profiles, Solver solver) {
  const auto r = responses(p, grid, solver);
  return profiles.spectral(r->pointers, grid);
}

RgbProfile skin_rgb_profile(const SkinParameters& p, const WavelengthGrid& grid,
                            ProfileSolver& profiles, Solver solver) {
  const auto r = responses(p, grid, solver);
  return profiles.rgb(r->pointers, color::Colorimetry(grid).srgb_weights());
}

}  // namespace skin
