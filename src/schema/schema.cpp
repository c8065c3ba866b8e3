#include "schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "skin/util/error.hpp"
#include "skin/util/escape.hpp"
#include "skin/util/input_file.hpp"

namespace skin::schema {

using skin::util::InputError;
using skin::util::Rgb;
using skin::util::format_number;

using skin::transport::DiffusionSlab;
using skin::transport::DiffusionStack;
using skin::transport::RadialGrid;
using skin::transport::RgbProfile;
using skin::transport::SpectralProfile;

using skin::model::SkinSpectrum;
using skin::model::skin_spectrum;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::ParameterInfo;
using skin::physics::ParameterNames;
using skin::physics::Preset;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::outside_skin_domain;
using skin::physics::parameter_table;
using skin::physics::presets;

Column constant_column(std::string name, double value, std::size_t rows) {
  return Column{std::move(name), std::vector<double>(std::max<std::size_t>(rows, 1), value), {}};
}

namespace {
using util::escape::csv_field;
// Numbers of CSV files: ten significant digits.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}
}  // namespace

std::string csv_header(const std::vector<Column>& columns) {
  std::string out;
  for (std::size_t c = 0; c < columns.size(); ++c) out += (c ? "," : "") + csv_field(columns[c].name);
  return out + '\n';
}

std::string csv_rows(const std::vector<Column>& columns) {
  std::string out;
  std::size_t rows = 0;
  for (const Column& col : columns) rows = std::max(rows, col.rows());
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const Column& col = columns[c];
      if (c) out += ',';
      if (r < col.numbers.size()) out += num(col.numbers[r]);
      else if (r < col.text.size()) out += csv_field(col.text[r]);
    }
    out += '\n';
  }
  return out;
}

std::string to_csv(const std::vector<Column>& columns) { return csv_header(columns) + csv_rows(columns); }

std::string columns_table(const std::vector<Column>& columns) {
  std::vector<std::vector<std::string>> rows(1);
  std::size_t n = 0;
  for (const auto& c : columns) {
    rows[0].push_back(c.name);
    n = std::max(n, c.rows());
  }
  for (std::size_t r = 0; r < n; ++r) {
    rows.emplace_back();
    for (const auto& c : columns) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.6g", r < c.numbers.size() ? c.numbers[r] : 0.0);
      rows.back().push_back(r < c.numbers.size() ? buf : r < c.text.size() ? c.text[r] : "");
    }
  }
  return format_text_table(rows);
}

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

std::string format_text_table(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (width.size() <= c) width.push_back(0);
      width[c] = std::max(width[c], row[c].size());
    }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c)
      line += row[c] + (c + 1 < row.size() ? std::string(width[c] - row[c].size() + 2, ' ') : "");
    out += line + "\n";
  }
  return out;
}

std::string format_fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

void append_rows(std::vector<Column>& to, const std::vector<Column>& more) {
  if (to.empty()) {
    to = more;
    return;
  }
  for (std::size_t k = 0; k < more.size(); ++k) {
    to[k].numbers.insert(to[k].numbers.end(), more[k].numbers.begin(), more[k].numbers.end());
    to[k].text.insert(to[k].text.end(), more[k].text.begin(), more[k].text.end());
  }
}

std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns) {
  std::ostringstream os;
  for (std::size_t c = 0; c < header.size(); ++c) os << (c ? "," : "") << csv_field(header[c]);
  os << '\n';
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) os << (c ? "," : "") << num(columns[c][r]);
    os << '\n';
  }
  return os.str();
}

json to_json(const SkinParameters& p) {
  json j = json::object();
  for (const ParameterInfo& info : parameter_table()) j[std::string(info.key)] = p.*(info.member);
  return j;
}

json to_json(const Layer& l) {
  json j;
  j["sigma_a"] = l.sigma_a;
  j["sigma_s_prime"] = l.sigma_s_prime;
  j["thickness_mm"] = l.semi_infinite() ? json(nullptr) : json(l.thickness);
  j["eta"] = l.eta;
  j["g"] = l.g;
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

json to_json(const transport::Validity& v) {
  json j;
  j["totals"] = v.totals;
  j["profile"] = v.profile;
  if (!v.ok()) j["reason"] = v.reason;
  return j;
}

std::vector<Column> color_columns(const color::ColorSummary& c) {
  return {{"XYZ.X", {c.XYZ.X}, {}},
          {"XYZ.Y", {c.XYZ.Y}, {}},
          {"XYZ.Z", {c.XYZ.Z}, {}},
          {"srgb_linear.r", {c.srgb_linear.r}, {}},
          {"srgb_linear.g", {c.srgb_linear.g}, {}},
          {"srgb_linear.b", {c.srgb_linear.b}, {}},
          {"srgb8.r", {double(c.srgb8[0])}, {}},
          {"srgb8.g", {double(c.srgb8[1])}, {}},
          {"srgb8.b", {double(c.srgb8[2])}, {}},
          {"hex", {}, {c.hex}},
          {"lab.L", {c.lab.L}, {}},
          {"lab.a", {c.lab.a}, {}},
          {"lab.b", {c.lab.b}, {}}};
}

std::string color_table(const color::ColorSummary& c) {
  std::ostringstream os;
  std::string xyz = "XYZ (" + c.illuminant + ", Y_white = 1)";
  xyz += std::string(xyz.size() < 22 ? 24 - xyz.size() : 2, ' ');
  os << xyz << num(c.XYZ.X) << "  " << num(c.XYZ.Y) << "  " << num(c.XYZ.Z) << '\n'
     << "linear sRGB             " << num(c.srgb_linear.r) << "  " << num(c.srgb_linear.g) << "  "
     << num(c.srgb_linear.b) << '\n'
     << "sRGB 8-bit              " << c.srgb8[0] << " " << c.srgb8[1] << " " << c.srgb8[2] << '\n'
     << "hex                     " << c.hex << '\n'
     << "CIELAB                  " << num(c.lab.L) << "  " << num(c.lab.a) << "  " << num(c.lab.b) << '\n';
  if (c.illuminant != color::kSrgbWhite)
    os << "sRGB and hex after the Bradford adaptation " << c.illuminant << " -> D65; CIELAB relative to "
       << c.illuminant << "'s white\n";
  return os.str();
}

ParameterFile ParameterFile::read(const std::string& path) {
  const std::string where = "params = '" + path + "': ";
  const std::string text = util::io::read_file(path, "params");
  json doc;
  try {
    doc = json::parse(text);
  } catch (const std::exception& e) {
    throw InputError(where + "not valid JSON (" + e.what() + ")");
  }
  return parse(doc, where);
}

ParameterFile ParameterFile::parse(const json& doc, const std::string& where) {
  // Messages of the checks below, with the file in front.
  const auto in_file = [&where](const auto& check) {
    try {
      return check();
    } catch (const InputError& e) {
      throw InputError(where + e.what());
    }
  };
  const bool nested = doc.is_object() && doc.contains("parameters");
  const json& obj = nested ? doc["parameters"] : doc;
  if (!obj.is_object())
    throw InputError(where + "expected an object of parameter keys (or a \"parameters\" object)");
  ParameterFile file;
  ParameterNames names(where + "key");
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (!nested && it.key() == "preset") {
      if (!it->is_string()) throw InputError(where + "\"preset\" must be a string");
      file.preset = it->get<std::string>();
      in_file([&] { return &find_preset(file.preset); });
      continue;
    }
    const ParameterInfo* info = &names.add(it.key());
    if (it->is_null()) continue;
    if (!it->is_number() || it->is_boolean())
      throw InputError(where + std::string(info->key) + " must be a number, not " + it->dump());
    const double v = it->get<double>();
    in_file([&] { info->check(v); return 0; });
    file.values.emplace_back(info, v);
  }
  return file;
}

bool ParameterFile::sets(const ParameterInfo* info) const {
  return std::any_of(values.begin(), values.end(), [info](const auto& v) { return v.first == info; });
}

void ParameterFile::apply(SkinParameters& p) const {
  if (!preset.empty()) p = find_preset(preset).parameters;
  for (const auto& [info, v] : values) p.*(info->member) = v;
}

json spectrum_document(const SkinSpectrum& s, const std::string& preset) {
  json j;
  j["preset"] = preset;
  j["parameters"] = to_json(s.parameters);
  j["solver"] = s.solver;
  j["units"] = {{"wavelength_nm", "nm"}, {"sigma_a", "1/mm"}, {"sigma_s_prime", "1/mm"}, {"R_d", "1"}};
  j["wavelength_nm"] = s.grid.values();
  j["R_d"] = s.R_d.values;
  j["epidermis"] = {{"sigma_a", s.epidermis_sigma_a.values},
                    {"sigma_s_prime", s.epidermis_sigma_s_prime.values},
                    {"thickness_mm", s.parameters.epidermis_thickness}};
  j["dermis"] = {{"sigma_a", s.dermis_sigma_a.values},
                 {"sigma_s_prime", s.dermis_sigma_s_prime.values}};
  j["color"] = to_json(s.color);
  return j;
}

Result spectrum_result(const SkinSpectrum& s, const std::string& preset) {
  Result result;
  result.document = spectrum_document(s, preset);
  const std::vector<std::string> header = {"wavelength_nm", "R_d", "epidermis.sigma_a",
                                           "epidermis.sigma_s_prime", "dermis.sigma_a",
                                           "dermis.sigma_s_prime"};
  const std::vector<std::vector<double>> cols = {s.grid.values(), s.R_d.values,
                                                 s.epidermis_sigma_a.values,
                                                 s.epidermis_sigma_s_prime.values,
                                                 s.dermis_sigma_a.values,
                                                 s.dermis_sigma_s_prime.values};
  for (std::size_t c = 0; c < header.size(); ++c)
    result.columns.push_back({header[c] + (c >= 2 ? " [1/mm]" : ""), cols[c], {}});
  result.table = format_table(header, cols) + "\n" + color_table(s.color);
  return result;
}

json color_document(const SkinSpectrum& s, const std::string& preset, const color::ColorSummary& c) {
  json j;
  j["preset"] = preset;
  j["parameters"] = to_json(s.parameters);
  j["solver"] = s.solver;
  j["illuminant"] = c.illuminant;
  j["color"] = to_json(c);
  return j;
}

Result color_result(const SkinSpectrum& s, const std::string& preset, const color::ColorSummary& c) {
  Result result;
  result.document = color_document(s, preset, c);
  result.columns = color_columns(c);
  result.table = color_table(c);
  return result;
}

namespace {
// What both profiles' documents begin with.
json profile_document(const SkinParameters& p, const std::string& preset, const std::string& solver,
                      const transport::Validity& validity) {
  json j;
  j["preset"] = preset;
  j["parameters"] = to_json(p);
  j["solver"] = solver;
  j["validity"] = to_json(validity);
  // Whether the parameters lie in the skin domain (the range the models are validated over:
  // skin parameters), and which do not.
  const std::vector<std::string> outside = outside_skin_domain(p);
  j["validity"]["skin_domain"] = outside.empty();
  if (!outside.empty()) j["validity"]["outside_skin_domain"] = outside;
  return j;
}
}  // namespace

json rgb_profile_document(const RgbProfile& rgb, const SkinParameters& p, const std::string& preset,
                          const std::string& solver, const transport::Validity& validity) {
  json j = profile_document(p, preset, solver, validity);
  j["units"] = {{"r_mm", "mm"}, {"R", "1/mm^2"}};
  j["r_mm"] = rgb.radii.r;
  j["R"] = {{"r", rgb.R[0]}, {"g", rgb.R[1]}, {"b", rgb.R[2]}};
  j["R_d"] = {{"r", rgb.R_d[0]}, {"g", rgb.R_d[1]}, {"b", rgb.R_d[2]}};
  return j;
}

Result rgb_profile_result(const RgbProfile& rgb, const SkinParameters& p, const std::string& preset,
                          const std::string& solver, const transport::Validity& validity) {
  const char* names[3] = {"r", "g", "b"};
  const RadialGrid& radii = rgb.radii;
  Result result;
  result.document = rgb_profile_document(rgb, p, preset, solver, validity);
  result.columns = {{"r_mm", radii.r, {}}};
  for (int c = 0; c < 3; ++c) result.columns.push_back({std::string("R.") + names[c] + " [1/mm^2]", rgb.R[c], {}});
  for (int c = 0; c < 3; ++c) result.columns.push_back(constant_column(std::string("R_d.") + names[c], rgb.R_d[c], radii.size()));
  result.table = format_table({"r_mm", "R_r", "R_g", "R_b"}, {radii.r, rgb.R[0], rgb.R[1], rgb.R[2]});
  return result;
}

namespace {
// The profile at each wavelength: R[i_lambda][j_r].
std::vector<std::vector<double>> profile_rows(const SpectralProfile& sp) {
  std::vector<std::vector<double>> rows(sp.grid.size());
  for (std::size_t i = 0; i < sp.grid.size(); ++i)
    rows[i].assign(sp.R.begin() + static_cast<std::ptrdiff_t>(i * sp.radii.size()),
                   sp.R.begin() + static_cast<std::ptrdiff_t>((i + 1) * sp.radii.size()));
  return rows;
}
}  // namespace

json spectral_profile_document(const SpectralProfile& sp, const SkinParameters& p, const std::string& preset,
                               const std::string& solver, const transport::Validity& validity) {
  json j = profile_document(p, preset, solver, validity);
  j["units"] = {{"r_mm", "mm"}, {"wavelength_nm", "nm"}, {"R", "1/mm^2"}};
  j["r_mm"] = sp.radii.r;
  j["wavelength_nm"] = sp.grid.values();
  j["R_d"] = sp.R_d.values;
  j["R"] = profile_rows(sp);  // R[i_lambda][j_r]
  return j;
}

Result spectral_profile_result(const SpectralProfile& sp, const SkinParameters& p,
                               const std::string& preset, const std::string& solver,
                               const transport::Validity& validity) {
  const WavelengthGrid& grid = sp.grid;
  const RadialGrid& radii = sp.radii;
  const std::vector<std::vector<double>> rows = profile_rows(sp);
  Result result;
  result.document = spectral_profile_document(sp, p, preset, solver, validity);
  std::vector<std::string> h = {"r_mm"};
  std::vector<std::vector<double>> cols = {radii.r};
  result.columns = {{"r_mm", radii.r, {}}};
  for (std::size_t i = 0; i < grid.size(); ++i) {
    h.push_back("R_" + format_number(grid[i]) + "nm");
    cols.push_back(rows[i]);
    result.columns.push_back({h.back() + " [1/mm^2]", rows[i], {}});
  }
  result.table = format_table(h, cols);
  return result;
}

namespace {
json bound(double v) { return std::isinf(v) ? json(nullptr) : json(v); }
}  // namespace

Result parameters_result() {
  Result result;
  result.document = json::array();
  std::vector<Column> cols = {{"key", {}, {}},      {"flag", {}, {}},    {"symbol", {}, {}},
                              {"unit", {}, {}},     {"min", {}, {}},     {"max", {}, {}},
                              {"min_exclusive", {}, {}}, {"max_exclusive", {}, {}},
                              {"default", {}, {}},  {"skin_domain.min", {}, {}},
                              {"skin_domain.max", {}, {}}, {"help", {}, {}}};
  std::vector<std::vector<std::string>> rows = {
      {"key", "symbol", "unit", "range", "skin domain", "default", "help"}};
  for (const auto& p : parameter_table()) {
    result.document.push_back({{"key", p.key},
                               {"flag", "--" + p.flag()},
                               {"symbol", p.symbol.empty() ? json(nullptr) : json(p.symbol)},
                               {"unit", p.unit},
                               {"min", bound(p.min)},
                               {"max", bound(p.max)},
                               {"min_exclusive", p.min_open},
                               {"max_exclusive", p.max_open},
                               {"default", p.default_value()},
                               {"skin_domain", {{"min", p.domain_min}, {"max", p.domain_max}}},
                               {"help", p.help}});
    const std::string text[] = {std::string(p.key), "--" + p.flag(), std::string(p.symbol),
                                std::string(p.unit), format_number(p.min), format_number(p.max),
                                p.min_open ? "true" : "false", p.max_open ? "true" : "false",
                                format_number(p.default_value()), format_number(p.domain_min),
                                format_number(p.domain_max), std::string(p.help)};
    for (std::size_t c = 0; c < cols.size(); ++c) cols[c].text.push_back(text[c]);
    rows.push_back({std::string(p.key), std::string(p.symbol), std::string(p.unit),
                    p.range_text(), p.domain_text(), format_number(p.default_value()),
                    std::string(p.help)});
  }
  result.columns = cols;
  result.table = format_text_table(rows);
  return result;
}

Result presets_result() {
  // Every preset's colour under D65 with the default solver (the exact one), as `skin color
  // --preset NAME` prints it: what the preset looks like under exact transport. Computed once.
  static const std::vector<color::ColorSummary> colors = [] {
    std::vector<color::ColorSummary> out;
    for (const auto& p : presets())
      out.push_back(skin_spectrum(p.parameters, WavelengthGrid{}, transport::default_model()).color);
    return out;
  }();
  Result result;
  result.document = json::array();
  Column name{"name", {}, {}}, description{"description", {}, {}}, source{"source", {}, {}},
      target{"target_hex", {}, {}}, hex{"hex", {}, {}};
  Column L{"lab_L", {}, {}}, a{"lab_a", {}, {}}, b{"lab_b", {}, {}};
  std::vector<Column> values;
  for (const ParameterInfo& info : parameter_table()) values.push_back({std::string(info.key), {}, {}});
  std::vector<std::vector<std::string>> rows{{"name", "hex", "L*", "a*", "b*", "description"}};
  for (std::size_t k = 0; k < presets().size(); ++k) {
    const Preset& p = presets()[k];
    const color::ColorSummary& c = colors[k];
    json doc = {{"name", p.name}, {"description", p.description}, {"source", p.source}};
    if (!p.target_hex.empty()) doc["target_hex"] = p.target_hex;
    doc["color"] = {{"solver", std::string(transport::default_model().name())},
                    {"illuminant", c.illuminant},
                    {"hex", c.hex},
                    {"lab", {c.lab.L, c.lab.a, c.lab.b}}};
    doc["parameters"] = to_json(p.parameters);
    result.document.push_back(std::move(doc));
    rows.push_back({p.name, c.hex, format_fixed(c.lab.L, 1), format_fixed(c.lab.a, 1), format_fixed(c.lab.b, 1),
                    p.description});
    name.text.push_back(p.name);
    description.text.push_back(p.description);
    source.text.push_back(p.source);
    target.text.push_back(p.target_hex);
    hex.text.push_back(c.hex);
    L.numbers.push_back(c.lab.L);
    a.numbers.push_back(c.lab.a);
    b.numbers.push_back(c.lab.b);
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i].numbers.push_back(p.parameters.*(parameter_table()[i].member));
  }
  result.table = format_text_table(rows);
  result.columns = {name, description, source, target, hex, L, a, b};
  result.columns.insert(result.columns.end(), values.begin(), values.end());
  return result;
}

Result layers_result(const LayerStack& stack, const DiffusionStack& diffusion, const std::string& solver,
                     const transport::Totals& totals, const std::vector<double>& r_mm,
                     const std::vector<double>& R, const transport::Validity& validity) {
  Result result;
  json& j = result.document;
  j["solver"] = solver;
  j["eta_above"] = stack.eta_above;
  j["eta_below"] = stack.eta_below;
  json layers = json::array();
  for (std::size_t i = 0; i < stack.layers.size(); ++i) {
    const DiffusionSlab& s = diffusion.slabs()[i];
    json jl = to_json(stack.layers[i]);
    jl["alpha_prime"] = s.alpha_prime;
    jl["sigma_tr"] = s.sigma_tr;
    jl["z_r"] = s.z_r;
    jl["z_b_top"] = s.z_b_top;
    jl["z_b_bottom"] = s.z_b_bottom;
    jl["A_top"] = s.A_top;
    jl["A_bottom"] = s.A_bottom;
    layers.push_back(jl);
  }
  j["layers"] = layers;
  j["R_specular"] = totals.R_specular;
  j["R_d"] = totals.R_d;
  j["T_d"] = totals.T_d;
  j["profile"] = {{"r_mm", r_mm}, {"R", R}};
  j["validity"] = to_json(validity);
  if (!r_mm.empty()) result.columns = {{"r_mm", r_mm, {}}, {"R [1/mm^2]", R, {}}};
  result.columns.push_back(constant_column("R_d", totals.R_d, r_mm.size()));
  result.columns.push_back(constant_column("T_d", totals.T_d, r_mm.size()));
  result.columns.push_back(constant_column("R_specular", totals.R_specular, r_mm.size()));
  result.table = "R_d  " + format_number(totals.R_d) + "\nT_d  " + format_number(totals.T_d) + "\n";
  if (!r_mm.empty()) result.table += "\n" + format_table({"r_mm", "R [1/mm^2]"}, {r_mm, R});
  return result;
}

Result illuminants_result() {
  const WavelengthGrid cie_grid(380, 780, 5);
  Result result;
  result.document = json::array();
  Column name{"name", {}, {}}, x{"x", {}, {}}, y{"y", {}, {}}, r{"light_srgb_linear.r", {}, {}},
      g{"light_srgb_linear.g", {}, {}}, b{"light_srgb_linear.b", {}, {}}, description{"description", {}, {}};
  std::vector<std::vector<std::string>> rows{{"name", "x", "y", "light (linear sRGB)", "description"}};
  for (const std::string& n : color::illuminant_names()) {
    const color::Illuminant& il = color::find_illuminant(n);
    const color::Colorimetry cm(cie_grid, il);
    const color::Xyz w = cm.white();
    const double sum = w.X + w.Y + w.Z;
    const Rgb light = cm.illuminant_rgb();
    result.document.push_back({{"name", n},
                               {"description", il.description()},
                               {"x", w.X / sum},
                               {"y", w.Y / sum},
                               {"white_XYZ", {w.X, w.Y, w.Z}},
                               {"light_srgb_linear", {light.r, light.g, light.b}}});
    name.text.push_back(n);
    description.text.push_back(il.description());
    x.numbers.push_back(w.X / sum);
    y.numbers.push_back(w.Y / sum);
    r.numbers.push_back(light.r);
    g.numbers.push_back(light.g);
    b.numbers.push_back(light.b);
    rows.push_back({n, format_fixed(w.X / sum, 5), format_fixed(w.Y / sum, 5),
                    format_fixed(light.r, 3) + " " + format_fixed(light.g, 3) + " " + format_fixed(light.b, 3),
                    il.description()});
  }
  result.columns = {name, x, y, r, g, b, description};
  result.table = format_text_table(rows) +
                 "x, y: CIE 1931 2-degree, 5 nm 380-780 nm. light: the illuminant's colour in the "
                 "white-balanced linear sRGB of an RGB renderer (Y = 1; D65 = 1 1 1)\n";
  return result;
}

Result illuminant_comparison_result(const IlluminantComparison& comparison) {
  const std::vector<std::string>& names = comparison.illuminants;
  Result result;
  result.document["solver"] = comparison.solver;
  result.document["method"] =
      "uniformly lit half-space; spectral: XYZ of R_d times the illuminant; rgb_rendering: the "
      "skin's white-balanced linear sRGB under D65 times the illuminant's light colour; both "
      "CIELAB relative to the illuminant's white; delta_e_2000 between them";
  result.document["illuminants"] = names;
  json& colors = result.document["colors"] = json::array();
  Column preset_col{"preset", {}, {}}, illum_col{"illuminant", {}, {}}, hex{"hex", {}, {}},
      hex_rgb{"rgb_rendering.hex", {}, {}}, dE{"delta_e_2000", {}, {}};
  std::vector<Column> lab(6);
  const char* lab_names[6] = {"lab.L", "lab.a", "lab.b", "rgb_rendering.lab.L", "rgb_rendering.lab.a",
                              "rgb_rendering.lab.b"};
  for (std::size_t k = 0; k < 6; ++k) lab[k].name = lab_names[k];
  std::vector<std::string> header{"delta_e_2000"};
  header.insert(header.end(), names.begin(), names.end());
  std::vector<std::vector<std::string>> table{header};
  for (const IlluminantComparison::Row& row : comparison.rows) {
    std::vector<std::string> line{row.preset};
    for (std::size_t j = 0; j < names.size(); ++j) {
      const color::RgbVsSpectral& c = row.colors[j];
      colors.push_back({{"preset", row.preset},
                        {"illuminant", names[j]},
                        {"color", to_json(c.spectral)},
                        {"rgb_rendering", to_json(c.rgb)},
                        {"delta_e_2000", c.delta_e_2000}});
      preset_col.text.push_back(row.preset);
      illum_col.text.push_back(names[j]);
      hex.text.push_back(c.spectral.hex);
      hex_rgb.text.push_back(c.rgb.hex);
      const color::Lab* labs[2] = {&c.spectral.lab, &c.rgb.lab};
      for (std::size_t k = 0; k < 6; ++k) {
        const color::Lab& l = *labs[k / 3];
        lab[k].numbers.push_back(k % 3 == 0 ? l.L : (k % 3 == 1 ? l.a : l.b));
      }
      dE.numbers.push_back(c.delta_e_2000);
      line.push_back(format_fixed(c.delta_e_2000, 2));
    }
    table.push_back(line);
  }
  result.columns = {preset_col, illum_col, hex, hex_rgb};
  result.columns.insert(result.columns.end(), lab.begin(), lab.end());
  result.columns.push_back(dE);
  result.table = format_text_table(table);
  return result;
}

}  // namespace skin::schema
