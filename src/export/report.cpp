// The shared report writer and number formatting (report.hpp), and the fit report's rounding
// (export.hpp: report_number, report_error).
#include "report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "skin/util/charconv.hpp"
#include "skin/util/escape.hpp"

namespace skin::exporting {

using skin::util::Rgb;

using skin::physics::SkinParameters;

namespace detail {

std::string json_text(const std::string& text, std::string_view what) {
  util::escape::require_utf8(text, what);
  return text;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
double rounded(double v) {
  if (!std::isfinite(v)) return v;
  const std::string t = num(v);
  double r = v;
  skin::util::from_chars(t.data(), t.data() + t.size(), r);
  return r + 0.0;  // no -0
}
double rounded_error(double v) { return std::isfinite(v) ? std::round(v * 1e6) / 1e6 + 0.0 : v; }
json rounded(json j) {
  if (j.is_number_float()) return rounded(j.get<double>());
  if (j.is_structured())
    for (auto& v : j) v = rounded(std::move(v));
  return j;
}
std::string triple(const Rgb& c, const char* sep) {
  return num(c.r) + sep + num(c.g) + sep + num(c.b);
}

std::vector<double> vec(const Rgb& c) { return {c.r, c.g, c.b}; }

FitReport fit_report(const Context& ctx, std::string target_model, const Rgb& R_d_target,
                     const std::array<std::vector<double>, 3>& R_target) {
  const Reference& ref = ctx.ref;
  FitReport r;
  r.target = std::string(ctx.target.name);
  r.target_model = std::move(target_model);
  r.unit = ctx.unit;
  r.R_d_ours = ref.R_d;
  r.R_d_target = R_d_target;
  r.delta_e_2000 = delta_e(ref.R_d, R_d_target);
  for (int c = 0; c < 3; ++c) {
    r.mean_radius_mm[c] = ref.mean_radius[c];
    r.profile_l1[c] = relative_l1(ref.radii, R_target[c], ref.R[c]);
    const double m = mean_radius(ref.radii, R_target[c]);
    r.mean_radius_error[c] = ref.mean_radius[c] > 0 ? m / ref.mean_radius[c] - 1.0 : 0.0;
  }
  return r;
}

std::string header_lines(const char* prefix, const Export& e, const Context& ctx) {
  const SkinParameters& p = ctx.ref.parameters;
  const Unit unit = ctx.unit;
  const double world_scale = ctx.options.world_scale;
  std::ostringstream os;
  os << prefix << " Spectral Skin export for " << e.report.target << " (docs/export.md).\n";
  os << prefix << " Skin: melanin " << num(p.melanin) << ", melanin_blend " << num(p.melanin_blend)
     << ", hemoglobin " << num(p.hemoglobin) << ", oiliness " << num(p.oiliness) << "; solver "
     << ctx.ref.model->name() << ".\n";
  os << prefix << " Colours: linear Rec.709 (sRGB primaries, D65). Lengths: " << unit_name(unit);
  if (world_scale != 1.0) os << " x world scale " << num(world_scale);
  os << ".\n";
  os << prefix << " Target model: " << e.report.target_model << "\n";
  const auto& l1 = e.report.profile_l1;
  os << prefix << " Fit: colour dE2000 " << num(rounded_error(e.report.delta_e_2000))
     << ", profile L1 (R, G, B) "
     << triple({rounded_error(l1[0]), rounded_error(l1[1]), rounded_error(l1[2])})
     << "; full report in the .fit.json beside this file.\n";
  for (const std::string& n : e.report.notes) os << prefix << " Note: " << n << "\n";
  return os.str();
}

json values_json(const FitReport& r) {
  json v = json::object();
  for (const auto& [k, vals] : r.values) v[k] = vals.size() == 1 ? json(vals[0]) : json(vals);
  return v;
}

json document_head(const std::string& format, const Options& o) {
  json j;
  j["format"] = format;
  j["name"] = json_text(o.name, kName);
  j["color_space"] = "linear Rec.709 (sRGB primaries, D65)";
  return j;
}

}  // namespace detail

using namespace detail;

double report_number(double v) { return rounded(v); }
double report_error(double v) { return rounded_error(v); }

}  // namespace skin::exporting
