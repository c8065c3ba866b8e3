#include "convert.hpp"

#include "skin/util/error.hpp"

namespace skin::python {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::one_line;
using skin::util::require_positive;

using skin::physics::Layer;

Layer layer_from_entries(const std::vector<std::pair<std::string, std::optional<double>>>& entries,
                         std::size_t index) {
  const std::string where = "layer " + std::to_string(index + 1);
  Layer l;
  bool have_a = false, have_s = false;
  for (const auto& [key, v] : entries) {
    const bool thickness = key == "thickness_mm" || key == "thickness";
    if (!thickness && key != "sigma_a" && key != "sigma_s_prime" && key != "eta" && key != "g")
      throw InputError(where + ": unknown key '" + one_line(key) + "' (" + std::string(kLayerKeys) + ")");
    if (!v) {
      if (thickness) continue;
      throw InputError(where + " " + key + " is None: must be a number");
    }
    if (key == "sigma_a") {
      l.sigma_a = *v;
      have_a = true;
    } else if (key == "sigma_s_prime") {
      l.sigma_s_prime = *v;
      have_s = true;
    } else if (thickness) {
      if (!(*v > 0)) require_positive(where + " thickness", *v, "mm");
      l.thickness = *v;
    } else if (key == "eta") {
      l.eta = *v;
    } else {
      l.g = *v;
    }
  }
  if (!have_a || !have_s)
    throw InputError(where + ": " + std::string(!have_a ? "sigma_a" : "sigma_s_prime") +
                     " is missing: sigma_a and sigma_s_prime are required (" + std::string(kLayerKeys) + ")");
  return l;
}

void check_linear_rgb(const std::vector<float>& rgb, std::size_t width) {
  for (std::size_t i = 0; i < rgb.size(); ++i)
    if (!(rgb[i] >= 0.0f && rgb[i] <= 1.0f)) {
      const std::size_t pixel = i / 3;
      const std::size_t w = width > 0 ? width : 1;
      throw InputError("image[" + std::to_string(pixel / w) + ", " + std::to_string(pixel % w) + ", " +
                       std::to_string(i % 3) + "] = " + format_number(rgb[i]) +
                       " is out of range: linear sRGB must be in [0, 1]");
    }
}

}  // namespace skin::python
