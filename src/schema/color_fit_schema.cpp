// The schemas of skin fit --hex / --srgb / --texture (color_fit_schema.hpp).
#include "color_fit_schema.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace skin::schema {

using skin::physics::ParameterInfo;
using skin::physics::parameter_table;
using skin::physics::WavelengthGrid;

Result color_fit_result(const fit::ColorFitResult& r, const color::Rgb& target, double melanin_blend_prior,
                        double melanin_blend_weight) {
  const color::Colorimetry cm{WavelengthGrid{}};
  const color::ColorSummary in = color::summarize_rgb(cm, target);
  const color::ColorSummary out = color::summarize_rgb(cm, r.fitted_srgb_linear);
  Result result;
  json& j = result.document;
  j["target"] = {{"hex", in.hex}, {"lab", {in.lab.L, in.lab.a, in.lab.b}}};
  j["parameters"] = to_json(r.parameters);
  j["fitted"] = {{"hex", out.hex}, {"lab", {r.fitted.L, r.fitted.a, r.fitted.b}},
                 {"srgb_linear", {r.fitted_srgb_linear.r, r.fitted_srgb_linear.g, r.fitted_srgb_linear.b}}};
  j["delta_e_2000"] = r.delta_e;
  j["model"] = std::string(fit::name(r.fit_model));
  if (r.fit_model == fit::FitModel::paper) {
    j["melanin_blend_prior"] = melanin_blend_prior;
    j["melanin_blend_weight"] = melanin_blend_weight;
  }
  // Outside the model's gamut when the best fit is more than fit::kGamutDeltaE away.
  j["outside_gamut"] = r.outside_gamut;
  json free = json::array(), unc = json::object(), at_bound = json::object();
  for (std::size_t i = 0; i < r.free.size(); ++i) {
    const std::string k(fit::key(r.free[i]));
    free.push_back(k);
    if (i < r.uncertainty.size()) unc[k] = std::isfinite(r.uncertainty[i]) ? json(r.uncertainty[i]) : json(nullptr);
    if (i < r.at_bound.size()) at_bound[k] = bool(r.at_bound[i]);
  }
  j["free"] = free;
  j["uncertainty"] = unc;
  j["at_bound"] = at_bound;
  // Every parameter (the fitted ones and those held fixed), then the colour error.
  for (const ParameterInfo& info : parameter_table())
    result.columns.push_back({std::string(info.key), {r.parameters.*(info.member)}, {}});
  result.columns.push_back({"target.hex", {}, {in.hex}});
  result.columns.push_back({"fitted.hex", {}, {out.hex}});
  result.columns.push_back({"delta_e_2000", {r.delta_e}, {}});
  std::ostringstream os;
  os << "target " << in.hex << "  Lab " << r.target << "  (model " << fit::name(r.fit_model) << ")\n";
  for (std::size_t i = 0; i < r.free.size(); ++i) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "  %-20s %11.6g  +- %-9.3g%s\n", std::string(fit::key(r.free[i])).c_str(),
                  fit::get(r.parameters, r.free[i]), i < r.uncertainty.size() ? r.uncertainty[i] : NAN,
                  i < r.at_bound.size() && r.at_bound[i] ? "  (at bound)" : "");
    os << buf;
  }
  os << "fitted " << out.hex << "  Lab " << r.fitted << "  dE2000 " << r.delta_e
     << (r.outside_gamut ? "  (outside the model's gamut)" : "") << "\n";
  result.table = os.str();
  return result;
}

json texture_fit_document(const fit::ParameterMaps& maps) {
  json j;
  j["width"] = maps.width;
  j["height"] = maps.height;
  j["channels"] = maps.channel_names();
  j["error_delta_e_2000"] = {{"mean", maps.mean_error}, {"max", maps.max_error}, {"fraction_below_1", maps.fraction_below_1}};
  // Outside the model's gamut: texels farther than fit::kGamutDeltaE; parameters on their bounds.
  j["outside_gamut"] = {{"fraction", 1.0 - maps.fraction_below_1}, {"mean_delta_e_2000", maps.mean_error_outside}};
  j["at_bound"] = {{"melanin", maps.at_bound[0]}, {"melanin_blend", maps.at_bound[1]},
                   {"hemoglobin", maps.at_bound[2]}, {"any", maps.any_at_bound}};
  for (std::size_t k = 0; k < maps.more_parameters.size() && k < maps.more_at_bound.size(); ++k)
    j["at_bound"][std::string(fit::key(maps.more_parameters[k]))] = maps.more_at_bound[k];
  return j;
}

Result texture_fit_result(const fit::ParameterMaps& maps, const std::string& texture,
                          const std::string& output) {
  Result result;
  json& j = result.document;
  j["texture"] = texture;
  j["output"] = output;
  const json summary = texture_fit_document(maps);
  for (const auto& [key, value] : summary.items()) j[key] = value;
  result.columns = {{"width", {double(maps.width)}, {}},
                    {"height", {double(maps.height)}, {}},
                    {"error_delta_e_2000.mean", {maps.mean_error}, {}},
                    {"error_delta_e_2000.max", {maps.max_error}, {}},
                    {"error_delta_e_2000.fraction_below_1", {maps.fraction_below_1}, {}}};
  std::string channels, more_bounds;
  for (const std::string& c : maps.channel_names()) channels += (channels.empty() ? "" : ", ") + c;
  for (std::size_t k = 0; k < maps.more_parameters.size() && k < maps.more_at_bound.size(); ++k)
    more_bounds += ", " + std::string(fit::key(maps.more_parameters[k])) + " " + std::to_string(maps.more_at_bound[k]);
  char buf[256];
  std::snprintf(buf, sizeof buf, "wrote %s: %dx%d, channels ", output.c_str(), maps.width, maps.height);
  result.table = buf + channels + "\n";
  std::snprintf(buf, sizeof buf, "colour error (dE2000): mean %.3g, max %.3g, %.3g of pixels below 1\n",
                maps.mean_error, maps.max_error, maps.fraction_below_1);
  result.table += buf;
  std::snprintf(buf, sizeof buf,
                "outside the gamut (> 1): %.3g of pixels, mean %.3g; at a bound: %.3g of pixels "
                "(melanin %zu, melanin_blend %zu, hemoglobin %zu",
                1.0 - maps.fraction_below_1, maps.mean_error_outside,
                maps.width > 0 ? static_cast<double>(maps.any_at_bound) / (static_cast<double>(maps.width) * maps.height) : 0.0,
                maps.at_bound[0], maps.at_bound[1], maps.at_bound[2]);
  result.table += buf + more_bounds + ")\n";
  return result;
}

}  // namespace skin::schema
