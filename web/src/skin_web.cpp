// The WebAssembly module of the browser page (web/page): the model behind the same schemas as the
// `skin` command (src/schema), so that the page, a Node script and the CLI agree. Every entry
// point takes a request as JSON text and returns the command's output as text (JSON, or CSV /
// table with "format"), or {"error": "..."} with the one-line message the CLI would print. An
// error about the skin parameters also lists their keys, {"error": "...", "parameters": [key]}:
// the entry of "params" the message is about, or the parameters a constraint between them names
// ("melanin + epidermal-hemoglobin = ..." names both); the page flags those fields.
//
// "update" returns both documents the page shows at each change ({"spectrum", "profile"}, and
// "color" under an illuminant other than D65). Request keys mirror the command-line options:
// "preset" (default kDefaultPreset), "params" (the object --params FILE.json holds: parameter keys or
// symbols, an optional "preset"), "solver", "lambda_min", "lambda_max", "lambda_step", "format";
// for color and update also "illuminant" (default D65); for profile also "rgb",
// "radius_min", "radius_max", "samples", "spacing"; for fit "csv" (the file's text), "file"
// (its name), "column", "free", "includes_specular", "fit_lambda_min", "fit_lambda_max"; for
// export "target" and the options of `skin export` ("units", "world_scale", "name", "gaussians",
// "taps", "spectra_files").
#include <emscripten/bind.h>

#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "export_schema.hpp"
#include "fit_schema.hpp"
#include "schema.hpp"
#include "skin/export/export.hpp"
#include "skin/fit/fit.hpp"
#include "skin/color/color.hpp"
#include "skin/color/illuminant.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::web {

using skin::util::InputError;
using skin::util::Rgb;
using skin::util::Table;
using skin::util::read_csv_file;

using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;

using skin::model::SkinAppearance;
using skin::model::SkinSpectrum;
using skin::model::color_under;
using skin::model::skin_appearance;
using skin::model::skin_profile_solves;
using skin::model::skin_rgb_profile;
using skin::model::skin_spectral_profile;
using skin::model::skin_spectrum;
using skin::model::skin_validity;

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_parameter;
using skin::physics::find_preset;
using skin::physics::kDefaultPreset;
using skin::physics::parameter_table;

namespace {

using schema::json;
using schema::Result;

template <typename T>
T get_or(const json& req, const char* key, T fallback) {
  if (!req.contains(key) || req[key].is_null()) return fallback;
  try {
    return req[key].get<T>();
  } catch (const std::exception&) {
    throw InputError(std::string(key) + " = " + req[key].dump() + " has the wrong type");
  }
}

std::string preset_of(const json& req) { return get_or<std::string>(req, "preset", std::string(kDefaultPreset)); }

// An InputError about skin parameters, with their keys (the "parameters" of the error reply).
class ParameterError : public InputError {
 public:
  ParameterError(const std::string& message, std::vector<std::string> keys)
      : InputError(message), keys(std::move(keys)) {}
  std::vector<std::string> keys;
};

// The keys of the entries of a "params" object that ParameterFile::parse refuses, each parsed
// alone (unknown keys and "preset" name no parameter and are left out).
std::vector<std::string> refused_keys(const json& params) {
  std::vector<std::string> keys;
  const json& obj = params.is_object() && params.contains("parameters") ? params["parameters"] : params;
  if (!obj.is_object()) return keys;
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const ParameterInfo* info = find_parameter(it.key());
    if (info == nullptr) continue;
    try {
      schema::ParameterFile::parse(json{{it.key(), *it}}, "");
    } catch (const InputError&) {
      keys.emplace_back(info->key);
    }
  }
  return keys;
}

// The keys of the parameters of `p` that SkinParameters::validate refuses (its `message`): each
// one out of its own range, else those a constraint between them names on the left of its
// " = " ("melanin + epidermal-hemoglobin = 1.2 is out of range: ...").
std::vector<std::string> invalid_keys(const SkinParameters& p, const std::string& message) {
  std::vector<std::string> keys;
  for (const ParameterInfo& info : parameter_table())
    if (!info.in_range(p.*(info.member))) keys.emplace_back(info.key);
  if (!keys.empty()) return keys;
  const auto eq = message.find(" = ");
  if (eq == std::string::npos) return keys;
  const std::string subject = message.substr(0, eq);
  for (std::size_t start = 0; start <= subject.size();) {
    const auto plus = subject.find(" + ", start);
    const std::string term = subject.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
    if (const ParameterInfo* info = find_parameter(term)) keys.emplace_back(info->key);
    if (plus == std::string::npos) break;
    start = plus + 3;
  }
  return keys;
}

// As ParameterOptions::resolve: the preset, then the --params object, validated. Refusals are
// ParameterErrors naming the keys.
SkinParameters parameters_of(const json& req) {
  SkinParameters p = find_preset(preset_of(req)).parameters;
  if (req.contains("params")) {
    try {
      schema::ParameterFile::parse(req["params"], "params: ").apply(p);
    } catch (const InputError& e) {
      throw ParameterError(e.what(), refused_keys(req["params"]));
    }
  }
  try {
    p.validate();
  } catch (const InputError& e) {
    throw ParameterError(e.what(), invalid_keys(p, e.what()));
  }
  return p;
}

const transport::Model& model_of(const json& req) {
  return transport::find_model(get_or<std::string>(req, "solver", std::string(transport::kDefaultModel)));
}

WavelengthGrid grid_of(const json& req) {
  return WavelengthGrid(get_or(req, "lambda_min", 400.0), get_or(req, "lambda_max", 700.0),
                        get_or(req, "lambda_step", 2.0));
}

std::string write(const Result& r, const json& req) {
  const std::string format = get_or<std::string>(req, "format", "json");
  if (format == "json") return r.document.dump(2) + "\n";
  if (format == "csv") return schema::to_csv(r.columns);
  if (format == "table") return r.table.empty() ? schema::columns_table(r.columns) : r.table;
  throw InputError("format = '" + format + "' is unknown: allowed values are json, csv, table");
}

// Profile solvers by radial grid, kept between calls (each keeps its quadrature).
ProfileSolver& profile_solver(const RadialGrid& radii) {
  static std::map<std::vector<double>, std::unique_ptr<ProfileSolver>> solvers;
  if (solvers.size() >= 8 && solvers.count(radii.r) == 0) solvers.clear();
  auto& s = solvers[radii.r];
  if (!s) s = std::make_unique<ProfileSolver>(radii);
  return *s;
}

RadialGrid radii_of(const json& req) {
  const auto n = get_or<std::size_t>(req, "samples", 256);
  const std::string spacing = get_or<std::string>(req, "spacing", "log");
  if (spacing != "log" && spacing != "linear")
    throw InputError("spacing = '" + spacing + "' is unknown: allowed values are log, linear");
  return spacing == "log" ? RadialGrid::logarithmic(get_or(req, "radius_min", 1e-3), get_or(req, "radius_max", 16.0), n)
                          : RadialGrid::linear(get_or(req, "radius_max", 16.0), n);
}

Result spectrum(const json& req) {
  return schema::spectrum_result(skin_spectrum(parameters_of(req), grid_of(req), model_of(req)), preset_of(req));
}

const color::Illuminant& illuminant_of(const json& req) {
  return color::find_illuminant(get_or<std::string>(req, "illuminant", std::string(color::kDefaultIlluminant)));
}

// As `skin color --illuminant NAME`.
Result color_result(const SkinSpectrum& s, const color::Illuminant& illuminant, const std::string& preset) {
  return schema::color_result(s, preset, color_under(s, illuminant));
}

// The update's "color": under an illuminant other than the default only (the spectrum document
// holds the default's).
void add_color(json& out, const SkinSpectrum& s, const color::Illuminant& illuminant, const std::string& preset) {
  if (illuminant.name() != color::kDefaultIlluminant) out["color"] = color_result(s, illuminant, preset).document;
}

Result color(const json& req) {
  const color::Illuminant& illuminant = illuminant_of(req);
  return color_result(skin_spectrum(parameters_of(req), grid_of(req), model_of(req)), illuminant, preset_of(req));
}

Result profile(const json& req) {
  const SkinParameters p = parameters_of(req);
  const WavelengthGrid grid = grid_of(req);
  const transport::Model& model = model_of(req);
  ProfileSolver& solver = profile_solver(radii_of(req));
  const transport::Validity validity = skin_validity(p, grid, model);
  const std::string name(model.name());
  if (get_or(req, "rgb", true))
    return schema::rgb_profile_result(skin_rgb_profile(p, grid, solver, model), p, preset_of(req), name, validity);
  return schema::spectral_profile_result(skin_spectral_profile(p, grid, solver, model), p,
                                         preset_of(req), name, validity);
}

// The page's live update: the spectrum (R_d, layer coefficients, colour) and the RGB profile, the
// two documents of `skin spectrum` and `skin profile --rgb`, with the transport run once per
// wavelength (skin_appearance) and the documents alone (no table text, no columns). Under an
// illuminant other than D65, also "color": the document of `skin color --illuminant NAME`, from
// the same R_d. With "solve_profile": false, a profile the model would solve at some wavelength
// (the accurate model off its skin table, sfd: seconds per wavelength in the page's one thread)
// is not computed: "profile" is null and "profile_pending" says at how many wavelengths of how
// many it would be solved; the spectrum and colour (the totals) are computed as always.
json update(const json& req) {
  const color::Illuminant& illuminant = illuminant_of(req);
  const SkinParameters p = parameters_of(req);
  const WavelengthGrid grid = grid_of(req);
  const transport::Model& model = model_of(req);
  const std::string preset = preset_of(req);
  if (!get_or(req, "solve_profile", true)) {
    if (const std::size_t solves = skin_profile_solves(p, grid, model); solves > 0) {
      const SkinSpectrum s = skin_spectrum(p, grid, model);
      json out{{"spectrum", schema::spectrum_document(s, preset)},
               {"profile", nullptr},
               {"profile_pending", {{"wavelengths", solves}, {"of", grid.size()}, {"solver", std::string(model.name())}}}};
      add_color(out, s, illuminant, preset);
      return out;
    }
  }
  const SkinAppearance a = skin_appearance(p, grid, profile_solver(radii_of(req)), model);
  json out{{"spectrum", schema::spectrum_document(a.spectrum, preset)},
           {"profile", schema::rgb_profile_document(a.rgb, p, preset, std::string(model.name()),
                                                    skin_validity(p, grid, model))}};
  add_color(out, a.spectrum, illuminant, preset);
  return out;
}

// The dropped file is written to the module's in-memory file system under its own name and read
// by the CLI's reader (fit::read_spectrum), so messages and the "input" key name it as the CLI
// does when run in the file's folder.
std::string stored_file(const json& req) {
  std::string name = get_or<std::string>(req, "file", "spectrum.csv");
  if (const auto slash = name.find_last_of("/\\"); slash != std::string::npos) name = name.substr(slash + 1);
  if (name.empty()) name = "spectrum.csv";
  std::ofstream(name, std::ios::binary) << get_or<std::string>(req, "csv", "");
  return name;
}

Result fit_spectrum(const json& req) {
  fit::SpectrumFitOptions opt;
  opt.start = parameters_of(req);
  const std::string free = get_or<std::string>(req, "free", "");
  if (!free.empty()) opt.free = fit::parse_parameter_list(free);
  opt.includes_specular = get_or(req, "includes_specular", false);
  opt.lambda_min = get_or(req, "fit_lambda_min", 400.0);
  opt.lambda_max = get_or(req, "fit_lambda_max", 700.0);
  const transport::Model& model = model_of(req);
  opt.model = fit::forward_model(model);
  const fit::MeasuredSpectrum m = fit::read_spectrum(stored_file(req), get_or<std::string>(req, "column", ""));
  const fit::FitResult r = fit::SpectrumFitter(opt).fit(m);
  return schema::spectrum_fit_result(m, r, std::string(model.name()), opt.includes_specular);
}

// The reflectance columns of a CSV file (all but the first, the wavelength), for the page to
// offer a choice as --column does; and each one's samples.
// Each column is read and checked as `skin fit --spectrum FILE [--column NAME]` reads it (range
// 0-1, 450-650 nm covered, ...), so that a file the fit would refuse (a spectrum in percent) is
// refused when it is loaded, with the fit's message.
json spectra(const json& req) {
  const std::string name = stored_file(req);
  const Table t = read_csv_file(name);
  if (t.columns.size() < 2)
    throw InputError(name + ": expected a wavelength column and at least one reflectance column");
  for (std::size_t c = 1; c < t.columns.size(); ++c)
    (void)fit::read_spectrum(name, t.columns.size() == 2 ? "" : t.columns[c]);
  json j;
  j["file"] = name;
  j["wavelength_nm"] = t.data.empty() ? std::vector<double>{} : t.data[0];
  j["columns"] = json::array();
  for (std::size_t c = 1; c < t.columns.size(); ++c)
    j["columns"].push_back({{"name", t.columns[c]}, {"R", t.data[c]}});
  return j;
}

// Colours along the melanin axis for the other parameters of the request ("melanin": [...]).
json melanin_strip(const json& req) {
  const SkinParameters p = parameters_of(req);
  const WavelengthGrid grid = grid_of(req);
  const transport::Model& model = model_of(req);
  json out = json::array();
  for (double m : get_or<std::vector<double>>(req, "melanin", {})) {
    SkinParameters q = p;
    q.melanin = m;
    const SkinSpectrum s = skin_spectrum(q, grid, model);
    out.push_back({{"melanin", m}, {"color", schema::to_json(s.color)}});
  }
  return out;
}

// The model's colour over a grid of (melanin, melanin_blend, hemoglobin), the other parameters
// the request's: {"melanin": [...], "melanin_blend": [...], "hemoglobin": [...]} ->
// {"srgb_linear": [r, g, b, ...]}, melanin fastest, then melanin_blend, then hemoglobin. The
// view shades fitted parameter maps (`skin fit --texture`) by interpolating it, as the texture
// fit interpolates its own table (docs/parameter-maps.md). At most kMaxGridNodes nodes; every
// node is validated as the parameters are.
constexpr std::size_t kMaxGridNodes = 4096;
json color_grid(const json& req) {
  const SkinParameters base = parameters_of(req);
  const WavelengthGrid grid = grid_of(req);
  const transport::Model& model = model_of(req);
  const auto axis = [&](const char* key) {
    const auto v = get_or<std::vector<double>>(req, key, {});
    if (v.empty()) throw InputError(std::string(key) + ": expected a non-empty array of values");
    return v;
  };
  const auto m = axis("melanin"), b = axis("melanin_blend"), h = axis("hemoglobin");
  if (m.size() * b.size() * h.size() > kMaxGridNodes)
    throw InputError("color_grid: " + std::to_string(m.size() * b.size() * h.size()) +
                     " nodes is too many: at most " + std::to_string(kMaxGridNodes));
  std::vector<double> out;
  out.reserve(3 * m.size() * b.size() * h.size());
  for (double hk : h)
    for (double bk : b)
      for (double mk : m) {
        SkinParameters q = base;
        q.melanin = mk;
        q.melanin_blend = bk;
        q.hemoglobin = hk;
        try {
          q.validate();
        } catch (const InputError& e) {
          throw ParameterError(e.what(), invalid_keys(q, e.what()));
        }
        const auto c = skin_spectrum(q, grid, model).color.srgb_linear;
        out.insert(out.end(), {c.r, c.g, c.b});
      }
  return json{{"srgb_linear", out}};
}

// `skin export --target T` in a folder of its own, without -o: the files it writes (named as it
// names them: NAME.TARGET + the target's extension, NAME.TARGET + each file's suffix) with their
// text, and NAME.TARGET.fit.json. {"target", "files": [{"name", "content"}], "images": [name], "report"}: "report"
// is the fit report (the last file, parsed). Images (the profile target's .exr) are listed, as
// the report lists them, but not written: the module has no OpenEXR.
json export_files(const json& req) {
  const SkinParameters p = parameters_of(req);
  const transport::Model& model = model_of(req);
  const exporting::Target& target = exporting::find_target(get_or<std::string>(req, "target", ""));
  exporting::Options opt;
  if (const auto units = get_or<std::string>(req, "units", ""); !units.empty()) opt.unit = exporting::parse_unit(units);
  opt.world_scale = get_or(req, "world_scale", opt.world_scale);
  opt.name = get_or(req, "name", opt.name);
  opt.gaussians = get_or(req, "gaussians", opt.gaussians);
  opt.taps = get_or(req, "taps", opt.taps);
  opt.spectra_files = get_or(req, "spectra_files", opt.spectra_files);
  opt.stem = exporting::default_stem(target, opt.name);
  opt.validate();
  const exporting::Export e = exporting::export_skin(target.name, p, model, opt);
  json out{{"target", std::string(target.name)}, {"files", json::array()}, {"images", json::array()}};
  std::vector<std::string> written;
  for (const exporting::TextFile& f : e.files) {
    written.push_back(opt.stem + (f.suffix.empty() ? std::string(target.extension) : f.suffix));
    out["files"].push_back({{"name", written.back()}, {"content", f.content}});
  }
  for (const exporting::ImageFile& f : e.images) {
    written.push_back(opt.stem + f.suffix);
    out["images"].push_back(written.back());
  }
  written.push_back(opt.stem + ".fit.json");
  const json report = schema::fit_report_document(e.report, p, model.name(), written);
  out["files"].push_back({{"name", written.back()}, {"content", report.dump(2) + "\n"}});
  out["report"] = report;
  return out;
}

template <typename F>
std::string guarded(const std::string& request, const F& f) {
  try {
    const json req = request.empty() ? json::object() : json::parse(request);
    return f(req);
  } catch (const json::exception& e) {
    return json{{"error", std::string("request: not valid JSON (") + e.what() + ")"}}.dump();
  } catch (const ParameterError& e) {
    return json{{"error", e.what()}, {"parameters", e.keys}}.dump();
  } catch (const std::exception& e) {
    return json{{"error", e.what()}}.dump();
  }
}

std::string run(const std::string& command, const std::string& request) {
  return guarded(request, [&](const json& req) -> std::string {
    if (command == "spectrum") return write(spectrum(req), req);
    if (command == "color") return write(color(req), req);
    if (command == "profile") return write(profile(req), req);
    if (command == "fit") return write(fit_spectrum(req), req);
    if (command == "parameters") return write(schema::parameters_result(), req);
    if (command == "presets") return write(schema::presets_result(), req);
    if (command == "update") return update(req).dump();
    if (command == "spectra") return spectra(req).dump();
    if (command == "melanin_strip") return melanin_strip(req).dump();
    if (command == "color_grid") return color_grid(req).dump();
    if (command == "export") return export_files(req).dump();
    // The fit's thresholds the page warns at, from the library (one home for each number).
    if (command == "fit_limits") return json{{"good_fit_rms", fit::kGoodFitRms}}.dump();
    if (command == "targets") {
      json j = json::array();
      for (const exporting::Target& t : exporting::targets())
        j.push_back({{"name", std::string(t.name)}, {"description", std::string(t.description)},
                     {"extension", std::string(t.extension)}});
      return j.dump();
    }
    if (command == "illuminants") {
      json j = json::array();
      // "light_srgb_linear": the illuminant as a light in an RGB renderer whose white is D65
      // (luminance 1), as `skin render` lights a scene with it (the page's 3D view).
      for (const auto& n : color::illuminant_names()) {
        const Rgb light = color::Colorimetry(WavelengthGrid(), color::find_illuminant(n)).illuminant_rgb();
        j.push_back({{"name", n}, {"description", color::find_illuminant(n).description()},
                     {"default", n == color::kDefaultIlluminant},
                     {"light_srgb_linear", {light.r, light.g, light.b}}});
      }
      return j.dump();
    }
    if (command == "solvers") {
      json j = json::array();
      for (const auto& n : transport::model_names())
        j.push_back({{"name", n}, {"description", std::string(transport::find_model(n).description())},
                     {"default", n == transport::kDefaultModel}});
      return j.dump();
    }
    throw InputError("command '" + command + "' is unknown: allowed values are spectrum, color, "
                     "profile, fit, parameters, presets, update, spectra, melanin_strip, color_grid, solvers, "
                     "illuminants, export, targets, fit_limits");
  });
}

}  // namespace
}  // namespace skin::web

EMSCRIPTEN_BINDINGS(skin_web) { emscripten::function("run", &skin::web::run); }
