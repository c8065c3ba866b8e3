#include "skin/model/skin_model.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::model {

using skin::util::ProgressCallback;

using skin::transport::DiffusionStack;
using skin::transport::Model;
using skin::transport::ProfileSolver;
using skin::transport::RadialResponse;
using skin::transport::RgbProfile;
using skin::transport::SpectralProfile;

using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::Spectrum;
using skin::physics::WavelengthGrid;
using skin::physics::skin_layer_stack;

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

namespace {
// The colour weights of an RGB profile: linear sRGB under sRGB's own white (the colour an RGB
// renderer multiplies its lights' colours by), whatever the default illuminant of colours is.
color::Colorimetry srgb_colorimetry(const WavelengthGrid& grid) {
  return color::Colorimetry(grid, color::find_illuminant(color::kSrgbWhite));
}

// A spectrum on `grid` without R_d and colour yet; `set_layers` fills wavelength i's coefficients.
SkinSpectrum empty_spectrum(const SkinParameters& p, const WavelengthGrid& grid, const Model& model) {
  return SkinSpectrum{p, std::string(model.name()), grid, Spectrum(grid), Spectrum(grid),
                      Spectrum(grid), Spectrum(grid), Spectrum(grid), {}};
}
// The stack carries the layer coefficients (eqs 6-8); report them from it.
void set_layers(SkinSpectrum& s, std::size_t i, const LayerStack& stack) {
  s.epidermis_sigma_a[i] = stack.layers[0].sigma_a;
  s.epidermis_sigma_s_prime[i] = stack.layers[0].sigma_s_prime;
  s.dermis_sigma_a[i] = stack.layers[1].sigma_a;
  s.dermis_sigma_s_prime[i] = stack.layers[1].sigma_s_prime;
}
}  // namespace

SkinSpectrum skin_spectrum(const SkinParameters& p, const WavelengthGrid& grid, const Model& model) {
  p.validate();
  SkinSpectrum s = empty_spectrum(p, grid, model);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    util::cancel::check();  // between wavelengths: a scene builds several spectra before its first pixel
    const LayerStack stack = skin_layer_stack(p, grid[i]);
    set_layers(s, i, stack);
    s.R_d[i] = model.R_d(stack);
  }
  s.color = color::summarize(color::Colorimetry(grid), s.R_d);
  return s;
}

color::ColorSummary color_under(const SkinSpectrum& s, const color::Illuminant& illuminant) {
  if (s.color.illuminant == illuminant.name()) return s.color;
  return color::summarize(color::Colorimetry(s.grid, illuminant), s.R_d);
}

color::ColorSummary color_under(const SkinSpectrum& s, const color::Colorimetry& cm) {
  if (s.color.illuminant == cm.illuminant().name() && cm.grid() == s.grid) return s.color;
  return color::summarize(cm, s.R_d);
}

namespace {
// The per-wavelength radial responses of the model, kept alive for the profile solver.
struct Responses {
  std::vector<std::unique_ptr<RadialResponse>> owned;
  std::vector<const RadialResponse*> pointers;
};
Responses responses(const std::vector<LayerStack>& stacks, const Model& model,
                    const ProgressCallback& progress = {}) {
  Responses r;
  r.owned.reserve(stacks.size());
  for (const auto& s : stacks) {
    util::cancel::check();  // between wavelengths: a stack's response can take a good part of a second
    r.pointers.push_back(r.owned.emplace_back(model.response(s)).get());
    if (progress) progress(r.owned.size(), stacks.size());
  }
  return r;
}
}  // namespace

SpectralProfile skin_spectral_profile(const SkinParameters& p, const WavelengthGrid& grid,
                                      ProfileSolver& profiles, const Model& model,
                                      const ProgressCallback& progress) {
  const auto r = responses(skin_layer_stacks(p, grid), model, progress);
  return profiles.spectral(r.pointers, grid);
}

RgbProfile skin_rgb_profile(const SkinParameters& p, const WavelengthGrid& grid,
                            ProfileSolver& profiles, const Model& model,
                            const ProgressCallback& progress) {
  const auto r = responses(skin_layer_stacks(p, grid), model, progress);
  return profiles.rgb(r.pointers, srgb_colorimetry(grid).srgb_weights());
}

SkinAppearance skin_appearance(const SkinParameters& p, const WavelengthGrid& grid,
                               ProfileSolver& profiles, const Model& model) {
  const auto stacks = skin_layer_stacks(p, grid);
  const auto r = responses(stacks, model);
  SkinAppearance a{empty_spectrum(p, grid, model), {}};
  for (std::size_t i = 0; i < grid.size(); ++i) {
    set_layers(a.spectrum, i, stacks[i]);
    a.spectrum.R_d[i] = r.pointers[i]->total();
  }
  a.spectrum.color = color::summarize(color::Colorimetry(grid), a.spectrum.R_d);
  a.rgb = profiles.rgb(r.pointers, srgb_colorimetry(grid).srgb_weights());
  return a;
}

namespace {
std::vector<std::string> wavelength_labels(const WavelengthGrid& grid) {
  std::vector<std::string> labels;
  labels.reserve(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    std::ostringstream os;
    os << grid[i] << " nm";
    labels.push_back(os.str());
  }
  return labels;
}
}  // namespace

SkinProfiles skin_profiles(const SkinParameters& p, const WavelengthGrid& grid, ProfileSolver& profiles,
                           const Model& model, const std::optional<WavelengthGrid>& spectral,
                           const ProgressCallback& progress) {
  // The spectral grid's wavelengths among grid's (a programming error otherwise: checked before
  // anything is solved).
  std::vector<std::size_t> rows;
  if (spectral) {
    for (std::size_t i = 0; i < spectral->size(); ++i) {
      const double l = (*spectral)[i];
      const double at = std::round((l - grid.lambda_min()) / grid.step());
      const auto j = static_cast<std::size_t>(std::max(at, 0.0));
      if (!(at >= 0 && j < grid.size() && std::abs(grid[j] - l) <= 1e-9 * l))
        throw std::invalid_argument("skin_profiles: the spectral grid's " + std::to_string(l) +
                                    " nm is not a wavelength of the profile's grid");
      rows.push_back(j);
    }
  }
  const auto stacks = skin_layer_stacks(p, grid);  // validates
  const auto r = responses(stacks, model, progress);
  SkinProfiles out;
  out.rgb = profiles.rgb(r.pointers, color::Colorimetry(grid).srgb_weights());
  if (spectral) {
    std::vector<const RadialResponse*> some;
    for (std::size_t j : rows) some.push_back(r.pointers[j]);
    out.spectral = profiles.spectral(some, *spectral);
  }
  out.total = skin_spectrum(p, WavelengthGrid(), model);
  out.validity = transport::combined_validity(model, stacks, wavelength_labels(grid));
  return out;
}

std::size_t skin_profile_solves(const SkinParameters& p, const WavelengthGrid& grid,
                                const Model& model) {
  std::size_t n = 0;
  for (const LayerStack& s : skin_layer_stacks(p, grid)) n += model.response_is_solved(s) ? 1 : 0;
  return n;
}

transport::Validity skin_validity(const SkinParameters& p, const WavelengthGrid& grid,
                                  const Model& model) {
  return transport::combined_validity(model, skin_layer_stacks(p, grid), wavelength_labels(grid));
}

}  // namespace skin::model
