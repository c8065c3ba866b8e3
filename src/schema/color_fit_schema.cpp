// The schemas of skin fit --hex / --srgb / --texture (color_fit_schema.hpp).
#include "color_fit_schema.hpp"

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
  j["melanin_blend_prior"] = melanin_blend_prior;
  j["melanin_blend_weight"] = melanin_blend_weight;
  // Every parameter (the fitted ones and those held fixed), then the colour error.
  for (const ParameterInfo& info : parameter_table())
    result.columns.push_back({std::string(info.key), {r.parameters.*(info.member)}, {}});
  result.columns.push_back({"target.hex", {}, {in.hex}});
  result.columns.push_back({"fitted.hex", {}, {out.hex}});
  result.columns.push_back({"delta_e_2000", {r.delta_e}, {}});
  std::ostringstream os;
  os << "target " << in.hex << "  Lab " << r.target << "\n"
     << "  melanin        " << r.parameters.melanin << "\n"
     << "  melanin_blend  " << r.parameters.melanin_blend << "\n"
     << "  hemoglobin     " << r.parameters.hemoglobin << "\n"
     << "fitted " << out.hex << "  Lab " << r.fitted << "  dE2000 " << r.delta_e << "\n";
  result.table = os.str();
  return result;
}

json texture_fit_document(const fit::ParameterMaps& maps) {
  json j;
  j["width"] = maps.width;
  j["height"] = maps.height;
  j["channels"] = {"melanin", "melanin_blend", "hemoglobin", "error"};
  j["error_delta_e_2000"] = {{"mean", maps.mean_error}, {"max", maps.max_error}, {"fraction_below_1", maps.fraction_below_1}};
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
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "wrote %s: %dx%d, channels melanin, melanin_blend, hemoglobin, error\n"
                "colour error (dE2000): mean %.3g, max %.3g, %.3g of pixels below 1\n",
                output.c_str(), maps.width, maps.height, maps.mean_error, maps.max_error,
                maps.fraction_below_1);
  result.table = buf;
  return result;
}

}  // namespace skin::schema
