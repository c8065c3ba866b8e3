#include "skin/batch/batch.hpp"

#include <algorithm>
#include <atomic>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::batch {

using skin::util::InputError;
using skin::util::ProgressCallback;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;

using skin::model::SkinSpectrum;
using skin::model::skin_rgb_profile;
using skin::model::skin_spectral_profile;
using skin::model::skin_spectrum;
using skin::model::skin_validity;

using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;

namespace {

// compute(i) for i in [0, n) on `threads` workers (0 = all cores), one set per task: a set
// costs 0.07-10 ms, far above TBB's scheduling overhead, and one per task balances best. A
// cancellation request (skin/util/cancel.hpp) ends it between sets with Cancelled.
template <class F>
void for_each_set(std::size_t n, const Options& options, const F& compute) {
  if (options.threads < 0)
    throw InputError("threads = " + std::to_string(options.threads) +
                     " is out of range: must be 0 (all cores) or more");
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          util::cancel::check();
                          compute(i);
                        }
                      });
  });
}

// The per-set progress of a profile call as one count over all its sets: each wavelength's
// response adds one, from whichever worker built it.
util::ProgressCallback counted(const util::ProgressCallback& progress, std::size_t total) {
  if (!progress) return {};
  auto done = std::make_shared<std::atomic<std::size_t>>(0);
  return [progress, done, total](std::size_t, std::size_t) { progress(++*done, total); };
}

}  // namespace

std::vector<SkinSpectrum> spectra(std::span<const SkinParameters> sets, const WavelengthGrid& grid,
                                  const transport::Model& model, const Options& options) {
  for (const SkinParameters& p : sets) p.validate();  // user errors before any work
  std::vector<SkinSpectrum> out(sets.size());
  for_each_set(sets.size(), options, [&](std::size_t i) { out[i] = skin_spectrum(sets[i], grid, model); });
  return out;
}

std::vector<RgbProfileResult> rgb_profiles(std::span<const SkinParameters> sets,
                                           const WavelengthGrid& grid, const RadialGrid& radii,
                                           const transport::Model& model, const Options& options) {
  for (const SkinParameters& p : sets) p.validate();
  std::vector<RgbProfileResult> out(sets.size());
  tbb::enumerable_thread_specific<ProfileSolver> solvers([&] { return ProfileSolver(radii); });
  const ProgressCallback step = counted(options.progress, sets.size() * grid.size());
  for_each_set(sets.size(), options, [&](std::size_t i) {
    out[i] = {skin_rgb_profile(sets[i], grid, solvers.local(), model, step),
              skin_validity(sets[i], grid, model)};
  });
  return out;
}

std::vector<SpectralProfileResult> spectral_profiles(std::span<const SkinParameters> sets,
                                                     const WavelengthGrid& grid,
                                                     const RadialGrid& radii, const transport::Model& model,
                                                     const Options& options) {
  for (const SkinParameters& p : sets) p.validate();
  std::vector<SpectralProfileResult> out(sets.size());
  tbb::enumerable_thread_specific<ProfileSolver> solvers([&] { return ProfileSolver(radii); });
  const ProgressCallback step = counted(options.progress, sets.size() * grid.size());
  for_each_set(sets.size(), options, [&](std::size_t i) {
    out[i] = {skin_spectral_profile(sets[i], grid, solvers.local(), model, step),
              skin_validity(sets[i], grid, model)};
  });
  return out;
}

double profile_solves(std::size_t n, const std::function<SkinParameters(std::size_t)>& set,
                      const WavelengthGrid& grid, const transport::Model& model) {
  constexpr std::size_t kLooked = 64;
  const std::size_t looked = std::min(n, kLooked);
  if (looked == 0) return 0;
  std::size_t solved = 0;
  for (std::size_t k = 0; k < looked; ++k) solved += model::skin_profile_solves(set(k * n / looked), grid, model);
  return static_cast<double>(solved) * static_cast<double>(n) / static_cast<double>(looked);
}

}  // namespace skin::batch
