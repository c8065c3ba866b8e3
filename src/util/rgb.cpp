#include "skin/util/rgb.hpp"

#include <ostream>

namespace skin::util {

std::ostream& operator<<(std::ostream& os, const Rgb& c) {
  return os << "RGB(" << c.r << ", " << c.g << ", " << c.b << ')';
}

}  // namespace skin::util
