#pragma once
// Many parameter sets at once: the skin model (skin/model/skin_model.hpp) evaluated for every set
// on all cores. Result i belongs to sets[i] and equals, bit for bit, the single call for that set
// (each set is computed by the same library function; threads share only the transport models'
// read-only tables). Used by `skin batch` and by the Python package's array calls. The thread
// pool (TBB) stays private: this header exposes standard types only. A cancellation request
// (skin/util/cancel.hpp) ends a call between sets by throwing skin::util::Cancelled.
#include <functional>
#include <span>
#include <vector>

#include "skin/model/skin_model.hpp"
#include "skin/util/progress.hpp"

namespace skin::batch {

struct Options {
  int threads = 0;  // worker threads; 0 = all cores
  // rgb_profiles and spectral_profiles: progress(wavelengths done, wavelengths) over all the
  // sets (sets x grid), after each wavelength's transport response is built (the slow part where
  // it is solved). Called from the worker threads, concurrently: it must be thread-safe.
  util::ProgressCallback progress;
};

// skin_spectrum for every set: R_d(lambda), the layer coefficients and the colour.
std::vector<model::SkinSpectrum> spectra(std::span<const physics::SkinParameters> sets, const physics::WavelengthGrid& grid,
                                  const transport::Model& model, const Options& options = {});

// A profile and whether the model's profile of that skin is in its validated range
// (skin_validity on the same grid).
struct RgbProfileResult {
  transport::RgbProfile profile;
  transport::Validity validity;
};
struct SpectralProfileResult {
  transport::SpectralProfile profile;
  transport::Validity validity;
};

// skin_rgb_profile / skin_spectral_profile for every set at the same radii (one ProfileSolver per
// worker thread).
std::vector<RgbProfileResult> rgb_profiles(std::span<const physics::SkinParameters> sets,
                                           const physics::WavelengthGrid& grid, const transport::RadialGrid& radii,
                                           const transport::Model& model, const Options& options = {});
std::vector<SpectralProfileResult> spectral_profiles(std::span<const physics::SkinParameters> sets,
                                                     const physics::WavelengthGrid& grid,
                                                     const transport::RadialGrid& radii, const transport::Model& model,
                                                     const Options& options = {});

// How many of the wavelength profiles of `n` sets (set(i), i < n) the model solves rather than
// reads (model::skin_profile_solves), counted on at most 64 of them spread evenly and scaled to
// all: the estimate said before a long call starts (`skin batch --radius`, Python's profiles).
double profile_solves(std::size_t n, const std::function<physics::SkinParameters(std::size_t)>& set,
                      const physics::WavelengthGrid& grid, const transport::Model& model);

}  // namespace skin::batch
