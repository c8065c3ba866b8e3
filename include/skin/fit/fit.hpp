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
#include <utility>
#include <vector>

#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/model.hpp"

namespace skin::fit {

// A parameter the fit can free: a row of the parameter table (skin_parameters.hpp) that has a
// fit interval (ParameterInfo::fit_min, fit_max), named by its member of SkinParameters. Its
// names are the table's: the key ("melanin_blend"), the flag ("melanin-blend") and the paper's
// symbol ("beta_m"), all accepted by parse_parameter.
class Parameter {
 public:
  // The table's row; InputError unless the row has a fit interval.
  static Parameter of(const physics::ParameterInfo& row);
  const physics::ParameterInfo& info() const;
  constexpr double physics::SkinParameters::*member() const { return member_; }
  bool operator==(const Parameter&) const = default;
  // The rows the fit's own code names (each has a fit interval; all_parameters() lists them all).
  static const Parameter melanin, melanin_blend, hemoglobin, oiliness, oxygenation,
      epidermis_thickness, epidermal_hemoglobin, beta_carotene, bilirubin, scattering_scale,
      dermis_scattering_scale, blood_vessel_radius;

 private:
  constexpr explicit Parameter(double physics::SkinParameters::*member) : member_(member) {}
  double physics::SkinParameters::*member_;
};
inline constexpr Parameter Parameter::melanin{&physics::SkinParameters::melanin};
inline constexpr Parameter Parameter::melanin_blend{&physics::SkinParameters::melanin_blend};
inline constexpr Parameter Parameter::hemoglobin{&physics::SkinParameters::hemoglobin};
inline constexpr Parameter Parameter::oiliness{&physics::SkinParameters::oiliness};
inline constexpr Parameter Parameter::oxygenation{&physics::SkinParameters::oxygenation};
inline constexpr Parameter Parameter::epidermis_thickness{&physics::SkinParameters::epidermis_thickness};
inline constexpr Parameter Parameter::epidermal_hemoglobin{&physics::SkinParameters::epidermal_hemoglobin};
inline constexpr Parameter Parameter::beta_carotene{&physics::SkinParameters::beta_carotene};
inline constexpr Parameter Parameter::bilirubin{&physics::SkinParameters::bilirubin};
inline constexpr Parameter Parameter::scattering_scale{&physics::SkinParameters::scattering_scale};
inline constexpr Parameter Parameter::dermis_scattering_scale{&physics::SkinParameters::dermis_scattering_scale};
inline constexpr Parameter Parameter::blood_vessel_radius{&physics::SkinParameters::blood_vessel_radius};

std::string_view key(Parameter p);   // "melanin_blend"
std::string flag(Parameter p);       // "melanin-blend"
std::ostream& operator<<(std::ostream& os, Parameter p);
// By key, flag or symbol (find_parameter). Throws InputError naming the name and listing the
// parameters the fit frees.
Parameter parse_parameter(std::string_view name);
// Comma-separated list ("oxygenation,scattering-scale", "C_m,beta_m"); throws on unknown or
// repeated parameters.
std::vector<Parameter> parse_parameter_list(std::string_view list);
// The rows of the parameter table with a fit interval, in the table's order.
const std::vector<Parameter>& all_parameters();

double get(const physics::SkinParameters& s, Parameter p);
void set(physics::SkinParameters& s, Parameter p, double value);

// Search interval of a parameter (inclusive).
struct Bounds {
  double lo = 0, hi = 1;
};
std::ostream& operator<<(std::ostream& os, const Bounds& b);
// The parameter table's fit interval: the paper's ranges (C_m 0-0.5, C_h 0-0.2) and
// physiological ranges for the extended terms (sources: src/physics/skin_parameters.cpp,
// docs/fit.md).
Bounds default_bounds(Parameter p);
// Throws InputError if a list of bounds overriding the defaults names a parameter twice (its key
// and its symbol name one parameter: one of the two would be dropped). The fitters check it.
void check_bounds(const std::vector<std::pair<Parameter, Bounds>>& bounds);

// The parameter set of a fit (`skin fit --model`, JSON "model"):
// - paper: the paper's C_m, beta_m, C_h within the fit intervals (default_bounds), no prior on a
//   spectrum; a colour fit pulls beta_m weakly toward ColorFitOptions::melanin_blend_prior;
// - extended: the free parameters of extended_model_free(), each kept in the range measured on
//   human skin (the parameter table's prior_min, prior_max: prior_bounds) and pulled weakly toward
//   its prior_centre by a Gaussian term (width: the range; in log(value) where prior_log). Free
//   parameters without a prior keep their fit interval. Sources: docs/fit.md "Priors".
enum class FitModel { paper, extended };
std::string_view name(FitModel m);  // "paper", "extended"
// Throws InputError "model = '<name>' is unknown: choose paper or extended".
FitModel parse_fit_model(std::string_view name);
// The extended model's free parameters. Colour (three numbers): melanin, melanin_blend,
// hemoglobin, oxygenation, epidermis_thickness, dermis_scattering_scale, scattering_scale (the
// parameter table's order); spectrum: those and beta_carotene, epidermal_hemoglobin,
// blood_vessel_radius (vessel packaging, since 2026-12-07).
std::vector<Parameter> extended_model_free(bool spectrum);
// Search interval under the extended model: the prior range where the table has one, else
// default_bounds.
Bounds prior_bounds(Parameter p);
// Position of v in p's prior range, 0 at prior_min and 1 at prior_max (in log(value) where
// prior_log); NaN if p has no prior centre. The Gaussian term of a fit is weight x (u(v) - u(centre)).
double prior_coordinate(Parameter p, double v);
bool has_prior_centre(Parameter p);
// Weights of the Gaussian prior terms, in the residuals' units per whole prior range: spectra
// [reflectance] (weak against ~150 samples: it only settles directions the spectrum does not
// determine), colours [CIEDE2000 units] (the tone presets' weight).
inline constexpr double kSpectrumPriorWeight = 0.002;
inline constexpr double kColorPriorWeight = 0.3;
// A colour or spectrum whose best fit is farther than this [CIEDE2000] lies outside the model's
// gamut (reported as outside_gamut).
inline constexpr double kGamutDeltaE = 1.0;

// The forward model: total diffuse reflectance R_d at one wavelength [nm]. Swappable so that
// another model (Monte Carlo tables, ...) can replace the transport models. Must be thread-safe
// (it is called from several threads by the texture fit and the report).
using ForwardModel = std::function<double(const physics::SkinParameters& p, double lambda)>;
// R_d of skin_layer_stack(p, lambda) by a transport model of the registry (its totals; NaN where
// they are outside the model's validated range, which the fit treats as a barrier). The model
// must outlive the function (the registry's do).
ForwardModel forward_model(const transport::Model& model);
// By name (transport::find_model: InputError naming the known ones).
ForwardModel forward_model(std::string_view solver);
// The reflectance a measurement over a finite area collects (an integrating sphere's sample port
// of radius `port_radius` [mm], the light entering evenly over a concentric disc of radius
// `beam_radius`, 0 for a pencil beam at its centre): R_d less the light that leaves the skin
// beyond the port (transport::PortCollection, from the model's radial profile). NaN, a wall for
// the fit, outside the model's totals and where the model would solve the profile rather than
// read it. Throws InputError for radii out of range. Thread-safe.
ForwardModel forward_model_through_port(const transport::Model& model, double port_radius, double beam_radius = 0);

// A measured reflectance spectrum: wavelengths [nm], strictly increasing, and reflectance 0-1.
struct MeasuredSpectrum {
  std::string name;
  std::vector<double> wavelength_nm;
  std::vector<double> R;
};
std::ostream& operator<<(std::ostream& os, const MeasuredSpectrum& m);

// Reads a spectrum from a CSV file (skin::util::read_csv_file): the first column is the wavelength in
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
// A spectrum fit whose RMS residual [reflectance] reaches this does not describe the spectrum
// well: the measured-spectra report counts the fits below it, the web page warns at it.
inline constexpr double kGoodFitRms = 0.02;

struct SpectrumFitOptions {
  // Parameters to fit; the others keep their values in `start`.
  std::vector<Parameter> free = {Parameter::melanin, Parameter::melanin_blend,
                                 Parameter::hemoglobin};
  physics::SkinParameters start;  // fixed values, and the LM start for the extended terms
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
  // extended: bounds default to prior_bounds and the Gaussian prior terms are added (weight
  // kSpectrumPriorWeight); `free` is not changed (use_fit_model sets it).
  FitModel fit_model = FitModel::paper;
};
// Sets options.fit_model and options.free (the paper's three or extended_model_free(true)).
void use_fit_model(SpectrumFitOptions& options, FitModel model);

struct FitResult {
  physics::SkinParameters parameters;     // fitted values (others as in the options' start)
  std::vector<Parameter> free;   // what was fitted, in this order in `uncertainty`
  std::vector<double> uncertainty;  // one standard deviation, from s^2 (J^T J)^-1
  std::vector<bool> at_bound;       // parameter ended on its bound (uncertainty is then local)
  double rms = 0;                   // root mean square residual [reflectance]
  double specular = 0;              // the constant specular term rho_s F (0 without it)
  std::vector<double> wavelength_nm, measured, fitted;  // fitted samples
  int iterations = 0;                // LM iterations of the winning start
  int starts = 0;                    // LM runs (global stage)
  FitModel fit_model = FitModel::paper;
  // CIEDE2000 between the colours (D65, as `skin color`) of the measured and the fitted samples,
  // each linearly interpolated to 400-700 nm every 2 nm (held flat beyond the fitted range).
  double delta_e = 0;
  // The spectrum lies outside what the model reaches: rms >= kGoodFitRms.
  bool outside_gamut = false;
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
std::vector<double> model_reflectance(const physics::SkinParameters& p, const std::vector<double>& lambda,
                                      const SpectrumFitOptions& options);

}  // namespace skin::fit
