#pragma once
// Shared pieces of the `skin` subcommands: option groups declared once (parameters, wavelength
// grid, output), output formats, and the registry of subcommands.
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/physics/layer.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"

namespace skin::cli {

using json = nlohmann::ordered_json;  // NOLINT

bool stdout_is_terminal();
bool stderr_is_terminal();

// --preset and one flag per model parameter; flags given override the preset.
struct ParameterOptions {
  std::string preset = "caucasian";
  SkinParameters values;  // targets of the flags
  std::vector<std::pair<CLI::Option*, double SkinParameters::*>> flags;
  void add_to(CLI::App& app);
  SkinParameters resolve() const;  // preset + overrides, validated
};

struct GridOptions {
  double lambda_min = 400, lambda_max = 700, lambda_step = 2;
  void add_to(CLI::App& app);
  WavelengthGrid resolve() const { return WavelengthGrid(lambda_min, lambda_max, lambda_step); }
};

// --solver NAME: a transport model of the registry (skin/transport/model.hpp, which holds the
// default).
struct SolverOption {
  std::string name{transport::kDefaultModel};
  CLI::Option* add_to(CLI::App& app);
  const transport::Model& model() const { return transport::find_model(name); }
};
// When `v` is not ok: one line on stderr naming the solver (and `what` it was for, if given),
// the reason and what stays exact.
void warn_validity(const transport::Model& model, const transport::Validity& v,
                   const std::string& what = "");
// {"totals": bool, "profile": bool, "reason": "..."} (reason only when one is false).
json to_json(const transport::Validity& v);

// The enumerator `json` names the format, the alias above the library: both read naturally at
// their use (Format::json, json j), so the shadowing warning is silenced here only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
enum class Format { table, csv, json };
#pragma GCC diagnostic pop
struct OutputOptions {
  std::string format;  // empty: table on a terminal, json otherwise
  std::string output;  // -o FILE; empty: stdout
  void add_to(CLI::App& app, bool with_table = true);
  Format resolve() const;
  // Writes the text to the file (atomically) or stdout.
  void emit(const std::string& text) const;
};

// Fixed-width table for terminals: header row, then rows of numbers.
std::string format_table(const std::vector<std::string>& header,
                         const std::vector<std::vector<double>>& columns);
std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns);

json to_json(const SkinParameters& p);
json to_json(const color::ColorSummary& c);
std::string color_table(const color::ColorSummary& c);
std::vector<double> to_vector(const Spectrum& s);

// Parses "--layer sigma_a=A,sigma_s_prime=S,thickness=D,eta=N,g=G" (thickness missing or "inf"
// = semi-infinite). Throws InputError naming the option and the problem.
Layer parse_layer(const std::string& spec, std::size_t index);

// Warns on stderr (once per quantity) if a spectrum or profile has negative values: diffusion
// outside its validity or an unphysical input. Values are never clamped.
// `colour` = true for linear sRGB channels, where negative values are legitimate (a spectrum
// outside the sRGB gamut, such as the deep-red tail of a profile) and the note says so.
void warn_if_negative(const std::string& what, const std::vector<double>& values,
                      const std::vector<double>& where, const std::string& where_unit,
                      bool colour = false);

// Each subcommand registers itself: adds a sub-App with its options and a callback.
using Registrar = void (*)(CLI::App& app);
void register_spectrum(CLI::App& app);
void register_profile(CLI::App& app);
void register_layers(CLI::App& app);
void register_color(CLI::App& app);
void register_presets(CLI::App& app);

}  // namespace skin::cli
