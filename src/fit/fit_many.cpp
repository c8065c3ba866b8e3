// Many fits at once (skin/fit/fit_many.hpp).
#include "skin/fit/fit_many.hpp"

#include <exception>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::fit {

using skin::util::InputError;
using skin::util::require_in_range;

namespace {

// prepare(), then out[i] = compute(i) for i in [0, n) on `threads` workers (0 = all cores), one
// fit per task (a fit costs milliseconds to seconds). Cancellation is polled between fits; the
// failure of the lowest index is rethrown once every task has ended.
template <class R, class Prepare, class F>
std::vector<R> each(std::size_t n, const ManyOptions& options, const Prepare& prepare, const F& compute) {
  if (options.threads < 0)
    throw InputError("threads = " + std::to_string(options.threads) +
                     " is out of range: must be 0 (all cores) or more");
  std::vector<R> out(n);
  std::vector<std::exception_ptr> failed(n);
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    prepare();  // the fitter's table, built on these workers
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (util::cancel::requested()) return;  // thrown below
        try {
          out[i] = compute(i);
        } catch (...) {
          failed[i] = std::current_exception();
        }
      }
    });
  });
  util::cancel::check();
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
  return out;
}

}  // namespace

std::vector<ColorFitResult> fit_colors(const ColorFitter& fitter, std::span<const color::Rgb> targets,
                                       const ManyOptions& options) {
  for (std::size_t i = 0; i < targets.size(); ++i)
    for (int c = 0; c < 3; ++c)
      require_in_range("target " + std::to_string(i) + ": srgb (linear)", targets[i][c], 0.0, 1.0);
  return each<ColorFitResult>(
      targets.size(), options, [&] { fitter.prepare(); }, [&](std::size_t i) { return fitter.fit(targets[i]); });
}

std::vector<FitResult> fit_spectra(const SpectrumFitter& fitter, std::span<const MeasuredSpectrum> spectra,
                                   const ManyOptions& options) {
  for (const MeasuredSpectrum& m : spectra) validate_spectrum(m);
  return each<FitResult>(
      spectra.size(), options, [&] { fitter.prepare(); }, [&](std::size_t i) { return fitter.fit(spectra[i]); });
}

}  // namespace skin::fit
