#include "common.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <algorithm>
#include <charconv>
#include <optional>
#include <iostream>
#include <sstream>

#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"

namespace skin::cli {

using skin::util::InputError;
using skin::util::WorkEstimate;
using skin::util::estimate_work;
using skin::util::format_number;
using skin::util::require_positive;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::Spectrum;
using skin::physics::find_preset;
using skin::physics::parameter_table;
using skin::physics::presets;

namespace {
std::vector<std::pair<int, Registrar>>& registrations() {
  static std::vector<std::pair<int, Registrar>> list;
  return list;
}
}  // namespace

CommandRegistration::CommandRegistration(int order, Registrar registrar) {
  registrations().emplace_back(order, registrar);
}

namespace {
// The validators of an option, for putting a check before those the command added (CLI11 runs
// them in order and reports the first failure; its public interface only appends).
struct OptionValidators : CLI::Option {
  static std::vector<CLI::Validator>& of(CLI::Option& o) { return o.*(&OptionValidators::validators_); }
};

// An empty value ("--melanin ''", "--melanin=", an unset shell variable) would otherwise reach
// CLI11's conversion, which reads it as 0 (or an empty name): refused for every option that
// takes a value, before that option's own checks.
void refuse_empty_values(CLI::App& app) {
  for (CLI::Option* o : app.get_options()) {
    if (o->get_type_size_max() == 0) continue;  // a flag
    CLI::Validator not_empty(
        [](std::string& value) {
          return value.empty() ? std::string("the value is empty (an unset shell variable?): give a value or leave the option out")
                               : std::string();
        },
        "");
    not_empty.non_modifying();
    auto& validators = OptionValidators::of(*o);
    validators.insert(validators.begin(), std::move(not_empty));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) refuse_empty_values(*sub);
}
}  // namespace

void register_commands(CLI::App& app) {
  auto list = registrations();
  std::stable_sort(list.begin(), list.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& r : list) r.second(app);
  refuse_empty_values(app);
}

bool stdout_is_terminal() { return ::isatty(STDOUT_FILENO) != 0; }
bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) != 0; }

void ParameterOptions::add_to(CLI::App& a) {
  app = &a;
  std::string names;
  for (const auto& p : presets()) names += (names.empty() ? "" : ", ") + p.name;
  preset_option = a.add_option("--preset", preset,
                               "Named parameter set (skin presets): " + names + " (several-lights = ear)")
                      ->capture_default_str()
                      ->group("Skin parameters");
  params_option =
      a.add_option("--params", params_file,
                   "Parameters from FILE.json: the JSON skin fit or skin spectrum writes, or an "
                   "object of parameter keys (skin parameters lists them); flags given after it "
                   "override it")
          ->group("Skin parameters");
  for (const ParameterInfo& info : parameter_table()) {
    std::string name = "--" + info.flag();
    if (!info.symbol.empty()) name += ",--" + std::string(info.symbol);
    const std::string unit = info.unit == "1" ? "" : " [" + std::string(info.unit) + "]";
    CLI::Option* o = a.add_option(name, values.*(info.member),
                                  std::string(info.help) + unit + ", " + info.range_text() +
                                      "; default " + format_number(info.default_value()));
    o->group("Skin parameters (override the preset)");
    flags.emplace_back(o, &info);
  }
}

bool ParameterOptions::given() const {
  if (preset_option->count() > 0 || params_option->count() > 0) return true;
  for (const auto& f : flags)
    if (f.first->count() > 0) return true;
  return false;
}

namespace {
// Position of the last occurrence of `o` in the command line's parse order (-1 if absent).
long last_position(const CLI::App& app, const CLI::Option* o) {
  const auto& order = app.parse_order();
  for (std::size_t i = order.size(); i-- > 0;)
    if (order[i] == o) return static_cast<long>(i);
  return -1;
}
}  // namespace

SkinParameters ParameterOptions::resolve() const {
  return change()(find_preset(preset).parameters);
}

std::function<SkinParameters(const SkinParameters&)> ParameterOptions::change() const {
  std::optional<SkinParameters> from_preset;
  if (preset_option->count() > 0) from_preset = find_preset(preset).parameters;
  ParameterFile file;
  if (params_option->count() > 0) file = ParameterFile::read(params_file);
  // The flags that apply: all but those given before --params for parameters the file sets.
  std::vector<const ParameterInfo*> applied;
  const long file_at = last_position(*app, params_option);
  for (const auto& [opt, info] : flags)
    if (opt->count() > 0 && (!file.sets(info) || last_position(*app, opt) > file_at))
      applied.push_back(info);
  return [from_preset, file = std::move(file), applied, values = values](const SkinParameters& base) {
    SkinParameters p = from_preset ? *from_preset : base;
    file.apply(p);
    for (const ParameterInfo* info : applied) p.*(info->member) = values.*(info->member);
    p.validate();
    return p;
  };
}

void note_profile_solves(std::size_t solves, std::size_t wavelengths, const std::string& what) {
  if (solves == 0 || !stderr_is_terminal()) return;
  const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const double seconds = static_cast<double>(solves) / (model::kProfileSolvesPerSecond * threads);
  std::cerr << "skin: note: " << solves << " of " << wavelengths << " " << what
            << " are off the skin and half-space tables and solved in the frequency domain: about "
            << format_number(std::round(seconds)) << " s on " << threads
            << " threads; Ctrl-C stops it without writing anything\n";
}

void warn_if_long(const WorkEstimate& estimate) {
  if (estimate.long_run())
    std::cerr << "skin: warning: " << estimate.text << "; Ctrl-C stops it without writing anything\n";
}

void check_request(const std::string& what, double units, double units_per_second_per_thread,
                   int threads, double bytes) {
  warn_if_long(estimate_work(what, units, units_per_second_per_thread, threads, bytes));
}

CLI::Validator whole_number(long long lo, long long hi) {
  const std::string allowed =
      hi == std::numeric_limits<long long>::max()
          ? ">= " + std::to_string(lo)
          : "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, allowed](std::string& text) -> std::string {
        long long v = 0;
        const char* end = text.data() + text.size();
        const auto res = std::from_chars(text.data(), end, v);
        if (res.ec != std::errc() || res.ptr != end || v < lo || v > hi)
          return text + " is out of range: must be a whole number " + allowed;
        return {};
      },
      "INT " + allowed);
}

CLI::Option* SolverOption::add_to(CLI::App& app) {
  std::string help = "Light transport in the layers:";
  for (const auto& n : transport::model_names())
    help += (n == transport::model_names().front() ? " " : ", ") + n + " (" +
            std::string(transport::find_model(n).description()) + ")";
  return app.add_option("--solver", name, help)
      ->check(CLI::IsMember(transport::model_names()))
      ->capture_default_str();
}

CLI::Validator illuminant_name() {
  return CLI::Validator(
      [](std::string& value) {
        try {
          value = color::find_illuminant(value).name();
          return std::string();
        } catch (const InputError& e) {
          return std::string(e.what());
        }
      },
      "NAME");
}

CLI::Option* IlluminantOption::add_to(CLI::App& app, const std::string& help) {
  return app.add_option("--illuminant", name, help)->transform(illuminant_name())->capture_default_str();
}

void warn_validity(const transport::Model& model, const transport::Validity& v,
                   const std::string& what, std::set<std::string>* said) {
  if (v.ok()) return;
  const std::string text = transport::warning_text(model.name(), v, what);
  if (said && !said->insert(text).second) return;
  std::cerr << "skin: warning: " << text << '\n';
}

void RunOptions::add_to(CLI::App& app, const std::string& seed_help, const std::string& group) {
  app.add_option("--seed", seed, seed_help)->check(whole_number(0))->capture_default_str()->group(group);
  app.add_option("--threads", threads, "Worker threads (0 = all cores)")
      ->check(whole_number(0, 4096))
      ->capture_default_str()
      ->group(group);
}

CLI::Option* StackOptions::add_to(CLI::App& app, const std::string& note) {
  layer_option =
      app.add_option("--layer", layers,
                     "A layer, top to bottom: sigma_a=A,sigma_s_prime=S[,thickness_mm=D][,eta=N][,g=G] "
                     "(1/mm, mm; thickness= is accepted too; eta default 1.4, g default 0.9; no thickness = semi-infinite, "
                     "last layer only)" + note)
          ->take_all()
          ->allow_extra_args(false)
          ->group("Layer stack");
  app.add_option("--eta-above", eta_above, "Refractive index above the stack, [1, 3]" + note)
      ->capture_default_str()
      ->group("Layer stack");
  app.add_option("--eta-below", eta_below, "Refractive index below the stack, [1, 3]" + note)
      ->capture_default_str()
      ->group("Layer stack");
  return layer_option;
}

LayerStack StackOptions::resolve() const {
  LayerStack stack;
  stack.eta_above = eta_above;
  stack.eta_below = eta_below;
  for (std::size_t i = 0; i < layers.size(); ++i) stack.layers.push_back(parse_layer(layers[i], i));
  stack.validate();
  return stack;
}

void GridOptions::add_to(CLI::App& app) {
  app.add_option("--lambda-min", lambda_min, "Shortest wavelength [nm]")->capture_default_str()->group("Wavelengths");
  app.add_option("--lambda-max", lambda_max, "Longest wavelength [nm]")->capture_default_str()->group("Wavelengths");
  app.add_option("--lambda-step", lambda_step, "Wavelength step [nm]; (max - min) / step must be whole")->capture_default_str()->group("Wavelengths");
}

void OutputOptions::add_to(CLI::App& app, bool table_allowed) {
  with_table = table_allowed;
  app.add_option("--format", format,
                 with_table ? "Output format: table (default on a terminal), csv, json (default "
                              "when piped); with -o, inferred from its extension (.txt, .csv, .json)"
                            : "Output format: csv, json (default); with -o, inferred from its "
                              "extension (.csv, .json)")
      ->check(with_table ? CLI::IsMember({"table", "csv", "json"}) : CLI::IsMember({"csv", "json"}))
      ->group("Output");
  CLI::Option* format_option = app.get_option("--format");
  std::string own_help;
  for (const std::string& e : own_extensions) own_help += (own_help.empty() ? " (." : ", .") + e;
  if (!own_help.empty()) own_help += ": written by the command itself)";
  app.add_option("-o,--output", output,
                 std::string("Write to FILE instead of standard output ('-'): a regular file is replaced "
                 "atomically (complete or not at all), a symbolic link's target likewise, a FIFO "
                 "or device is written in place. Its extension chooses the format (") +
                     (with_table ? ".json, .csv, .txt" : ".json, .csv") +
                     "); another one, or none, needs --format" + own_help)
      ->check(CLI::Validator(
          [this, format_option](std::string& path) {
            return format_option->count() > 0 ? std::string() : extension_problem(path, true);
          },
          ""))
      ->group("Output");
}

std::string OutputOptions::extension_problem(const std::string& path, bool or_own) const {
  if (path.empty() || path == "-") return {};
  const std::string ext = util::io::extension(path);
  if (ext == "json" || ext == "csv" || (ext == "txt" && with_table)) return {};
  if (or_own && std::find(own_extensions.begin(), own_extensions.end(), ext) != own_extensions.end()) return {};
  // A FIFO or device (/dev/null, a pipe) has no format of its own: the default, as on a pipe.
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
      !std::filesystem::is_directory(st))
    return {};
  return "'" + path + "' " + (ext.empty() ? std::string("has no extension") : "has the extension ." + ext) +
         ", which names no format: use " + (with_table ? ".json, .csv or .txt" : ".json or .csv") +
         ", or give --format";
}

Format OutputOptions::resolve() const {
  const bool to_stdout = output.empty() || output == "-";
  std::optional<Format> from_extension;
  const std::string ext = to_stdout ? "" : util::io::extension(output);
  if (ext == "json") from_extension = Format::json;
  if (ext == "csv") from_extension = Format::csv;
  if (ext == "txt" && with_table) from_extension = Format::table;
  if (format.empty())
    if (const std::string problem = extension_problem(output); !problem.empty())
      throw InputError("output = " + problem);
  if (!format.empty()) {
    const Format f = format == "table" ? Format::table : format == "csv" ? Format::csv : Format::json;
    if (from_extension && *from_extension != f)
      throw InputError("--format " + format + " contradicts the extension of -o '" + output +
                       "' (." + ext + "): give one or make them agree");
    return f;
  }
  if (from_extension) return *from_extension;
  return (to_stdout && stdout_is_terminal() && with_table) ? Format::table : Format::json;
}

void OutputOptions::emit(const std::string& text) const {
  if (output.empty() || output == "-") util::io::write_stdout(text);
  else util::io::write_file_atomic(output, text);
}

void OutputOptions::write(const Result& result) const {
  switch (resolve()) {
    case Format::json: emit(result.document.dump(2) + "\n"); break;
    case Format::csv: emit(to_csv(result.columns)); break;
    case Format::table: emit(result.table.empty() ? schema::columns_table(result.columns) : result.table); break;
  }
}

std::vector<double> to_vector(const Spectrum& s) { return s.values; }

Layer parse_layer(const std::string& spec, std::size_t index) {
  const std::string where = "--layer " + std::to_string(index + 1) + " '" + spec + "'";
  const std::string keys = "keys: sigma_a, sigma_s_prime, thickness_mm (or thickness), eta, g";
  Layer l;
  bool have_a = false, have_s = false;
  std::size_t start = 0;
  if (spec.empty()) throw InputError(where + " is malformed: expected key=value pairs separated by commas (" + keys + ")");
  while (start <= spec.size()) {
    std::size_t comma = spec.find(',', start);
    const std::string item = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
      throw InputError(where + " is malformed: '" + item + "' is not key=value (" + keys + ")");
    const std::string key = item.substr(0, eq), val = item.substr(eq + 1);
    double v;
    try {
      std::size_t used = 0;
      v = std::stod(val, &used);
      if (used != val.size()) throw std::invalid_argument(val);
    } catch (const std::exception&) {
      throw InputError(where + " is malformed: value of " + key + " ('" + val + "') is not a number");
    }
    if (key == "sigma_a") { l.sigma_a = v; have_a = true; }
    else if (key == "sigma_s_prime") { l.sigma_s_prime = v; have_s = true; }
    else if (key == "thickness_mm" || key == "thickness") {
      if (!(v > 0)) require_positive("layer " + std::to_string(index + 1) + " thickness", v, "mm");
      l.thickness = v;
    }
    else if (key == "eta") l.eta = v;
    else if (key == "g") l.g = v;
    else throw InputError(where + " is malformed: unknown key '" + key + "' (" + keys + ")");
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (!have_a || !have_s)
    throw InputError(where + " is malformed: sigma_a and sigma_s_prime are required");
  return l;
}

void warn_if_negative(const std::string& what, const std::vector<double>& values,
                      const std::vector<double>& where, const std::string& where_unit,
                      bool colour) {
  double peak = 0.0;
  for (double v : values) peak = std::max(peak, std::abs(v));
  for (std::size_t i = 0; i < values.size(); ++i) {
    // The numerical inverse transform is accurate to ~1e-8 of the profile's peak (tests in
    // tests/physics); values below that are its noise, anything beyond is real.
    if (values[i] < -1e-8 * peak) {
      if (colour) {
        std::cerr << "skin: note: " << what << " is negative (" << values[i] << ") from "
                  << where[i] << ' ' << where_unit
                  << " on: the light there is outside the sRGB gamut (too saturated); values are "
                     "not clamped\n";
        return;
      }
      std::cerr << "skin: warning: " << what << " is negative (" << values[i] << ") at "
                << where[i] << ' ' << where_unit
                << ": diffusion theory is outside its validity here (unphysical input or a layer "
                   "thinner than one transport mean free path); values are not clamped\n";
      return;
    }
  }
}

}  // namespace skin::cli
