#pragma once
// Inverse model: recovering skin parameters from a measured reflectance spectrum (the paper's
// closing suggestion, DJ06 section 7). Bounded Levenberg-Marquardt on R_d(lambda) from a coarse
// table search (global start), parameter uncertainties from the Jacobian, and an optional
// constant specular term for measurements that include the surface reflection. Derivations and
// choices: docs/fit.md.
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/model.hpp"

namespace skin::fit {

// The parameters the fit can free. Names: JSON keys use underscores ("melanin_blend"), CLI flags
// dashes ("melanin-blend"); both spellings are accepted by parse_parameter.
enum class Parameter {
  melanin,               // C_m
  melanin_blend,         // beta_m
  hemoglobin,            // C_h
  oiliness,              // rho_s (only seen through the specular term, see SpectrumFitOptions)
  epidermal_hemoglobin,  // extended model
  beta_carotene,         // [umol/L]
  bilirubin,             // [umol/L]
  epidermis_thickness,   // [mm]
  oxygenation,           // gamma
  scattering_scale,      // factor on sigma_s' of both layers
};
std::string_view key(Parameter p);   // "melanin_blend"
std::string flag(Parameter p);       // "melanin-blend"
std::ostream& operator<<(std::ostream& os, Parameter p);
// Throws InputError naming the unknown name and listing the known ones.
Parameter parse_parameter(std::string_view name);
// Comma-separated list ("oxygenation,scattering-scale"); throws on unknown or repeated names.
std::vector<Parameter> parse_parameter_list(std::string_view list);
const std::vector<Parameter>& all_parameters();

double get(const SkinParameters& s, Parameter p);
void set(SkinParameters& s, Parameter p, double value);

// Search interval of a parameter (inclusive). The defaults are the paper's ranges (C_m 0-0.5,
// C_h 0-0.2) and physiological ranges for the extended terms; see docs/fit.md for sources.
struct Bounds {
  double lo = 0, hi = 1;
};
std::ostream& operator<<(std::ostream& os, const Bounds& b);
Bounds default_bounds(Parameter p);

// The forward model: total diffuse reflectance R_d at one wavelength [nm]. Swappable so that
// another model (Monte Carlo tables, ...) can replace the transport models. Must be thread-safe
// (it is called from several threads by the texture fit and the report).
using ForwardModel = std::function<double(const SkinParameters& p, double lambda)>;
// R_d of skin_layer_stack(p, lambda) by a transport model of the registry (its totals; NaN where
// they are outside the model's validated range, which the fit treats as a barrier). The model
// must outlive the function (the registry's do).
ForwardModel forward_model(const transport::Model& model);
// By name (transport::find_model: InputError naming the known ones).
ForwardModel forward_model(std::string_view solver);

// A measured reflectance spectrum: wavelengths [nm], strictly increasing, and reflectance 0-1.
struct MeasuredSpectrum {
  std::string name;
  std::vector<double> wavelength_nm;
  std::vector<double> R;
};
std::ostream& operator<<(std::ostream& os, const MeasuredSpectrum& m);

// Reads a spectrum from a CSV file (skin::read_csv_file): the first column is the wavelength in
// nm; the reflectance is `column` if given, else the second column, and the file must then have
// exactly two columns. Rows whose reflectance is empty (NaN) are skipped. Validated with
// validate_spectrum. Throws InputError naming the file and the problem.
MeasuredSpectrum read_spectrum(const std::string& path, const std::string& column = "");
// All reflectance columns of a CSV file (first column: wavelength), each validated.
std::vector<MeasuredSpectrum> read_spectra(const std::string& path);
// Checks: at least kMinSamples samples in [400, 700] nm, wavelengths finite and strictly
// increasing, reflectances finite and within [0, 1], and the range covers 450-650 nm.
void validate_spectrum(const MeasuredSpectrum& m);
inline constexpr std::size_t kMinSamples = 8;

struct SpectrumFitOptions {
  // Parameters to fit; the others keep their values in `start`.
  std::vector<Parameter> free = {Parameter::melanin, Parameter::melanin_blend,
                                 Parameter::hemoglobin};
  SkinParameters start;  // fixed values, and the LM start for the extended terms
  // The measurement includes the surface reflection (integrating sphere, specular included):
  // the model becomes rho_s F + (1 - rho_s F) R_d with F = specular_albedo, and `oiliness` is
  // freed. F defaults to the normal-incidence Fresnel reflectance of eta (0.028 for 1.4).
  bool includes_specular = false;
  double specular_albedo = -1;  // < 0: Fresnel reflectance at normal incidence of start.eta
  // Only measured samples in [lambda_min, lambda_max] are fitted.
  double lambda_min = 400, lambda_max = 700;
  // Per-parameter bounds overriding default_bounds.
  std::vector<std::pair<Parameter, Bounds>> bounds;
  int max_iterations = 60;
  ForwardModel model;  // empty: forward_model(transport::default_model())
};

struct FitResult {
  SkinParameters parameters;     // fitted values (others as in the options' start)
  std::vector<Parameter> free;   // what was fitted, in this order in `uncertainty`
  std::vector<double> uncertainty;  // one standard deviation, from s^2 (J^T J)^-1
  std::vector<bool> at_bound;       // parameter ended on its bound (uncertainty is then local)
  double rms = 0;                   // root mean square residual [reflectance]
  double specular = 0;              // the constant specular term rho_s F (0 without it)
  std::vector<double> wavelength_nm, measured, fitted;  // fitted samples
  int iterations = 0;                // LM iterations of the winning start
  int starts = 0;                    // LM runs (global stage)
  double uncertainty_of(Parameter p) const;  // throws if p is not free
};
std::ostream& operator<<(std::ostream& os, const FitResult& r);

// Fits spectra; holds the coarse table of the global stage, built on first use for the fixed
// parameters of the options (so reuse one fitter for many spectra). Thread-safe after
// construction: fit() may be called concurrently.
class SpectrumFitter {
 public:
  explicit SpectrumFitter(SpectrumFitOptions options = {});
  ~SpectrumFitter();
  SpectrumFitter(SpectrumFitter&&) noexcept;
  SpectrumFitter& operator=(SpectrumFitter&&) noexcept;
  const SpectrumFitOptions& options() const;
  // Validates the spectrum (InputError) and fits.
  FitResult fit(const MeasuredSpectrum& m) const;
  // Builds the coarse table now (otherwise the first fit does).
  void prepare() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot convenience.
FitResult fit_spectrum(const MeasuredSpectrum& m, const SpectrumFitOptions& options = {});

// The model's reflectance (R_d plus the options' specular term) at the given wavelengths.
std::vector<double> model_reflectance(const SkinParameters& p, const std::vector<double>& lambda,
                                      const SpectrumFitOptions& options);

}  // namespace skin::fit
