#pragma once
// The measured-spectra report (validation): every skin spectrum under a directory fitted with
// the paper's parameters and with the extended model over 400-700 nm, RMS errors, fitted values
// and one plot per spectrum (model against measurement).
#include <iosfwd>
#include <string>
#include <vector>

#include "skin/fit/fit.hpp"

namespace skin::fit {

struct MeasuredEntry {
  MeasuredSpectrum spectrum;
  std::string description;      // from the metadata file, if any
  bool used_in_paper = false;   // flagged used_in_donner_jensen_2006 = yes
  FitResult paper;              // C_m, beta_m, C_h (the paper's model, no surface term)
  FitResult paper_specular;     // + rho_s through the specular term (the four parameters)
  FitResult extended;           // + all extended terms (extended_parameters())
  std::vector<std::pair<Parameter, double>> single_term_rms;  // four parameters + one term
};

// The project's copy of the measured spectra (<source>/../shared/data/skin_spectra), the
// default of `skin fit --spectra-dir`.
std::string default_spectra_dir();

// The extended model's free terms, added to the four parameters in the report.
const std::vector<Parameter>& extended_parameters();

// Reads every *.csv under `spectra_dir` (recursively, sorted; files named *metadata* are read as
// metadata: columns `column`, `original_label`, `used_in_donner_jensen_2006`, header case-insensitive) and fits each
// spectrum. `model` empty: the registry's default (transport::default_model()). Throws
// InputError if the directory has no spectra.
std::vector<MeasuredEntry> fit_measured_spectra(const std::string& spectra_dir,
                                                const ForwardModel& model = {});

// Fits, writes one PNG per spectrum into `out_dir` (created if needed; <name>.png) and the
// markdown report (relative image links) to `markdown`. Returns the entries.
// `model_name` names the forward model in the text.
std::vector<MeasuredEntry> write_measured_report(const std::string& spectra_dir,
                                                 const std::string& out_dir,
                                                 std::ostream& markdown,
                                                 const ForwardModel& model = {},
                                                 const std::string& model_name = "multipole");

}  // namespace skin::fit
