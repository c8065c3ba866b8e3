#pragma once
// Many fits at once: ColorFitter::fit and SpectrumFitter::fit for every target of a list, on all
// cores (TBB, private). Result i belongs to input i and equals, bit for bit, the fitter's single
// call on it (each fit is deterministic, and the fitters are thread-safe: threads share only
// their read-only tables). Used by the Python package's fit_color and fit_spectrum on arrays. A
// cancellation request (skin/util/cancel.hpp) ends a call between fits by throwing
// skin::util::Cancelled.
#include <span>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"

namespace skin::fit {

struct ManyOptions {
  int threads = 0;  // worker threads; 0 = all cores
};

// fitter.fit(targets[i]) for every i. Every target is checked before the first fit (InputError
// naming the first bad one: "target 3: srgb (linear) = ..."); an error of a fit itself is the
// one of the lowest index, as one call after another would raise it first.
std::vector<ColorFitResult> fit_colors(const ColorFitter& fitter, std::span<const color::Rgb> targets,
                                       const ManyOptions& options = {});

// fitter.fit(spectra[i]) for every i; every spectrum is validated (validate_spectrum, naming it)
// before the first fit. Errors as fit_colors.
std::vector<FitResult> fit_spectra(const SpectrumFitter& fitter, std::span<const MeasuredSpectrum> spectra,
                                   const ManyOptions& options = {});

}  // namespace skin::fit
