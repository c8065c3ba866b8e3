#pragma once
// Measured skin spectra against the model: every spectrum under a directory fitted with the
// paper's parameters, with the specular term and with the extended model over 400-700 nm. The
// library computes and returns the fits; the application writes the report (Markdown and one
// plot per spectrum: src/app/report_measured.cpp, docs/validation/measured/).
#include <string>
#include <utility>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/fit/fit.hpp"

namespace skin::fit {

struct MeasuredEntry {
  MeasuredSpectrum spectrum;
  std::string description;      // from the metadata file, if any
  bool used_in_paper = false;   // flagged used_in_donner_jensen_2006 = yes
  bool includes_specular = false;  // flagged includes_specular = yes: the measurement holds the
                                   // surface reflection, so extended_model fits rho_s F as well
  FitResult paper;              // C_m, beta_m, C_h (the paper's model, no surface term)
  FitResult paper_specular;     // + rho_s through the specular term (the four parameters)
  FitResult extended;           // + all extended terms (extended_parameters())
  std::vector<std::pair<Parameter, double>> single_term_rms;  // four parameters + one term
  FitResult extended_model;     // `--model extended`: extended_model_free(true) with the priors
                                // (+ oiliness through rho_s F where includes_specular)
  color::Lab lab;               // the measured spectrum's colour (reflectance_lab)
  double ita = 0;               // its ITA [degrees] (ita_degrees; bin: ita_bin)
};

// The extended model's free terms, added to the four parameters in extended fits.
const std::vector<Parameter>& extended_parameters();

// Reads every *.csv under `spectra_dir` (recursively, sorted; files named *metadata* are read as
// metadata: columns `column`, `original_label`, `used_in_donner_jensen_2006`,
// `includes_specular`, header case-insensitive) and fits each spectrum (in parallel). `model` empty: the registry's default
// (transport::default_model()). Throws
// InputError naming the directory if it is not one or holds no spectra.
std::vector<MeasuredEntry> fit_measured_spectra(const std::string& spectra_dir,
                                                const ForwardModel& model = {});

}  // namespace skin::fit
