// Parameter maps out and in (OpenEXR through skin::image), docs/parameter-maps.md.
#include "skin/fit/color_fit.hpp"
#include "skin/image/image.hpp"
#include "skin/util/error.hpp"

namespace skin::fit {

namespace {
const std::vector<std::string> kChannels = {"melanin", "melanin_blend", "hemoglobin", "error"};
}

void write_parameter_maps(const ParameterMaps& maps, const std::string& path) {
  std::vector<image::PlaneView> planes = {{kChannels[0], &maps.melanin},
                                          {kChannels[1], &maps.melanin_blend},
                                          {kChannels[2], &maps.hemoglobin},
                                          {kChannels[3], &maps.error}};
  // The extended model's other free parameters, named by key (read by a scene's
  // parameter_maps like the three above).
  std::vector<std::string> names;
  for (Parameter p : maps.more_parameters) names.emplace_back(key(p));
  for (std::size_t k = 0; k < maps.more.size() && k < names.size(); ++k) planes.push_back({names[k], &maps.more[k]});
  image::write_exr_planes(path, maps.width, maps.height, planes,
                          {{"skin_layout",
                            "Spectral Skin parameter maps v1: melanin (C_m), melanin_blend "
                            "(beta_m), hemoglobin (C_h), error (CIEDE2000), and under the extended "
                            "model one channel per other free parameter, named by its key; "
                            "docs/parameter-maps.md"}},
                          "parameter maps");
}

ParameterMaps read_parameter_maps(const std::string& path) {
  image::Planes planes = image::read_exr_planes(path, kChannels, "parameter maps");
  ParameterMaps maps;
  maps.width = planes.width;
  maps.height = planes.height;
  maps.melanin = std::move(planes.values[0]);
  maps.melanin_blend = std::move(planes.values[1]);
  maps.hemoglobin = std::move(planes.values[2]);
  maps.error = std::move(planes.values[3]);
  maps.update_error_statistics();
  return maps;
}

}  // namespace skin::fit
