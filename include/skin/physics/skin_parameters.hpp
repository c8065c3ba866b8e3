#pragma once
// The biophysical parameters of the two-layer skin model (DJ06 section 3, Table 1) and the
// fixed choices of the paper as named, documented defaults.
#include <iosfwd>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "skin/physics/layer.hpp"

namespace skin::physics {

struct SkinParameters {
  // The paper's four parameters (Table 1).
  double melanin = 0.005;        // C_m: melanin volume fraction of the epidermis [0, 1]
  double melanin_blend = 0.7;    // beta_m: eumelanin share of the melanin [0, 1]
  double hemoglobin = 0.005;     // C_h: blood volume fraction of the dermis [0, 1]
  double oiliness = 0.3;         // rho_s: scale of the specular lobe [0, 1]

  // The paper's fixed choices, as parameters.
  double oxygenation = 0.75;            // gamma: oxy share of the hemoglobin [0, 1] (sec 3.4)
  double epidermis_thickness = 0.25;    // [mm] (sec 3.5)
  double dermis_scattering_scale = 0.5; // dermis sigma_s' = this x epidermis sigma_s' (sec 3.5)
  double eta = 1.4;                     // refractive index of both layers (sec 3.5)
  double roughness = 0.35;              // Beckmann RMS slope sigma of the surface (sec 3.1)
  double g = 0.9;                       // HG anisotropy, used only by transport solvers
                                        // (the paper gives reduced scattering only)

  // Extended model (the paper's future work), all off by default.
  double epidermal_hemoglobin = 0.0;  // blood volume fraction of the epidermis [0, 1]
  double beta_carotene = 0.0;         // beta-carotene in the epidermis [umol/L], [0, 1000]
  double bilirubin = 0.0;             // bilirubin in the dermis [umol/L], [0, 1000]
  double scattering_scale = 1.0;      // multiplies sigma_s' of both layers, (0, 10]
  // Mean radius of the dermis' blood vessels [mm], [0, 1]: blood confined to vessels absorbs
  // less than the same blood spread evenly (vessel packaging). 0: spread evenly (the paper's).
  double blood_vessel_radius = 0.0;

  // Throws InputError naming the parameter (with its CLI spelling), value and range.
  void validate() const;
  bool operator==(const SkinParameters&) const = default;
};

std::ostream& operator<<(std::ostream& os, const SkinParameters& p);

// The parameter table: the one home of every model parameter's name, symbol, unit, range,
// default and help. Every surface iterates it: validation, printing, CLI flags (the key with
// dashes), JSON keys, scene material keys, EXR channel names, Python keywords, the fit's free
// parameters (the rows with a fit interval: fit::Parameter) and `skin parameters`.
struct ParameterInfo {
  std::string_view key;     // canonical name: JSON/scene key, EXR channel, Python keyword
  std::string_view symbol;  // the paper's symbol (accepted as an alias on input), "" if none
  std::string_view unit;    // "1" for dimensionless quantities, "mm", "umol/L"
  double min, max;          // allowed range; max may be infinite
  bool min_open, max_open;  // whether the bound itself is excluded
  std::string_view help;    // one line
  double SkinParameters::*member;
  // The skin domain: the range a person would use for human skin (the transport models are
  // validated over it, docs/accurate-solver.md sec. 7; the validity report names what lies
  // outside). Inside [min, max].
  double domain_min, domain_max;
  // The fit's default search interval [fit_min, fit_max] (inclusive, inside the range; sources
  // in src/physics/skin_parameters.cpp and docs/fit.md); NaN for a parameter the fit does not
  // free.
  double fit_min = std::numeric_limits<double>::quiet_NaN();
  double fit_max = std::numeric_limits<double>::quiet_NaN();
  // The prior of the extended fit (`skin fit --model extended`, fit::FitModel::extended): the
  // range measured on human skin that the fit keeps the parameter in [prior_min, prior_max], and
  // the centre of a weak Gaussian pull toward it (its width is the range; prior_log: in
  // log(value)). NaN where there is none; prior_centre NaN: the range only. Sources in
  // src/physics/skin_parameters.cpp and docs/fit.md.
  double prior_min = std::numeric_limits<double>::quiet_NaN();
  double prior_max = std::numeric_limits<double>::quiet_NaN();
  double prior_centre = std::numeric_limits<double>::quiet_NaN();
  bool prior_log = false;
  // Whether sample_skin_domain draws it (false: it keeps its default there; the domain still
  // bounds it for outside_skin_domain).
  bool sampled = true;

  std::string flag() const;        // the CLI spelling: key with dashes ("melanin-blend")
  std::string label() const;       // for messages: "melanin-blend (beta_m)"
  std::string range_text() const;  // "[0, 1]", "(0, inf)"
  double default_value() const;    // the value in a default-constructed SkinParameters
  bool in_range(double v) const;   // false for NaN
  bool fittable() const;           // whether the fit can free it (it has a fit interval)
  bool has_prior_range() const;    // whether prior_min, prior_max are set
  // Throws InputError "<label> = <v> [unit] is out of range: ..." unless in_range(v).
  void check(double v) const;
  bool in_domain(double v) const { return v >= domain_min && v <= domain_max; }
  std::string domain_text() const;  // "[0.02, 0.5]"
};
// All parameters, in the order of SkinParameters' members.
std::span<const ParameterInfo> parameter_table();
// The parameters of `p` outside the skin domain, as "<label> = <v> (skin domain [lo, hi])",
// in the table's order; empty when `p` lies in it.
std::vector<std::string> outside_skin_domain(const SkinParameters& p);
// `n` parameter sets drawn from the skin domain by a generator seeded with `seed` (the same
// sets for the same seed on every platform). Each parameter independently: with probability
// 1/8 its lower edge, 1/8 its upper edge, otherwise uniform over the domain (uniform in the
// logarithm when the domain spans more than a factor of 4 above 0: epidermis thickness and the
// scattering scales), so that samples reach the domain's edges and corners. Rows with
// `sampled` false keep their default (blood_vessel_radius: packaging only lowers the dermis'
// absorption, a range the sampled blood fraction already spans; the sets of a seed are those
// drawn before it was added).
std::vector<SkinParameters> sample_skin_domain(std::size_t n, std::uint64_t seed);
// By key, key with dashes, or paper symbol; nullptr if unknown.
const ParameterInfo* find_parameter(std::string_view name);
// The same; throws InputError "<what> '<name>' is unknown: known parameters are ..." otherwise.
const ParameterInfo& parameter_info(std::string_view name, std::string_view what = "parameter");
// Of some channel names (an OpenEXR file's), those that are a parameter's key exactly (a map of
// that parameter, as skin fit --texture writes them), in the parameter table's order (the
// extended model's free parameters' order; an OpenEXR file lists its channels alphabetically).
std::vector<std::string> parameter_channels(const std::vector<std::string>& names);
// The parameters named by one source (a parameter file's keys, a table's columns): each name
// resolved as parameter_info(name, what) does, and a second name for a parameter already named
// (its key and its symbol, "melanin" and "C_m") refused, since one of the two values would be
// dropped: InputError "<what> '<name>' repeats parameter <key> (given as '<first>' already)".
class ParameterNames {
 public:
  explicit ParameterNames(std::string what = "parameter") : what_(std::move(what)) {}
  const ParameterInfo& add(std::string_view name);

 private:
  std::string what_;
  std::vector<std::pair<const ParameterInfo*, std::string>> named_;
};

// Absorption and reduced scattering of the two layers at one wavelength [1/mm] (eqs 3-8).
struct LayerCoefficients {
  double sigma_a;
  double sigma_s_prime;
};
LayerCoefficients epidermis_coefficients(const SkinParameters& p, double lambda);
LayerCoefficients dermis_coefficients(const SkinParameters& p, double lambda);
// Vessel packaging (Svaasand et al. 1995, Lasers Med Sci 10:55; in the form of van Veen,
// Verkruysse & Sterenborg 2002, Opt Lett 27:246): blood of absorption `sigma_a_blood` [1/mm] in
// vessels of radius `radius` [mm] absorbs as the same blood spread evenly times
// (1 - exp(-2 sigma_a_blood radius)) / (2 sigma_a_blood radius); 1 at radius 0.
double vessel_packaging(double sigma_a_blood, double radius);

// Epidermis (finite) over semi-infinite dermis, air above, at one wavelength.
LayerStack skin_layer_stack(const SkinParameters& p, double lambda);

// Named parameter sets: the paper's (Fig. 8 and Fig. 10, tuned by eye under its multipole model)
// and the tone presets monk-01 ... monk-10, fitted offline to the Monk Skin Tone scale's swatches
// with the default exact solver under D65 (scripts/fit_tone_presets.py, docs/tone-presets.md).
struct Preset {
  std::string name;
  std::string description;
  SkinParameters parameters;
  std::string source;      // where the values come from
  std::string target_hex;  // "#rrggbb" the preset was fitted to; "" for the paper's
};
const std::vector<Preset>& presets();
// The paper's six, the first rows of presets(). The transport tests and the golden outputs run
// over these (the paper's geometry; every preset, the tone presets too, is read from the skin
// table at every wavelength).
std::span<const Preset> paper_presets();
// The preset a command, a Python call or the web page starts from when none is named (its
// parameters are a default-constructed SkinParameters').
inline constexpr std::string_view kDefaultPreset = "caucasian";
// Throws InputError listing the known names when `name` is unknown. Accepts aliases
// ("several-lights" for "ear").
const Preset& find_preset(std::string_view name);

}  // namespace skin::physics
