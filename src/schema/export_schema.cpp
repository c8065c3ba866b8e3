// The schema of skin export's fit report (export_schema.hpp).
#include "export_schema.hpp"

#include "skin/util/escape.hpp"

namespace skin::schema {

using skin::util::Rgb;

using skin::physics::SkinParameters;

json fit_report_document(const exporting::FitReport& r, const SkinParameters& p, std::string_view solver,
                         const std::vector<std::string>& files) {
  using exporting::report_error;
  using exporting::report_number;
  auto rgb = [](const Rgb& c) {
    return json{{"r", report_number(c.r)}, {"g", report_number(c.g)}, {"b", report_number(c.b)}};
  };
  auto arr = [](const std::array<double, 3>& a) {
    return json{{"r", report_number(a[0])}, {"g", report_number(a[1])}, {"b", report_number(a[2])}};
  };
  auto err = [](const std::array<double, 3>& a) {
    return json{{"r", report_error(a[0])}, {"g", report_error(a[1])}, {"b", report_error(a[2])}};
  };
  json j;
  j["target"] = r.target;
  j["target_model"] = r.target_model;
  j["parameters"] = to_json(p);
  j["solver"] = solver;
  j["units"] = {{"files", std::string(exporting::unit_name(r.unit))},
                {"mean_radius_mm", "mm"},
                {"colors", "linear Rec.709 (sRGB primaries, D65)"}};
  json names = json::array();
  for (const std::string& f : files) {
    util::escape::require_utf8(f, "output");  // JSON holds text
    names.push_back(f);
  }
  j["files"] = names;
  j["representable"] = r.representable;
  j["notes"] = r.notes;
  j["R_d_ours"] = rgb(r.R_d_ours);
  j["R_d_target"] = rgb(r.R_d_target);
  j["delta_e_2000"] = report_error(r.delta_e_2000);
  j["profile_l1"] = err(r.profile_l1);
  j["mean_radius_mm"] = arr(r.mean_radius_mm);
  j["mean_radius_error"] = err(r.mean_radius_error);
  // A number for a single value, an array otherwise.
  json values = json::object();
  for (const auto& [key, v] : r.values) {
    json rounded = json::array();
    for (double x : v) rounded.push_back(report_number(x));
    values[key] = v.size() == 1 ? rounded[0] : rounded;
  }
  j["values"] = values;
  if (r.texels) {
    j["texels"] = r.texels;
    j["max_delta_e_2000"] = report_error(r.max_delta_e_2000);
  }
  return j;
}

}  // namespace skin::schema
