#pragma once
// The validation report of `skin validate` (docs/validation/README.md): Markdown tables, error
// summaries and radial-profile plots of a skin::mc::ValidationRun. The Monte Carlo library
// computes the run; the application presents it.
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "skin/mc/validation.hpp"

namespace skin::cli {

// Writes the Markdown report to `md` and one PNG per case (plus an overview of R_d errors) into
// `plot_dir` (must exist; "" = no plots); images are linked as `link_prefix + file name`. A case
// whose Monte Carlo profile has no meaningful bin (too few photons) gets a note instead of a plot.
// Returns the number of plots written.
std::size_t write_validation_report(std::ostream& md, const mc::ValidationRun& run,
                                    const std::string& plot_dir, const std::string& link_prefix = "");

// The report of `skin validate --domain N`: cases drawn from the skin domain (mc::domain_cases,
// seeded with `seed`), the check of issue 31 per model (CaseResult::check_domain, rd_within),
// maps of the domain (PNG, into `plot_dir`; "" = none) and a table of every case. Returns the
// number of cases.
std::size_t write_domain_report(std::ostream& md, const mc::ValidationRun& run,
                                const std::string& plot_dir, std::uint64_t seed);

// One line per finished case, for the terminal: "pale-650nm: MC R_d 0.53521 +- 0.00050,
// multipole 0.54012 (+0.92 %), ..., 1.2 s".
std::string validation_case_line(const mc::CaseResult& c,
                                 const std::vector<std::string>& solver_names);

}  // namespace skin::cli
