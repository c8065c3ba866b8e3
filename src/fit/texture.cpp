// Parameter maps out and in (OpenEXR through skin::image), docs/parameter-maps.md.
#include "skin/fit/color_fit.hpp"
#include "skin/image/image.hpp"
#include "skin/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace skin::fit {

namespace {
const std::vector<std::string> kChannels = {"melanin", "melanin_blend", "hemoglobin", "error"};
const std::string kUncertainty = "uncertainty.";
}

std::string uncertainty_channel(Parameter p) { return kUncertainty + std::string(key(p)); }

std::vector<std::string> ParameterMaps::channel_names() const {
  std::vector<std::string> names = kChannels;
  // The extended model's other free parameters, named by key (read by a scene's
  // parameter_maps like the three above), then one standard deviation per free parameter.
  for (Parameter p : more_parameters) names.emplace_back(key(p));
  for (Parameter p : uncertainty_parameters) names.push_back(uncertainty_channel(p));
  return names;
}

void write_parameter_maps(const ParameterMaps& maps, const std::string& path) {
  if (maps.more.size() != maps.more_parameters.size() || maps.uncertainty.size() != maps.uncertainty_parameters.size())
    throw std::logic_error("write_parameter_maps: a map per parameter named");
  const std::vector<std::string> names = maps.channel_names();
  std::vector<const std::vector<float>*> values = {&maps.melanin, &maps.melanin_blend, &maps.hemoglobin, &maps.error};
  for (const auto& v : maps.more) values.push_back(&v);
  for (const auto& v : maps.uncertainty) values.push_back(&v);
  std::vector<image::PlaneView> planes;
  for (std::size_t k = 0; k < names.size(); ++k) planes.push_back({names[k], values[k]});
  image::write_exr_planes(path, maps.width, maps.height, planes,
                          {{"skin_layout",
                            "Spectral Skin parameter maps v1: melanin (C_m), melanin_blend "
                            "(beta_m), hemoglobin (C_h), error (CIEDE2000), and under the extended "
                            "model one channel per other free parameter, named by its key; with "
                            "--uncertainty one standard deviation per free parameter, "
                            "uncertainty.<key>; docs/parameter-maps.md"}},
                          "parameter maps");
}

std::vector<std::string> extended_map_channels(const std::string& path) {
  std::vector<std::string> more;
  for (const std::string& name : physics::parameter_channels(image::exr_channel_names(path, "parameter maps")))
    if (std::find(kChannels.begin(), kChannels.end(), name) == kChannels.end()) more.push_back(name);
  return more;
}

ParameterMaps read_parameter_maps(const std::string& path) {
  std::vector<std::string> names = kChannels;
  const std::vector<std::string> more = extended_map_channels(path);
  names.insert(names.end(), more.begin(), more.end());
  // The uncertainty channels in the maps' order: melanin, melanin_blend, hemoglobin, then the
  // other channels' (the file lists its channels alphabetically).
  std::vector<Parameter> found;
  for (const std::string& n : image::exr_channel_names(path, "parameter maps"))
    if (const physics::ParameterInfo* info = n.rfind(kUncertainty, 0) == 0 ? physics::find_parameter(n.substr(kUncertainty.size())) : nullptr;
        info && std::isfinite(info->fit_min))
      found.push_back(parse_parameter(n.substr(kUncertainty.size())));
  std::vector<Parameter> order = {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin}, sd;
  for (const std::string& m : more) order.push_back(parse_parameter(m));
  for (Parameter p : found)
    if (std::find(order.begin(), order.end(), p) == order.end()) order.push_back(p);
  for (Parameter p : order)
    if (std::find(found.begin(), found.end(), p) != found.end()) sd.push_back(p), names.push_back(uncertainty_channel(p));
  image::Planes planes = image::read_exr_planes(path, names, "parameter maps");
  ParameterMaps maps;
  maps.width = planes.width;
  maps.height = planes.height;
  maps.melanin = std::move(planes.values[0]);
  maps.melanin_blend = std::move(planes.values[1]);
  maps.hemoglobin = std::move(planes.values[2]);
  maps.error = std::move(planes.values[3]);
  for (std::size_t k = 0; k < more.size(); ++k) {
    maps.more_parameters.push_back(parse_parameter(more[k]));
    maps.more.push_back(std::move(planes.values[4 + k]));
  }
  maps.more_at_bound.assign(more.size(), 0);
  maps.uncertainty_parameters = sd;
  for (std::size_t k = 0; k < sd.size(); ++k) maps.uncertainty.push_back(std::move(planes.values[4 + more.size() + k]));
  maps.update_error_statistics();
  return maps;
}

}  // namespace skin::fit
