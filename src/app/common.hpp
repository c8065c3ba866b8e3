#pragma once
// Shared pieces of the `skin` subcommands: option groups declared once (parameters, wavelength
// grid, output), output formats, and the registry of subcommands.
#include <CLI/CLI.hpp>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "schema.hpp"
#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/physics/layer.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/util/work_estimate.hpp"

namespace skin::cli {

// The schemas of the outputs (src/schema/schema.hpp), shared with the web page's module.
using schema::color_columns;
using schema::color_table;
using schema::Column;
using schema::constant_column;
using schema::format_csv;
using schema::format_table;
using schema::format_text_table;
using schema::json;
using schema::ParameterFile;
using schema::Result;
using schema::to_csv;
using schema::csv_header;
using schema::csv_rows;
using schema::to_json;

bool stdout_is_terminal();
bool stderr_is_terminal();

// --preset, --params FILE.json and one flag per row of the parameter table (the key with dashes,
// and the paper's symbol as an alias): the preset, then the file, then the flags given after it
// (a flag given before --params is overridden by the file when the file sets that parameter).
struct ParameterOptions {
  std::string preset{physics::kDefaultPreset};
  std::string params_file;
  physics::SkinParameters values;  // targets of the flags
  std::vector<std::pair<CLI::Option*, const physics::ParameterInfo*>> flags;
  CLI::App* app = nullptr;
  CLI::Option* preset_option = nullptr;
  CLI::Option* params_option = nullptr;
  void add_to(CLI::App& app);
  // Whether --preset, --params or any parameter flag was given.
  bool given() const;
  physics::SkinParameters resolve() const;  // preset + file + overrides, validated
  // The same as a change of any base set, used when --preset is not given (the renderer: each
  // material's own set). The file is read once, here; the change validates what it returns.
  std::function<physics::SkinParameters(const physics::SkinParameters&)> change() const;
};

// Check of a whole-number option (counts, seeds, threads): anything but a whole number within
// [lo, hi] is refused with "<value> is out of range: must be a whole number ..." (CLI11 alone
// would wrap "-1" around in an unsigned option).
CLI::Validator whole_number(long long lo, long long hi = std::numeric_limits<long long>::max());

// Checks a request before long or large work starts (skin::util::estimate_work,
// skin/util/work_estimate.hpp): refuses it (InputError) when its memory estimate exceeds the
// machine's physical memory or its time estimate a week (a typo, surely); warns once on stderr
// with the time estimate when it would take more than an hour (SIGINT or SIGTERM stop it
// cleanly). `what` names the work ("a render of 16384x16384 pixels"), `units` /
// `units_per_second_per_thread` give the time estimate for `threads` (0 = all cores); `bytes`
// the memory.
void warn_if_long(const util::WorkEstimate& estimate);
void check_request(const std::string& what, double units, double units_per_second_per_thread,
                   int threads, double bytes);
// Measured rates for those estimates (docs/benchmarks.md; reference machine, one thread):
// renderer camera samples (default scene ~1.0e6/s, the head ~0.7e6/s) and Monte Carlo photons
// (pale skin at 650 nm, g = 0.9: 32 CPU s per 1e6).
inline constexpr double kRenderSamplesPerSecond = 1.0e6;
inline constexpr double kMcPhotonsPerSecond = 3.0e4;
// On a terminal, when `solves` of `wavelengths` profiles are solved rather than read: one line
// before the work starts, "skin: note: 151 of 151 wavelengths are off the skin table and solved
// in the frequency domain: about 44 s on 2 threads".
void note_profile_solves(std::size_t solves, std::size_t wavelengths, const std::string& what = "wavelengths");

// The run group: --seed and --threads, the same in every command that draws random numbers.
struct RunOptions {
  std::uint64_t seed = 1;
  int threads = 0;  // 0 = all cores
  void add_to(CLI::App& app, const std::string& seed_help, const std::string& group = "Run");
};

// The stack group: --layer (repeatable, top to bottom), --eta-above, --eta-below.
struct StackOptions {
  std::vector<std::string> layers;
  double eta_above = 1.0, eta_below = 1.0;
  CLI::Option* layer_option = nullptr;
  CLI::Option* add_to(CLI::App& app, const std::string& note = "");
  bool given() const { return !layers.empty(); }
  physics::LayerStack resolve() const;  // parsed and validated
};

struct GridOptions {
  double lambda_min = 400, lambda_max = 700, lambda_step = 2;
  void add_to(CLI::App& app);
  physics::WavelengthGrid resolve() const { return physics::WavelengthGrid(lambda_min, lambda_max, lambda_step); }
};

// --solver NAME: a transport model of the registry (skin/transport/model.hpp, which holds the
// default).
struct SolverOption {
  std::string name{transport::kDefaultModel};
  CLI::Option* add_to(CLI::App& app);
  const transport::Model& model() const { return transport::find_model(name); }
};
// --illuminant NAME: a CIE illuminant (skin/color/illuminant.hpp, which holds the default, D65),
// any case; an unknown name is refused with the list of the allowed ones.
struct IlluminantOption {
  std::string name{color::kDefaultIlluminant};
  CLI::Option* add_to(CLI::App& app, const std::string& help);
  const color::Illuminant& illuminant() const { return color::find_illuminant(name); }
};
// The check behind it: canonicalises the name (d65 -> D65) or fails with find_illuminant's message.
CLI::Validator illuminant_name();

// When `v` is not ok: one line on stderr naming the solver (and `what` it was for, if given),
// the reason and what stays exact. With `said`: not a line already said (its text is kept there).
void warn_validity(const transport::Model& model, const transport::Validity& v,
                   const std::string& what = "", std::set<std::string>* said = nullptr);

// The enumerator `json` names the format, the alias above the library: both read naturally at
// their use (Format::json, json j), so the shadowing warning is silenced here only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
enum class Format { table, csv, json };
#pragma GCC diagnostic pop
struct OutputOptions {
  std::string format;  // empty: table on a terminal, json otherwise
  std::string output;  // -o FILE; empty or "-": stdout
  bool with_table = true;
  void add_to(CLI::App& app, bool table_allowed = true);
  // The format; InputError for an extension of -o that names none (.xml, no extension) when
  // --format is not given (a FIFO or device takes the default).
  Format resolve() const;
  // Why `path` cannot choose the format ("'x.xml' has the extension .xml, which ..."); "" if it
  // can. `or_own`: the command's own extensions (below) are accepted too.
  std::string extension_problem(const std::string& path, bool or_own = false) const;
  // Extensions of -o that the command writes itself, not a Result (skin fit --texture: .exr);
  // set before add_to.
  std::vector<std::string> own_extensions;
  // Writes the text to the file (see skin::util::io) or stdout.
  void emit(const std::string& text) const;
  // The one result writer: the result in the resolved format, to the file or stdout.
  void write(const Result& result) const;
};

std::vector<double> to_vector(const physics::Spectrum& s);

// Parses "--layer sigma_a=A,sigma_s_prime=S,thickness=D,eta=N,g=G" (thickness missing or "inf"
// = semi-infinite). Throws InputError naming the option and the problem.
physics::Layer parse_layer(const std::string& spec, std::size_t index);

// Warns on stderr (once per quantity) if a spectrum or profile has negative values: diffusion
// outside its validity or an unphysical input. Values are never clamped.
// `colour` = true for linear sRGB channels, where negative values are legitimate (a spectrum
// outside the sRGB gamut, such as the deep-red tail of a profile) and the note says so.
void warn_if_negative(const std::string& what, const std::vector<double>& values,
                      const std::vector<double>& where, const std::string& where_unit,
                      bool colour = false);

// Each subcommand registers itself from its own file (adding one touches that file only):
// SKIN_REGISTER_COMMAND(order, function) at namespace scope; main() adds them in `order` (the
// order of `skin --help`). The function adds a sub-App with its options and callback.
using Registrar = void (*)(CLI::App& app);
struct CommandRegistration {
  CommandRegistration(int order, Registrar registrar);
};
void register_commands(CLI::App& app);
#define SKIN_REGISTER_COMMAND(order, function) \
  static const ::skin::cli::CommandRegistration skin_command_##function{order, function}

}  // namespace skin::cli
