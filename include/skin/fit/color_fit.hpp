#pragma once
// Inverse model from colour: the parameters (C_m, beta_m, C_h) whose R_d colour under D65 (as
// `skin color` computes it: CIE 1931 2-degree, 400-700 nm every 2 nm, white-balanced sRGB)
// matches a given sRGB colour, and per-pixel parameter maps from an albedo texture.
//
// Three colour coordinates, three unknowns, but beta_m (eumelanin share) is weakly identifiable
// from colour: many (C_m, beta_m) pairs give nearly the same colour. It is resolved by a
// regulariser toward a prior: the least-squares objective is
//   |Lab(params) - Lab_target|^2 + (w (beta_m - beta_prior))^2,
// with w small (default 0.2 Lab units per unit of beta_m), so that the colour error it can cause
// is at most ~0.2 while flat directions are pulled to the prior. Fixing beta_m (leaving it out
// of `free`) is the limit w -> infinity. Details: docs/fit.md.
#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/fit/fit.hpp"
#include "skin/image/image.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/util/progress.hpp"

namespace skin::fit {

struct ColorFitOptions {
  // A subset of {melanin, melanin_blend, hemoglobin}; the others keep their values in `start`.
  std::vector<Parameter> free = {Parameter::melanin, Parameter::melanin_blend,
                                 Parameter::hemoglobin};
  physics::SkinParameters start;            // fixed values (and the other model parameters)
  double melanin_blend_prior = 0.7;   // beta_prior (the paper's Caucasian and African value)
  double melanin_blend_weight = 0.2;  // w [Lab units per unit beta_m], >= 0
  physics::WavelengthGrid grid;                // colour integration grid, as `skin color`
  std::vector<std::pair<Parameter, Bounds>> bounds;  // overriding default_bounds
  ForwardModel model;                 // empty: forward_model(transport::default_model())
  // extended: any parameter with a fit interval may be free; bounds default to prior_bounds; the
  // residuals are CIEDE2000's three components (delta_e_2000_components) and the Gaussian prior
  // terms (weight kColorPriorWeight); melanin_blend_prior/weight are not used. docs/fit.md.
  FitModel fit_model = FitModel::paper;
};
// Sets options.fit_model and options.free (the paper's three or extended_model_free(false)).
void use_fit_model(ColorFitOptions& options, FitModel model);

struct ColorFitResult {
  physics::SkinParameters parameters;
  color::Lab target, fitted;     // CIELAB relative to the grid's D65 white
  color::Rgb fitted_srgb_linear;
  double delta_e = 0;            // CIEDE2000 between target and fitted
  int iterations = 0;
  FitModel fit_model = FitModel::paper;
  bool outside_gamut = false;    // delta_e > kGamutDeltaE: the model does not reach the target
  std::vector<Parameter> free;   // fitted, in the order of the next two
  // One standard deviation per free parameter for a target known to one unit per residual (Lab
  // units for the paper model, CIEDE2000 for the extended one): sqrt of the diagonal of
  // (J^T J)^-1, J the Jacobian of the residuals (prior terms included) at the solution; infinity
  // where the colour and the prior leave a direction free. Empty for the texture path.
  std::vector<double> uncertainty;
  std::vector<bool> at_bound;    // ended on its search bound
};
std::ostream& operator<<(std::ostream& os, const ColorFitResult& r);

// The colour (CIELAB under D65, as `skin color`: 400-700 nm every 2 nm, white-balanced) of a
// reflectance sampled at increasing wavelengths `lambda`, linearly interpolated to the grid and
// held flat beyond the samples.
color::Lab reflectance_lab(const std::vector<double>& lambda, const std::vector<double>& R);
// The Individual Typology Angle of a colour, atan((L* - 50) / b*) in degrees (atan2, so b* <= 0
// gives +-90), and its skin-tone bin: "very light" > 55, "light" > 41, "intermediate" > 28,
// "tan" > 10, "brown" > -30, else "dark" (docs/fit.md, "Validation by skin tone").
double ita_degrees(const color::Lab& lab);
std::string_view ita_bin(double ita_degrees);
// The bins in that order, lightest first.
const std::vector<std::string_view>& ita_bins();

// Parses "R,G,B" (8-bit sRGB-encoded values 0-255, decimals allowed) or "RRGGBB" / "#RRGGBB";
// returns linear sRGB. Throws InputError naming the option and value.
color::Rgb parse_srgb8(const std::string& text);
color::Rgb parse_hex(const std::string& text);

// Fits single colours with the exact model (R_d on the whole grid per evaluation). Holds a
// table over the parameter space (built on first use) for the starting point. Thread-safe.
class ColorFitter {
 public:
  explicit ColorFitter(ColorFitOptions options = {});
  ~ColorFitter();
  ColorFitter(ColorFitter&&) noexcept;
  ColorFitter& operator=(ColorFitter&&) noexcept;
  const ColorFitOptions& options() const;
  // Target as linear sRGB (white-balanced: a perfect reflector is 1, 1, 1).
  ColorFitResult fit(const color::Rgb& srgb_linear) const;
  // The model's colour for a parameter set (Lab relative to the grid's white).
  color::Lab lab(const physics::SkinParameters& p) const;
  void prepare() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  friend class TextureFitter;
};

// Albedo textures are read by skin::image::read_image (8- or 16-bit PNG, JPEG, ...: linear sRGB
// in 0-1, the transfer curve decoded).
using image::Image;

// Per-pixel parameter maps. Channels, in this order: melanin, melanin_blend, hemoglobin, error
// (CIEDE2000 between the pixel and the fitted colour). Layout: docs/parameter-maps.md.
struct ParameterMaps {
  int width = 0, height = 0;
  std::vector<float> melanin, melanin_blend, hemoglobin, error;
  // Statistics of the error channel.
  double mean_error = 0, max_error = 0;
  double fraction_below_1 = 0;  // share of pixels with error < 1
  // Gamut: the pixels with error > kGamutDeltaE lie outside the model's gamut; their mean error.
  double mean_error_outside = 0;
  // Texels whose melanin, melanin_blend, hemoglobin ended on its search bound (by the fit; 0 for
  // maps read from a file), and texels with any of them on a bound.
  std::array<std::size_t, 3> at_bound{};
  std::size_t any_at_bound = 0;
  // Extended model (--model extended): the maps of the free parameters besides those three
  // (oxygenation, epidermis_thickness, dermis_scattering_scale, scattering_scale, ...), in the
  // order fitted, written as more channels named by parameter key; and the texels with each of
  // them on its bound.
  std::vector<Parameter> more_parameters;
  std::vector<std::vector<float>> more;
  std::vector<std::size_t> more_at_bound;
  // With TextureFitter::fit(..., uncertainty = true): one standard deviation per free parameter
  // and texel, in the parameter's unit, as ColorFitResult::uncertainty defines it (a target known
  // to one unit per residual: Lab units for the paper model, CIEDE2000 for the extended one;
  // infinity where the colour and the prior leave a direction free); written as the channels
  // "uncertainty.<key>" (an EXR layer). In the order of uncertainty_parameters (the fit's free
  // parameters).
  std::vector<Parameter> uncertainty_parameters;
  std::vector<std::vector<float>> uncertainty;
  // The file's channels in the maps' order: the four, `more`'s keys, then the uncertainty layer.
  std::vector<std::string> channel_names() const;
  // Recomputes the three statistics from the error channel.
  void update_error_statistics();
};
std::ostream& operator<<(std::ostream& os, const ParameterMaps& m);
// The channel of a parameter's uncertainty map: "uncertainty.<key>".
std::string uncertainty_channel(Parameter p);

// A texture fit's colour table: the model's colour as the texture tables hold it
// (TextureFitter::node_lab) at every node of a grid over the free parameters (per parameter,
// `nodes` values evenly spaced over its bounds: in log(value + offset) where `log`, else in the
// value), row-major with the last free parameter fastest. The built-in ones,
// data/paper_color_table.csv and data/extended_color_table.csv (`skin tabulate-color-table`),
// serve the default paper and extended texture fits; any other set of free parameters, bounds,
// fixed values or forward model builds its own.
struct ColorTable {
  std::vector<Parameter> free;
  std::vector<Bounds> bounds;  // per free parameter
  std::vector<int> nodes;      // per free parameter
  std::vector<bool> log;       // per free parameter: nodes even in log(value + offset)
  std::vector<double> offset;  // per free parameter (0 where not log)
  std::vector<color::Lab> lab;
  physics::SkinParameters fixed;  // the other parameters' values (the free ones' are unused)
  // CSV text: "# key: value" lines (free, lo, hi, nodes, log, offset, the fixed parameters,
  // provenance), then L,a,b per node, every number round-trip exact.
  std::string to_csv(std::string_view provenance) const;
  // Throws InputError naming `source` on a malformed file or a node count that does not match.
  static ColorTable parse(std::string_view text, const std::string& source);
};

// Texture fit: a dense table of the model's Lab over (log C_m, beta_m, log C_h), the per-pixel
// objective above on the trilinearly interpolated table, solved per distinct pixel colour (in
// parallel, TBB). The error map is measured against the interpolated model; the table's own
// interpolation error is small against the exact model (tests/fit, docs/fit.md).
// Extended model: a table over every free parameter (ColorTable), the extended colour
// fit's objective (CIEDE2000 components and the prior terms) on its multilinear interpolation,
// solved twice per colour: the second time with the table's colour shifted by the table's
// piecewise-polynomial (mostly cubic) interpolation minus its multilinear one at the first
// solution; the colour reported is that interpolation's at the second, within ~0.1 dE2000 of
// the exact model (docs/fit.md).
class TextureFitter {
 public:
  // built_in_table: the fit may read its model's built-in table where it is the one these
  // options need (same free parameters, nodes, bounds and fixed values, and a few of its nodes
  // computed again agree); false always builds it (`skin tabulate-color-table`).
  explicit TextureFitter(ColorFitOptions options = {}, bool built_in_table = true);
  ~TextureFitter();
  TextureFitter(TextureFitter&&) noexcept;
  TextureFitter& operator=(TextureFitter&&) noexcept;
  // Builds the table (otherwise the first fit does); progress(nodes done, nodes) between batches
  // where the table is built, not read (may be empty).
  void prepare(const util::ProgressCallback& progress = {}) const;
  // progress(distinct colours done, distinct colours) after each batch (may be empty).
  // uncertainty: also the maps of one standard deviation per free parameter (ParameterMaps).
  ParameterMaps fit(const Image& linear_srgb, const util::ProgressCallback& progress = {},
                    bool uncertainty = false) const;
  // One colour through the texture path (interpolated table), for tests; with its uncertainty
  // (the texel's, from the table's derivatives at the solution).
  ColorFitResult fit_color(const color::Rgb& srgb_linear) const;
  // The interpolated model colour for a parameter set (for tests against ColorFitter::lab).
  color::Lab lab(const physics::SkinParameters& p) const;
  // The colour a table node holds: R_d every 10 nm (and at the grid's ends), linearly
  // interpolated to the colour grid, weighted as `skin color` does.
  color::Lab node_lab(const physics::SkinParameters& p) const;
  // The table (built, or the built-in one), and whether it is the built-in one.
  const ColorTable& color_table() const;
  bool uses_built_in_table() const;

 private:
  ParameterMaps fit_extended(int width, int height, const std::vector<std::uint32_t>& slot,
                             const std::vector<std::uint64_t>& uniq, const std::vector<std::uint32_t>& count,
                             const util::ProgressCallback& progress, bool uncertainty) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes the maps as a multi-channel 32-bit float OpenEXR (channels melanin, melanin_blend,
// hemoglobin, error; see docs/parameter-maps.md), atomically. Throws InputError on failure.
void write_parameter_maps(const ParameterMaps& maps, const std::string& path);
// Reads such a file back (all four channels required; the extended model's other channels,
// those named by a parameter key, into `more`; "uncertainty.<key>" channels into `uncertainty`).
// Throws InputError.
ParameterMaps read_parameter_maps(const std::string& path);
// The channels of a parameter-maps file beyond the four, each named by a parameter key (the
// extended model's maps: epidermis_thickness, ...), in the file's order.
std::vector<std::string> extended_map_channels(const std::string& path);

}  // namespace skin::fit
