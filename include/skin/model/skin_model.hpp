#pragma once
// The four-parameter skin model end to end: parameters -> per-wavelength layer stacks -> total
// diffuse reflectance spectrum, radial profiles and colour (DJ06 sections 3-4).
#include <optional>
#include <string>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/progress.hpp"
#include "skin/transport/profile.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/transport/stack.hpp"

namespace skin::model {

// Light transport in the layers is a transport::Model from the registry
// (skin/transport/model.hpp: transport::find_model(name), transport::default_model()).

struct SkinSpectrum {
  physics::SkinParameters parameters;
  std::string solver{transport::kDefaultModel};  // name of the transport model
  physics::WavelengthGrid grid;
  physics::Spectrum epidermis_sigma_a, epidermis_sigma_s_prime;  // [1/mm]
  physics::Spectrum dermis_sigma_a, dermis_sigma_s_prime;        // [1/mm]
  physics::Spectrum R_d;                                         // total diffuse reflectance
  color::ColorSummary color;                            // colour of R_d under D65
};

// The colour of the spectrum's R_d under an illuminant (XYZ under it; sRGB after the Bradford
// adaptation to D65; CIELAB relative to its white), on the spectrum's grid: s.color when that is
// already under this illuminant (skin_spectrum's, D65), else computed from R_d. The one way every
// command, the Python package and the web page take a colour under an illuminant.
color::ColorSummary color_under(const SkinSpectrum& s, const color::Illuminant& illuminant);
// The same with the colour-matching weights given (many spectra on one grid: built once). `cm`
// must be on s.grid.
color::ColorSummary color_under(const SkinSpectrum& s, const color::Colorimetry& cm);

// One two-layer stack per wavelength (validates the parameters).
std::vector<physics::LayerStack> skin_layer_stacks(const physics::SkinParameters& p, const physics::WavelengthGrid& grid);
std::vector<transport::DiffusionStack> skin_diffusion_stacks(const physics::SkinParameters& p,
                                                  const physics::WavelengthGrid& grid);

// R_d(lambda) and colour. Throws InputError for invalid parameters.
SkinSpectrum skin_spectrum(const physics::SkinParameters& p, const physics::WavelengthGrid& grid = {},
                           const transport::Model& model = transport::default_model());

// Radial profiles per wavelength, or per linear sRGB channel (colour weights from `grid`, under
// sRGB's white, color::kSrgbWhite). `progress` counts the wavelengths whose response is built
// (the slow part where a response is solved rather than read from the accurate model's skin
// table; docs/benchmarks.md).
transport::SpectralProfile skin_spectral_profile(const physics::SkinParameters& p, const physics::WavelengthGrid& grid,
                                      transport::ProfileSolver& profiles,
                                      const transport::Model& model = transport::default_model(),
                                      const util::ProgressCallback& progress = {});
transport::RgbProfile skin_rgb_profile(const physics::SkinParameters& p, const physics::WavelengthGrid& grid,
                            transport::ProfileSolver& profiles,
                            const transport::Model& model = transport::default_model(),
                            const util::ProgressCallback& progress = {});

// The spectrum and the RGB profile of one skin together, as skin_spectrum and skin_rgb_profile
// give them (the same numbers): the profile's radial responses give R_d too (a response's total
// is the model's R_d), so the transport runs once per wavelength instead of twice (the web
// page's live update).
struct SkinAppearance {
  SkinSpectrum spectrum;
  transport::RgbProfile rgb;
};
SkinAppearance skin_appearance(const physics::SkinParameters& p, const physics::WavelengthGrid& grid,
                               transport::ProfileSolver& profiles,
                               const transport::Model& model = transport::default_model());

// Everything a renderer or an export takes from one skin, from one call: the shape of its RGB
// profile and its validity on `grid` (the transport responses built once per wavelength and used
// for both), the colour of its total R_d from skin_spectrum on the paper's grid (exact at k = 0),
// and with `spectral` the per-wavelength profiles on that grid from the same responses: its
// wavelengths must be among `grid`'s (std::invalid_argument otherwise), so that no wavelength is
// solved twice. The numbers are those of skin_rgb_profile, skin_validity, skin_spectrum and
// skin_spectral_profile.
struct SkinProfiles {
  transport::RgbProfile rgb;                          // on `grid`
  SkinSpectrum total;                      // skin_spectrum(p, WavelengthGrid(), model)
  transport::Validity validity;            // on `grid`
  std::optional<transport::SpectralProfile> spectral; // on the `spectral` grid, when asked for
};
SkinProfiles skin_profiles(const physics::SkinParameters& p, const physics::WavelengthGrid& grid, transport::ProfileSolver& profiles,
                           const transport::Model& model = transport::default_model(),
                           const std::optional<physics::WavelengthGrid>& spectral = std::nullopt,
                           const util::ProgressCallback& progress = {});

// How many wavelengths of `grid` the model's profile of this skin solves numerically
// (Model::response_is_solved; the cost is in docs/benchmarks.md) rather than reads: 0 for the accurate
// model on its skin table, every wavelength for sfd.
std::size_t skin_profile_solves(const physics::SkinParameters& p, const physics::WavelengthGrid& grid,
                                const transport::Model& model = transport::default_model());
// Such solves per second per thread, for the estimates said before they start (the command line,
// the Python module); measured, docs/benchmarks.md ("Measurements formerly in headers").
inline constexpr double kProfileSolvesPerSecond = 0.85;

// Whether the model's profiles (and totals) of this skin are in its validated range at every
// wavelength of `grid`; the reason names the first wavelength out and how many are
// (transport::combined_validity).
transport::Validity skin_validity(const physics::SkinParameters& p, const physics::WavelengthGrid& grid,
                                  const transport::Model& model = transport::default_model());

}  // namespace skin::model
