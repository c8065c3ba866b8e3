#pragma once
// The measured-spectra report (docs/validation/measured/): Markdown tables and one plot per
// spectrum of the fits skin::fit::fit_measured_spectra computes. Written by
// `skin fit --measured-report` and `skin validate`.
#include <iosfwd>
#include <string>
#include <vector>

#include "skin/fit/measured.hpp"

namespace skin::cli {

// Where the measured skin spectra are looked for unless --spectra-dir is given: the environment
// variable SKIN_SPECTRA_DIR if set and not empty, else ../shared/data/skin_spectra (relative to
// the current directory: the project's copy, seen from the root of a checkout).
std::string default_spectra_dir();

// Writes one PNG per spectrum into `out_dir` (created if needed; <name>.png) and the Markdown
// report (relative image links) to `md`. `spectra_dir` is named in the text (as an absolute
// path), `model_name` names the forward model. `plots` false: no PNG per spectrum and no link to
// one (a set of a hundred spectra would be megabytes of plots); the one figure of the set,
// tone_bins.png (the median fit of each skin-tone bin), is drawn either way.
void write_measured_report(std::ostream& md, const std::vector<fit::MeasuredEntry>& entries,
                           const std::string& spectra_dir, const std::string& out_dir,
                           const std::string& model_name, bool plots = true);

// Fits every spectrum under `spectra_dir` with the solver named (skin::fit::forward_model) and
// writes `out_dir`/README.md and the plots. Throws InputError naming the directory when it is
// not a directory or holds no spectra.
std::vector<fit::MeasuredEntry> write_measured_report(const std::string& spectra_dir,
                                                      const std::string& out_dir,
                                                      const std::string& solver, bool plots = true);
// The same for fits already made: writes `out_dir`/README.md and the plots.
void write_measured_report(const std::vector<fit::MeasuredEntry>& entries,
                           const std::string& spectra_dir, const std::string& out_dir,
                           const std::string& solver, bool plots = true);

}  // namespace skin::cli
