#include "skin/physics/layer.hpp"

#include <cmath>
#include <ostream>
#include <sstream>

#include "skin/util/error.hpp"

namespace skin::physics {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_in_range;
using skin::util::require_non_negative;
using skin::util::require_positive;

void LayerStack::validate() const {
  if (layers.empty()) throw InputError("layer stack is empty: give at least one --layer");
  require_in_range("eta_above", eta_above, 1.0, 3.0);
  require_in_range("eta_below", eta_below, 1.0, 3.0);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const Layer& l = layers[i];
    const std::string p = "layer " + std::to_string(i + 1) + " ";
    require_non_negative(p + "sigma_a", l.sigma_a, "1/mm");
    require_positive(p + "sigma_s_prime", l.sigma_s_prime, "1/mm");
    require_in_range(p + "eta", l.eta, 1.0, 3.0);
    if (!(l.g > -1.0 && l.g < 1.0))
      throw InputError(p + "g = " + format_number(l.g) +
                       " is out of range: allowed range is (-1, 1)");
    if (l.semi_infinite()) {
      if (i + 1 != layers.size())
        throw InputError(p + "thickness = inf is out of range: only the last layer may be "
                             "semi-infinite (give a thickness in mm)");
    } else {
      require_positive(p + "thickness", l.thickness, "mm");
    }
  }
}

std::ostream& operator<<(std::ostream& os, const Layer& l) {
  os << "Layer{sigma_a=" << l.sigma_a << "/mm, sigma_s_prime=" << l.sigma_s_prime
     << "/mm, thickness=";
  if (l.semi_infinite()) os << "inf"; else os << l.thickness << "mm";
  return os << ", eta=" << l.eta << ", g=" << l.g << '}';
}

std::ostream& operator<<(std::ostream& os, const LayerStack& s) {
  os << "LayerStack{eta_above=" << s.eta_above;
  for (const auto& l : s.layers) os << ", " << l;
  return os << ", eta_below=" << s.eta_below << '}';
}

std::string to_string(const LayerStack& s) {
  std::ostringstream ss;
  ss << s;
  return ss.str();
}

}  // namespace skin::physics
