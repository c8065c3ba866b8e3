#include "common.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::cli {

bool stdout_is_terminal() { return ::isatty(STDOUT_FILENO) != 0; }
bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) != 0; }

void ParameterOptions::add_to(CLI::App& app) {
  std::string names;
  for (const auto& p : presets()) names += (names.empty() ? "" : ", ") + p.name;
  app.add_option("--preset", preset,
                 "Parameter set of the paper: " + names + " (several-lights = ear)")
      ->capture_default_str();
  struct Flag {
    const char* name;
    double SkinParameters::*member;
    const char* help;
  };
  static const Flag table[] = {
      {"--melanin", &SkinParameters::melanin, "C_m: melanin volume fraction of the epidermis, [0, 1]"},
      {"--melanin-blend", &SkinParameters::melanin_blend, "beta_m: eumelanin share of the melanin, [0, 1]"},
      {"--hemoglobin", &SkinParameters::hemoglobin, "C_h: blood volume fraction of the dermis, [0, 1]"},
      {"--oiliness", &SkinParameters::oiliness, "rho_s: scale of the specular lobe, [0, 1]"},
      {"--oxygenation", &SkinParameters::oxygenation, "gamma: oxygenated share of hemoglobin, [0, 1]; default 0.75"},
      {"--epidermis-thickness", &SkinParameters::epidermis_thickness, "Epidermis thickness [mm], > 0; default 0.25"},
      {"--dermis-scattering-scale", &SkinParameters::dermis_scattering_scale, "Dermis sigma_s' relative to the epidermis', > 0; default 0.5"},
      {"--eta", &SkinParameters::eta, "Refractive index of both layers, [1, 3]; default 1.4"},
      {"--roughness", &SkinParameters::roughness, "Beckmann RMS slope of the surface, > 0; default 0.35"},
      {"--g", &SkinParameters::g, "Henyey-Greenstein anisotropy for transport solvers, (-1, 1); default 0.9"},
      {"--epidermal-hemoglobin", &SkinParameters::epidermal_hemoglobin, "Extended model: blood volume fraction of the epidermis, [0, 1]; default 0"},
      {"--beta-carotene", &SkinParameters::beta_carotene, "Extended model: beta-carotene in the epidermis [umol/L], [0, 1000]; default 0"},
      {"--bilirubin", &SkinParameters::bilirubin, "Extended model: bilirubin in the dermis [umol/L], [0, 1000]; default 0"},
      {"--scattering-scale", &SkinParameters::scattering_scale, "Extended model: factor on sigma_s' of both layers, (0, 10]; default 1"},
  };
  for (const auto& f : table) {
    CLI::Option* o = app.add_option(f.name, values.*(f.member), f.help);
    o->group("Skin parameters (override the preset)");
    flags.emplace_back(o, f.member);
  }
}

SkinParameters ParameterOptions::resolve() const {
  SkinParameters p = find_preset(preset).parameters;
  for (const auto& [opt, member] : flags)
    if (opt->count() > 0) p.*member = values.*member;
  p.validate();
  return p;
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

void warn_validity(const transport::Model& model, const transport::Validity& v,
                   const std::string& what) {
  if (v.ok()) return;
  std::cerr << "skin: warning: solver " << model.name() << (what.empty() ? "" : " for " + what)
            << ": "
            << (v.totals ? "profile" : v.profile ? "totals" : "totals and profile")
            << " outside its validated range: " << v.reason;
  if (!v.exact.empty()) std::cerr << "; still exact: " << v.exact;
  std::cerr << '\n';
}

json to_json(const transport::Validity& v) {
  json j;
  j["totals"] = v.totals;
  j["profile"] = v.profile;
  if (!v.ok()) j["reason"] = v.reason;
  return j;
}

void GridOptions::add_to(CLI::App& app) {
  app.add_option("--lambda-min", lambda_min, "Shortest wavelength [nm]")->capture_default_str()->group("Wavelengths");
  app.add_option("--lambda-max", lambda_max, "Longest wavelength [nm]")->capture_default_str()->group("Wavelengths");
  app.add_option("--lambda-step", lambda_step, "Wavelength step [nm]; (max - min) / step must be whole")->capture_default_str()->group("Wavelengths");
}

void OutputOptions::add_to(CLI::App& app, bool with_table) {
  app.add_option("--format", format,
                 with_table ? "Output format: table (default on a terminal), csv, json (default when piped)"
                            : "Output format: csv, json (default)")
      ->check(with_table ? CLI::IsMember({"table", "csv", "json"}) : CLI::IsMember({"csv", "json"}))
      ->group("Output");
  app.add_option("-o,--output", output, "Write to FILE (atomically: complete or not at all) instead of stdout")
      ->group("Output");
}

Format OutputOptions::resolve() const {
  if (format == "table") return Format::table;
  if (format == "csv") return Format::csv;
  if (format == "json") return Format::json;
  return (output.empty() && stdout_is_terminal()) ? Format::table : Format::json;
}

void OutputOptions::emit(const std::string& text) const {
  if (output.empty()) {
    std::cout << text;
    std::cout.flush();
  } else {
    io::write_file_atomic(output, text);
  }
}

namespace {
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}
}  // namespace

std::string format_table(const std::vector<std::string>& header,
                         const std::vector<std::vector<double>>& columns) {
  std::ostringstream os;
  std::vector<std::size_t> width(header.size());
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = std::max<std::size_t>(header[c].size(), 12);
  }
  for (std::size_t c = 0; c < header.size(); ++c)
    os << (c ? "  " : "") << std::string(width[c] - header[c].size(), ' ') << header[c];
  os << '\n';
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < header.size(); ++c) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.6g", columns[c][r]);
      const std::string s = buf;
      os << (c ? "  " : "") << std::string(width[c] > s.size() ? width[c] - s.size() : 0, ' ') << s;
    }
    os << '\n';
  }
  return os.str();
}

std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns) {
  std::ostringstream os;
  for (std::size_t c = 0; c < header.size(); ++c) os << (c ? "," : "") << header[c];
  os << '\n';
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) os << (c ? "," : "") << num(columns[c][r]);
    os << '\n';
  }
  return os.str();
}

json to_json(const SkinParameters& p) {
  json j;
  j["melanin"] = p.melanin;
  j["melanin_blend"] = p.melanin_blend;
  j["hemoglobin"] = p.hemoglobin;
  j["oiliness"] = p.oiliness;
  j["oxygenation"] = p.oxygenation;
  j["epidermis_thickness"] = p.epidermis_thickness;
  j["dermis_scattering_scale"] = p.dermis_scattering_scale;
  j["eta"] = p.eta;
  j["roughness"] = p.roughness;
  j["g"] = p.g;
  j["epidermal_hemoglobin"] = p.epidermal_hemoglobin;
  j["beta_carotene"] = p.beta_carotene;
  j["bilirubin"] = p.bilirubin;
  j["scattering_scale"] = p.scattering_scale;
  return j;
}

json to_json(const color::ColorSummary& c) {
  json j;
  j["XYZ"] = {c.XYZ.X, c.XYZ.Y, c.XYZ.Z};
  j["srgb_linear"] = {c.srgb_linear.r, c.srgb_linear.g, c.srgb_linear.b};
  j["srgb8"] = {c.srgb8[0], c.srgb8[1], c.srgb8[2]};
  j["hex"] = c.hex;
  j["lab"] = {c.lab.L, c.lab.a, c.lab.b};
  return j;
}

std::string color_table(const color::ColorSummary& c) {
  std::ostringstream os;
  os << "XYZ (D65, Y_white = 1)  " << num(c.XYZ.X) << "  " << num(c.XYZ.Y) << "  " << num(c.XYZ.Z) << '\n'
     << "linear sRGB             " << num(c.srgb_linear.r) << "  " << num(c.srgb_linear.g) << "  "
     << num(c.srgb_linear.b) << '\n'
     << "sRGB 8-bit              " << c.srgb8[0] << " " << c.srgb8[1] << " " << c.srgb8[2] << '\n'
     << "hex                     " << c.hex << '\n'
     << "CIELAB                  " << num(c.lab.L) << "  " << num(c.lab.a) << "  " << num(c.lab.b) << '\n';
  return os.str();
}

std::vector<double> to_vector(const Spectrum& s) { return s.values; }

Layer parse_layer(const std::string& spec, std::size_t index) {
  const std::string where = "--layer " + std::to_string(index + 1) + " '" + spec + "'";
  const std::string keys = "keys: sigma_a, sigma_s_prime, thickness, eta, g";
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
    else if (key == "thickness") {
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
